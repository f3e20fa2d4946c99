"""The approval record: an in-toto Statement v1 about the orders digest (DESIGN.md)."""

from __future__ import annotations

import hashlib
from dataclasses import dataclass
from typing import Any

import rfc8785

from .. import strict_json
from ..orders.json_fields import Malformed, an_object, nullable, only, optional, required, strings

STATEMENT_TYPE = "https://in-toto.io/Statement/v1"
PREDICATE_TYPE = "https://countersign.invalid/approval/v1"
DECISIONS = ("approved", "rejected", "revoked")


def json_digest(data: Any) -> str:
    return "sha256:" + hashlib.sha256(bytes(rfc8785.dumps(data))).hexdigest()


@dataclass(frozen=True)
class Subject:
    """What the statement is about: the orders by name and digest."""

    name: str
    digest: dict[str, str]

    def to_json(self) -> dict[str, Any]:
        return {"name": self.name, "digest": dict(self.digest)}

    @classmethod
    def from_json(cls, data: Any, where: str = "subject[0]") -> Subject:
        data = an_object(data, where)
        only(data, ("name", "digest"), where)
        return cls(required(data, "name", str, where),
                   strings(required(data, "digest", dict, where), f"{where}.digest"))


# The predicate's fields in the order build_statement writes them: the prepared statement the
# browser shows keeps this order (the signed bytes are canonical, so sorted, either way).
_ALWAYS = ("mission", "version", "submission", "decision", "reason", "revokes",
           "report_digest", "paths", "rehearsal_digest", "vehicle", "author", "supervisor",
           "key_id", "time", "nonce")
_ADDED = ("probabilities", "exports", "campaigns", "checker", "team")


@dataclass(frozen=True)
class Predicate:
    """The approval predicate (DESIGN.md, approval record). The fields after `nonce` came
    later and are written only when set, so the statements signed before them keep their
    bytes: None means absent, never null."""

    mission: str
    version: int
    submission: int
    decision: str
    reason: str
    revokes: str | None
    report_digest: str
    paths: dict[str, Any] | None
    rehearsal_digest: str | None
    vehicle: str | None
    author: str
    supervisor: str
    key_id: str
    time: str
    nonce: str
    # The outcome probabilities the supervisor saw: only when the orders declare some.
    probabilities: dict[str, Any] | None = None
    # Every vehicle file of the approved package by name -> digest: only on orders that
    # export, so a verifier that cannot rebuild the exports can still check the rest.
    exports: dict[str, str] | None = None
    # The rehearsal campaigns attached to the submission, by record digest, sorted.
    campaigns: tuple[str, ...] | None = None
    # The fingerprint of the checks that made the report (verify.fingerprint): the report
    # digest alone does not say which code judged the orders.
    checker: str | None = None
    # A team's orders (orders/team.py): every member's orders digest by vehicle, so one
    # signature covers each vehicle's orders by the digest that vehicle loads.
    team: dict[str, str] | None = None

    def to_json(self) -> dict[str, Any]:
        data: dict[str, Any] = {name: getattr(self, name) for name in _ALWAYS}
        if self.paths is not None:
            data["paths"] = dict(self.paths)
        for name in _ADDED:
            value = getattr(self, name)
            if value is not None:
                data[name] = (list(value) if isinstance(value, tuple)
                              else dict(value) if isinstance(value, dict) else value)
        return data

    @classmethod
    def from_json(cls, data: Any, where: str = "predicate") -> Predicate:
        data = an_object(data, where)
        only(data, _ALWAYS + _ADDED, where)
        decision = required(data, "decision", str, where)
        if decision not in DECISIONS:
            raise Malformed(f"{where}.decision must be one of {', '.join(DECISIONS)}")
        campaigns = optional(data, "campaigns", list, where)
        if campaigns is not None and not all(isinstance(c, str) for c in campaigns):
            raise Malformed(f"{where}.campaigns must be a list of digests")
        exports, team = optional(data, "exports", dict, where), optional(data, "team", dict, where)
        return cls(
            mission=required(data, "mission", str, where),
            version=required(data, "version", int, where),
            submission=required(data, "submission", int, where),
            decision=decision, reason=required(data, "reason", str, where),
            revokes=nullable(data, "revokes", str, where),
            report_digest=required(data, "report_digest", str, where),
            paths=nullable(data, "paths", dict, where),
            rehearsal_digest=nullable(data, "rehearsal_digest", str, where),
            vehicle=nullable(data, "vehicle", str, where),
            author=required(data, "author", str, where),
            supervisor=required(data, "supervisor", str, where),
            key_id=required(data, "key_id", str, where),
            time=required(data, "time", str, where), nonce=required(data, "nonce", str, where),
            probabilities=optional(data, "probabilities", dict, where),
            exports=None if exports is None else strings(exports, f"{where}.exports"),
            campaigns=None if campaigns is None else tuple(campaigns),
            checker=optional(data, "checker", str, where),
            team=None if team is None else strings(team, f"{where}.team"),
        )


