"""A supervisor's signed decision on a procedure version: an in-toto Statement v1
whose subject is the procedure's digest, in the same DSSE envelope as an approval.

Its predicate type differs from a mission approval's (approvals/statement.py), so neither
statement can be replayed as the other: each parser refuses the other's type."""

from __future__ import annotations

from typing import Any

from .. import strict_json
from .statement import STATEMENT_TYPE, statement_bytes

PROCEDURE_PREDICATE_TYPE = "https://countersign.invalid/procedure-approval/v1"
PROCEDURE_DECISIONS = ("approved", "rejected")


def build_procedure_statement(
    *, name: str, version: int, procedure_digest: str, decision: str, reason: str,
    paths: dict[str, Any] | None, author: str, supervisor: str, key_id: str, time: str,
    nonce: str, checker: str,
) -> dict[str, Any]:
    if decision not in PROCEDURE_DECISIONS:
        raise ValueError(f"decision must be one of {', '.join(PROCEDURE_DECISIONS)}")
    algorithm, _, hexdigest = procedure_digest.partition(":")
    return {
        "_type": STATEMENT_TYPE,
        "subject": [{"name": f"procedure:{name}@v{version}", "digest": {algorithm: hexdigest}}],
        "predicateType": PROCEDURE_PREDICATE_TYPE,
        "predicate": {
            "procedure": name, "version": version, "decision": decision, "reason": reason,
            "paths": paths, "author": author, "supervisor": supervisor, "key_id": key_id,
            "time": time, "nonce": nonce, "checker": checker,
        },
    }


def parse_procedure_statement(payload: bytes) -> dict[str, Any]:
    """The statement in these payload bytes: canonical RFC 8785 JSON of a procedure decision."""
    try:
        data = strict_json.loads(payload)
    except (ValueError, UnicodeDecodeError):
        raise ValueError("the payload is not JSON") from None
    if not isinstance(data, dict) or data.get("_type") != STATEMENT_TYPE or data.get(
            "predicateType") != PROCEDURE_PREDICATE_TYPE or not isinstance(
            data.get("predicate"), dict):
        raise ValueError("the payload is not a Countersign procedure decision statement")
    if statement_bytes(data) != payload:
        raise ValueError("the payload is not canonical RFC 8785 JSON")
    return data
