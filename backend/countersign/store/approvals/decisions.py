"""Signed decisions: the statement to sign, its checks, and storing the approval."""

from __future__ import annotations

import secrets
from dataclasses import dataclass
from typing import Any

from sqlalchemy import select
from sqlalchemy.exc import IntegrityError
from sqlalchemy.orm import Session as DbSession

from ...approvals import dsse
from ...approvals.dsse import SignatureError
from ...approvals.signer import LogSigner
from ...approvals.statement import (
    build_statement,
    json_digest,
    parse_statement,
    statement_bytes,
    subject_digest,
)
from ...export.package import export_digests
from ...limits import MAX_REASON
from ...orders.reader import orders_from_data
from ...orders.team import member_digests
from ...verify import fingerprint
from ...verify.report_document import ReportDocument
from ..campaigns import cited_digests as cited_campaigns
from ..decide_guard import (
    lock_submission,
)
from ..events import record
from ..missions import NotFound, get_mission
from ..reauth import confirm_password
from ..report_service import ReportService
from ..tables import (
    Approval,
    Mission,
    MissionVersion,
    SigningKey,
    Submission,
    User,
    utcnow,
)
from .common import (
    BadDecision,
    BadSignature,
    Stale,
    _now_text,
    _username,
    check_signed_time,
)
from .duties import _check_duties
from .keys import _usable_key
from .submission import _report, get_submission


@dataclass(frozen=True)
class Context:
    submission: Submission
    version: MissionVersion
    mission: Mission
    report: ReportDocument


def _context(db: DbSession, submission_id: int, reports: ReportService) -> Context:
    submission = get_submission(db, submission_id)
    version = db.get_one(MissionVersion, submission.version_id)
    mission = get_mission(db, version.mission_id)
    return Context(submission, version, mission,
                   ReportDocument.from_json(_report(db, version, reports)))


def _statement(db: DbSession, ctx: Context, *, decision: str, reason: str, supervisor: User,
               key_id: str, time: str, nonce: str, revokes: str | None = None) -> dict[str, Any]:
    checker = ctx.report.checker
    if checker != fingerprint.checker_fingerprint():
        # report_for recomputes such reports; this guards the one thing that must never
        # happen: a signature over findings the current checks did not make.
        raise Stale("the validation report was made by other checks than this server's; "
                    "reload the review and prepare the statement again")
    orders = ctx.version.orders
    model = orders_from_data(orders)
    exports = export_digests(model, version=ctx.version.number,
                             submission=ctx.submission.id) if decision == "approved" else None
    return build_statement(
        mission=ctx.mission.id, version=ctx.version.number, orders_digest=ctx.version.digest,
        decision=decision, reason=reason, submission=ctx.submission.id,
        report_digest=json_digest(ctx.report.to_json()),
        paths=ctx.report.paths.to_json() if ctx.report.paths is not None else None,
        vehicle=orders.get("vehicle"), author=_username(db, ctx.version.author_id) or "",
        supervisor=supervisor.username, key_id=key_id, time=time, nonce=nonce, revokes=revokes,
        rehearsal_digest=ctx.submission.rehearsal_digest,
        probabilities=ctx.report.probabilities, exports=exports,
        campaigns=cited_campaigns(db, ctx.submission.id),
        checker=checker,
        team=member_digests(model) if model.team is not None else None)


@dataclass(frozen=True)
class Prepared:
    statement: dict[str, Any]
    payload: bytes

    def to_json(self) -> dict[str, Any]:
        return {"payloadType": dsse.PAYLOAD_TYPE, "payload": dsse.b64(self.payload),
                "pae": dsse.b64(dsse.pae(dsse.PAYLOAD_TYPE, self.payload)),
                "statement": self.statement}


def _reason(decision: str, reason: str) -> str:
    reason = reason.strip()
    if decision in ("rejected", "revoked") and not reason:
        raise BadDecision(f"a {decision.removesuffix('ed')}ion needs a reason"
                           if decision == "rejected" else "a revocation needs a reason")
    if len(reason) > MAX_REASON:
        raise BadDecision(f"a reason has at most {MAX_REASON} characters")
    return reason


def prepare_decision(db: DbSession, *, submission_id: int, supervisor: User, decision: str,
                     reason: str, key_id: str, reports: ReportService,
                     signer: LogSigner | None) -> Prepared:
    """The exact statement the supervisor signs (the client signs its DSSE PAE)."""
    if decision not in ("approved", "rejected"):
        raise BadDecision("decision is 'approved' or 'rejected'")
    ctx = _context(db, submission_id, reports)
    _check_open(ctx)
    _check_duties(db, supervisor, ctx.version, ctx.submission, signer=signer)
    _usable_key(db, key_id, supervisor)
    statement = _statement(db, ctx, decision=decision, reason=_reason(decision, reason),
                           supervisor=supervisor, key_id=key_id, time=_now_text(),
                           nonce=secrets.token_hex(16))
    return Prepared(statement, statement_bytes(statement))


def _check_open(ctx: Context) -> None:
    if ctx.submission.state != "submitted":
        raise Stale(f"submission {ctx.submission.id} is {ctx.submission.state}; "
                    "there is nothing to decide")
    if ctx.report.errors:
        raise Stale("the current validation report of this version has errors")