@dataclass(frozen=True)
class Statement:
    """An in-toto Statement v1 whose predicate is the approval predicate."""

    subject: tuple[Subject, ...]
    predicate: Predicate

    @property
    def orders_digest(self) -> str:
        """The signed orders digest, `sha256:<hex>` ('' hex when the subject has none)."""
        digests = self.subject[0].digest if self.subject else {}
        return f"sha256:{digests.get('sha256', '')}"

    def to_json(self) -> dict[str, Any]:
        return {"_type": STATEMENT_TYPE, "subject": [s.to_json() for s in self.subject],
                "predicateType": PREDICATE_TYPE, "predicate": self.predicate.to_json()}

    @classmethod
    def from_json(cls, data: Any) -> Statement:
        data = an_object(data, "the statement")
        only(data, ("_type", "subject", "predicateType", "predicate"), "statement")
        if data.get("_type") != STATEMENT_TYPE:
            raise Malformed(f"statement._type must be {STATEMENT_TYPE}")
        if data.get("predicateType") != PREDICATE_TYPE:
            raise Malformed(f"statement.predicateType must be {PREDICATE_TYPE}")
        subjects = required(data, "subject", list, "statement")
        if not subjects:
            raise Malformed("statement.subject names no subject")
        return cls(tuple(Subject.from_json(s, f"statement.subject[{i}]")
                         for i, s in enumerate(subjects)),
                   Predicate.from_json(data.get("predicate"), "statement.predicate"))


def build_statement(
    *, mission: str, version: int, orders_digest: str, decision: str, reason: str,
    submission: int, report_digest: str, paths: dict[str, Any] | None, vehicle: str | None,
    author: str, supervisor: str, key_id: str, time: str, nonce: str,
    rehearsal_digest: str | None = None, revokes: str | None = None,
    probabilities: dict[str, Any] | None = None, exports: dict[str, str] | None = None,
    campaigns: list[str] | None = None, checker: str | None = None,
    team: dict[str, str] | None = None,
) -> dict[str, Any]:
    """The statement to sign, as JSON (what the browser is sent and signs)."""
    if decision not in DECISIONS:
        raise ValueError(f"decision must be one of {', '.join(DECISIONS)}")
    algorithm, _, hexdigest = orders_digest.partition(":")
    predicate = Predicate(
        mission=mission, version=version, submission=submission, decision=decision,
        reason=reason, revokes=revokes, report_digest=report_digest, paths=paths,
        rehearsal_digest=rehearsal_digest, vehicle=vehicle, author=author,
        supervisor=supervisor, key_id=key_id, time=time, nonce=nonce,
        probabilities=probabilities, exports=exports,
        campaigns=tuple(sorted(campaigns)) if campaigns else None, checker=checker,
        team=None if team is None else dict(team))
    subject = Subject(f"{mission}@v{version}", {algorithm: hexdigest})
    return Statement((subject,), predicate).to_json()


def statement_bytes(statement: dict[str, Any]) -> bytes:
    return bytes(rfc8785.dumps(statement))


def _statement_json(payload: bytes) -> dict[str, Any]:
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


def read_statement(payload: bytes) -> Statement:
    """The statement in these payload bytes: canonical RFC 8785 JSON of an approval statement
    with every field of its type (Malformed, a ValueError, names the one that is not)."""
    return Statement.from_json(_statement_json(payload))


def parse_statement(payload: bytes) -> dict[str, Any]:
    """The statement in these payload bytes as JSON, checked as read_statement checks it."""
    data = _statement_json(payload)
    Statement.from_json(data)
    return data


def subject_digest(statement: dict[str, Any]) -> str:
    subject = statement.get("subject") or [{}]
    digests = subject[0].get("digest", {}) if isinstance(subject[0], dict) else {}
    return f"sha256:{digests.get('sha256', '')}"
