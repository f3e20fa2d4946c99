"""The approval record: an in-toto Statement v1 about the orders digest (DESIGN.md)."""

from __future__ import annotations

import hashlib
from typing import Any

import rfc8785

from .. import strict_json

STATEMENT_TYPE = "https://in-toto.io/Statement/v1"
PREDICATE_TYPE = "https://countersign.invalid/approval/v1"
DECISIONS = ("approved", "rejected", "revoked")


def json_digest(data: Any) -> str:
    return "sha256:" + hashlib.sha256(bytes(rfc8785.dumps(data))).hexdigest()


def build_statement(
    *, mission: str, version: int, orders_digest: str, decision: str, reason: str,
    submission: int, report_digest: str, paths: dict[str, Any] | None, vehicle: str | None,
    author: str, supervisor: str, key_id: str, time: str, nonce: str,
    rehearsal_digest: str | None = None, revokes: str | None = None,
    probabilities: dict[str, Any] | None = None, exports: dict[str, str] | None = None,
    campaigns: list[str] | None = None, checker: str | None = None,
    team: dict[str, str] | None = None,
) -> dict[str, Any]:
    if decision not in DECISIONS:
        raise ValueError(f"decision must be one of {', '.join(DECISIONS)}")
    algorithm, _, hexdigest = orders_digest.partition(":")
    predicate: dict[str, Any] = {
        "mission": mission, "version": version, "submission": submission,
        "decision": decision, "reason": reason, "revokes": revokes,
        "report_digest": report_digest, "paths": paths,
        "rehearsal_digest": rehearsal_digest, "vehicle": vehicle, "author": author,
        "supervisor": supervisor, "key_id": key_id, "time": time, "nonce": nonce,
    }
    # The outcome probabilities the supervisor saw. Only present when the orders
    # declare some, so the statements of orders without them stay byte for byte as before and
    # approvals prepared before this field existed still match when they are decided.
    if probabilities is not None:
        predicate["probabilities"] = probabilities
    # The digest of every vehicle file of the approved package, by its name in the
    # package: only on approvals of orders that export, so other statements stay as before
    # and a verifier that cannot rebuild the exports can still check them.
    if exports is not None:
        predicate["exports"] = exports
    # The rehearsal campaigns attached to the submission, by record digest, sorted:
    # only when some are, for the same reason as above.
    if campaigns:
        predicate["campaigns"] = sorted(campaigns)
    # The fingerprint of the checks that made the report (verify.fingerprint): the report
    # digest alone does not say which code judged the orders. Statements signed before it
    # existed have none and still verify.
    if checker is not None:
        predicate["checker"] = checker
    # A team's orders (orders/team.py): every member's orders digest by vehicle, so one
    # signature covers each vehicle's orders by the digest that vehicle loads. Only on teams,
    # so the statements of single-vehicle orders stay byte for byte as before.
    if team is not None:
        predicate["team"] = dict(team)
    return {
        "_type": STATEMENT_TYPE,
        "subject": [{"name": f"{mission}@v{version}", "digest": {algorithm: hexdigest}}],
        "predicateType": PREDICATE_TYPE,
        "predicate": predicate,
    }


def statement_bytes(statement: dict[str, Any]) -> bytes:
    return bytes(rfc8785.dumps(statement))


def parse_statement(payload: bytes) -> dict[str, Any]:
    """The statement in these payload bytes; it must be canonical RFC 8785 JSON."""
    try:
        data = strict_json.loads(payload)
    except (ValueError, UnicodeDecodeError):
        raise ValueError("the payload is not JSON") from None
    if not isinstance(data, dict) or data.get("_type") != STATEMENT_TYPE or data.get(
            "predicateType") != PREDICATE_TYPE or not isinstance(data.get("predicate"), dict):
        raise ValueError("the payload is not a Countersign approval statement")
    if statement_bytes(data) != payload:
        raise ValueError("the payload is not canonical RFC 8785 JSON")
    return data


def subject_digest(statement: dict[str, Any]) -> str:
    subject = statement.get("subject") or [{}]
    digests = subject[0].get("digest", {}) if isinstance(subject[0], dict) else {}
    return f"sha256:{digests.get('sha256', '')}"