def _verified(db: DbSession, envelope_text: str, supervisor: User
              ) -> tuple[dict[str, Any], dict[str, Any], SigningKey, bytes]:
    try:
        envelope = dsse.parse_envelope(envelope_text)
    except SignatureError as exc:
        raise BadSignature(str(exc)) from None
    key = _usable_key(db, dsse.envelope_key_id(envelope), supervisor)
    try:
        payload = dsse.verify_envelope(envelope, dsse.public_key(key.public_key))
        statement = parse_statement(payload)
    except (SignatureError, ValueError) as exc:
        raise BadSignature(str(exc)) from None
    used = db.scalar(select(Approval.id).where(
        Approval.payload_digest == json_digest(statement)))
    if used is not None:
        raise Stale(f"this signed statement was used already (approval {used}); replay refused")
    return envelope, statement, key, payload


def _check_fresh(db: DbSession, ctx: Context, statement: dict[str, Any], supervisor: User,
                 key: SigningKey, revokes: str | None = None) -> None:
    predicate = statement["predicate"]
    check_signed_time(predicate.get("time"))
    decision = predicate.get("decision")
    if decision not in ("approved", "rejected", "revoked"):
        raise BadSignature("the statement's decision is not approved, rejected or revoked")
    expected = _statement(db, ctx, decision=str(decision), reason=str(predicate.get("reason")),
                          supervisor=supervisor, key_id=key.id, time=str(predicate.get("time")),
                          nonce=str(predicate.get("nonce")), revokes=revokes)
    if subject_digest(statement) != ctx.version.digest:
        raise Stale(f"the statement signs {subject_digest(statement)}, but version "
                    f"{ctx.version.number} is {ctx.version.digest}")
    differing = sorted(k for k in expected["predicate"]
                       if expected["predicate"][k] != predicate.get(k))
    if differing or expected != statement:
        fields = ", ".join(differing) or "subject"
        raise Stale(f"the signed statement no longer matches the stored version and its "
                    f"current report ({fields} differ); prepare it again")


def _store(db: DbSession, ctx: Context, *, envelope_text: str, statement: dict[str, Any],
           key: SigningKey, supervisor: User, revokes: Approval | None,
           signer: LogSigner | None) -> Approval:
    predicate = statement["predicate"]
    decision = str(predicate["decision"])
    detail = {"decision": decision, "envelope_digest": dsse.envelope_digest(envelope_text),
              "payload_digest": json_digest(statement), "key_id": key.id,
              "submission": ctx.submission.id, "version": ctx.version.number,
              "orders_digest": ctx.version.digest, "reason": predicate["reason"],
              "revokes": revokes.id if revokes else None}
    event = record(db, kind=f"approval.{decision}", actor=supervisor, mission_id=ctx.mission.id,
                   after=ctx.version.digest, detail=detail, signer=signer)
    approval = Approval(
        submission_id=ctx.submission.id, version_id=ctx.version.id, mission_id=ctx.mission.id,
        vehicle=ctx.version.orders.get("vehicle"), author_id=ctx.version.author_id,
        decision=decision, reason=str(predicate["reason"]),
        revokes=revokes.id if revokes else None, supervisor_id=supervisor.id, key_id=key.id,
        envelope=envelope_text, envelope_digest=detail["envelope_digest"],
        payload_digest=detail["payload_digest"], orders_digest=ctx.version.digest,
        event_id=event.id)
    db.add(approval)
    ctx.submission.state = decision
    ctx.submission.decided_by, ctx.submission.decided_at = supervisor.id, utcnow()
    ctx.submission.reason = approval.reason
    ctx.mission.status = decision
    try:
        db.flush()
    except IntegrityError:  # uq_approvals_*_submission: a parallel decision won
        raise Stale(f"submission {ctx.submission.id} was decided by another request just now"
                    ) from None
    # The entry's receipt (receipt_of) is the caller's proof of logging; checkpoints are
    # signed over committed entries only (_checkpoint_now).
    return approval


def decide(db: DbSession, *, submission_id: int, supervisor: User, envelope: str,
           password: str | None, reports: ReportService, signer: LogSigner | None) -> Approval:
    """Verify a signed decision and store its envelope verbatim, or refuse with nothing kept.
    `password` is the supervisor's, entered again for this decision (store/reauth.py)."""
    # User verification first, then the row locks (store/decide_guard.py).
    confirm_password(db, username=supervisor.username, password_hash=supervisor.password_hash,
                     password=password)
    lock_submission(db, submission_id)
    ctx = _context(db, submission_id, reports)
    _check_duties(db, supervisor, ctx.version, ctx.submission, signer=signer)
    _, statement, key, _ = _verified(db, envelope, supervisor)
    if statement["predicate"].get("submission") != submission_id:
        raise Stale(f"the statement is about submission {statement['predicate'].get('submission')}"
                    f", not {submission_id}")
    if statement["predicate"].get("decision") not in ("approved", "rejected"):
        raise BadSignature("a decision is approved or rejected")
    _check_open(ctx)
    _check_fresh(db, ctx, statement, supervisor, key)
    return _store(db, ctx, signer=signer, envelope_text=envelope, statement=statement, key=key,
                  supervisor=supervisor, revokes=None)


def get_approval(db: DbSession, approval_id: int) -> Approval:
    approval = db.get(Approval, approval_id)
    if approval is None:
        raise NotFound(f"no approval {approval_id}")
    return approval
