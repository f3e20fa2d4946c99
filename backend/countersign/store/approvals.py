"""Submission, review, signed decisions, supervisor keys and the transparency log (issue 6).

Every refusal raises before anything is written, and the route's transaction rolls back, so a
refused request records nothing. Every accepted step is an event (store/events.record), which
appends the next hash-chained leaf of the log in the same transaction."""

from __future__ import annotations

import secrets
import threading
from dataclasses import dataclass
from datetime import datetime, timedelta
from typing import Any

from argon2.exceptions import InvalidHashError, VerificationError
from sqlalchemy import Select, select
from sqlalchemy.exc import IntegrityError
from sqlalchemy.orm import Session as DbSession
from sqlalchemy.orm import aliased

from ..approvals import dsse
from ..approvals.bundle import BUNDLE_FORMAT
from ..approvals.dsse import SignatureError
from ..approvals.merkle import Tree
from ..approvals.note import signature_line
from ..approvals.signer import LogSigner
from ..approvals.signer import Refused as SignerRefused
from ..approvals.statement import (
    build_statement,
    json_digest,
    parse_statement,
    statement_bytes,
    subject_digest,
)
from ..orders.reader import orders_from_data
from .accounts import HASHER
from .db import BEGIN_MODE
from .decide_guard import (
    editors_up_to,
    lock_submission,
    lock_version,
    logged_key_revocation,
)
from .events import record
from .integrity import approval_integrity
from .missions import Conflict, MissionError, NotFound, get_mission, get_version, report_for
from .reauth import confirm_password
from .rehearsals import attach as attach_rehearsal
from .tables import (
    Approval,
    Checkpoint,
    LogEntry,
    LogReceipt,
    Mission,
    MissionVersion,
    RehearsalRecord,
    SigningKey,
    Submission,
    User,
    utcnow,
)

STATEMENT_MAX_AGE = timedelta(hours=1)
CLOCK_SKEW = timedelta(minutes=5)
MAX_REASON = 2000


class Refused(MissionError):
    """The caller may not do this (wrong role, own work, someone else's key)."""

    status = 403


class Stale(MissionError):
    """The request was made against a state that has changed (or was already used)."""

    status = 409


class BadSignature(MissionError):
    status = 400


def _now_text() -> str:
    return utcnow().isoformat().replace("+00:00", "Z")


def _username(db: DbSession, user_id: int | None) -> str | None:
    if user_id is None:
        return None
    user = db.get(User, user_id)
    return user.username if user else f"#{user_id}"


# --- keys -----------------------------------------------------------------------------------

def _confirm_password(user: User, password: str) -> None:
    try:
        HASHER.verify(user.password_hash, password)
    except (VerificationError, InvalidHashError):
        raise Refused("the password confirmation is wrong") from None


def register_key(db: DbSession, *, user: User, public_key: str, name: str,
                 password: str) -> SigningKey:
    if user.role != "supervisor":
        raise Refused("only supervisors register signing keys")
    _confirm_password(user, password)
    try:
        kid = dsse.key_id(public_key)
    except SignatureError as exc:
        raise MissionError(str(exc)) from None
    if db.get(SigningKey, kid) is not None:
        raise Conflict(f"the key {kid} is registered already")
    key = SigningKey(id=kid, user_id=user.id, name=name[:100], public_key=public_key)
    db.add(key)
    db.flush()
    record(db, kind="key.registered", actor=user, detail={
        "key_id": kid, "public_key": public_key, "user": user.username, "name": key.name})
    return key


def revoke_key(db: DbSession, *, user: User, key_id: str, password: str,
               reason: str) -> SigningKey:
    key = db.get(SigningKey, key_id)
    if key is None:
        raise NotFound(f"no signing key {key_id!r}")
    if key.user_id != user.id and user.role != "admin":
        raise Refused("only the key's owner or an admin can revoke it")
    _confirm_password(user, password)
    if key.revoked_at is not None:
        raise Stale(f"the key {key_id} is revoked already")
    key.revoked_at, key.revoke_reason = utcnow(), reason[:MAX_REASON]
    record(db, kind="key.revoked", actor=user, detail={"key_id": key_id, "reason": reason})
    return key


def key_status(db: DbSession, key: SigningKey) -> str:
    """From the log (issue 14 item 5); a row that claims otherwise is reported by integrity."""
    if key.revoked_at is not None or logged_key_revocation(db, key.id) is not None:
        return "revoked"
    return "active"


def _usable_key(db: DbSession, key_id: str, supervisor: User) -> SigningKey:
    key = db.get(SigningKey, key_id)
    if key is None:
        raise Refused(f"the key {key_id!r} is not registered")
    if key.user_id != supervisor.id:
        raise Refused(f"the key {key_id} belongs to someone else")
    if key.revoked_at is not None:
        raise Refused(f"the key {key_id} was revoked at {key.revoked_at.isoformat()}")
    # The log, not the row, says whether a key is revoked (issue 14 finding 5: a writer who
    # sets revoked_at back to NULL must not make the key usable again).
    logged = logged_key_revocation(db, key_id)
    if logged is not None:
        raise Refused(f"the key {key_id} was revoked (log entry {logged}); the signing_keys "
                      "row disagrees with the log")
    return key


# --- workflow -------------------------------------------------------------------------------

def _report(db: DbSession, version: MissionVersion) -> dict[str, Any]:
    return report_for(db, orders_from_data(version.orders), version.digest).report


def submit(db: DbSession, *, mission_id: str, number: int, operator: User,
           rehearsal: str | None = None) -> Submission:
    mission = get_mission(db, mission_id)
    version = get_version(db, mission_id, number)
    lock_version(db, version.id)  # issue 14 item 6: parallel submits of one version queue here
    report = _report(db, version)
    errors = [f for f in report["findings"] if f["severity"] == "error"]
    if errors:
        codes = ", ".join(sorted({f["code"] for f in errors}))
        raise Stale(f"version {number} has {len(errors)} error finding(s) ({codes}); fix them "
                    "in the draft and create a new version")
    active = db.scalar(select(Submission).where(
        Submission.version_id == version.id, Submission.state.in_(("submitted", "approved"))))
    if active is not None:
        raise Stale(f"version {number} is {active.state} already (submission {active.id})")
    submission = Submission(version_id=version.id, submitted_by=operator.id)
    db.add(submission)
    try:
        db.flush()
    except IntegrityError:  # uq_submissions_active_version: a parallel submit won
        raise Stale(f"version {number} was submitted by another request just now") from None
    mission.status = "submitted"
    record(db, kind="submission.created", actor=operator, mission_id=mission_id,
           after=version.digest, detail={"submission": submission.id, "version": number})
    if rehearsal is not None:
        attach_rehearsal(db, submission=submission, digest=rehearsal, actor=operator)
    return submission


def get_submission(db: DbSession, submission_id: int) -> Submission:
    submission = db.get(Submission, submission_id)
    if submission is None:
        raise NotFound(f"no submission {submission_id}")
    return submission


def withdraw(db: DbSession, *, submission_id: int, operator: User) -> Submission:
    submission = get_submission(db, submission_id)
    if submission.submitted_by != operator.id:
        raise Refused("only the operator who submitted it can withdraw a submission")
    if submission.state != "submitted":
        raise Stale(f"submission {submission_id} is {submission.state}, not submitted")
    version = db.get_one(MissionVersion, submission.version_id)
    submission.state, submission.decided_at = "withdrawn", utcnow()
    get_mission(db, version.mission_id).status = "withdrawn"
    record(db, kind="submission.withdrawn", actor=operator, mission_id=version.mission_id,
           after=version.digest, detail={"submission": submission_id, "version": version.number})
    return submission


def _editors(db: DbSession, version: MissionVersion) -> set[int]:
    """Everyone who authored or edited any revision leading to this version (decide_guard)."""
    return editors_up_to(db, version)


def _check_duties(db: DbSession, supervisor: User, version: MissionVersion,
                  submission: Submission) -> None:
    if supervisor.role != "supervisor":
        raise Refused(f"the {supervisor.role} role may not sign decisions")
    if supervisor.id in _editors(db, version) | {submission.submitted_by}:
        raise Refused("separation of duties: you authored, edited or submitted this version, "
                      "so another supervisor must decide on it")


def decision_refusal(db: DbSession, user: User, version: MissionVersion,
                     submission: Submission | None) -> str | None:
    """Why this user may not sign a decision on this version (None when they may): what
    the review page shows beside a disabled button; signing checks it again."""
    if user.role != "supervisor":
        return f"the {user.role} role may not sign decisions"
    try:
        if submission is None:
            raise Stale("the version is not submitted")
        _check_duties(db, user, version, submission)
        if submission.state != "submitted":
            raise Stale(f"submission {submission.id} is {submission.state}; there is nothing "
                        "to decide")
    except MissionError as exc:
        return str(exc)
    return None


def previous_approval(db: DbSession, version: MissionVersion) -> Approval | None:
    """The newest approval of an earlier version of the same mission (revoked or not)."""
    return db.scalar(
        select(Approval).join(MissionVersion, MissionVersion.id == Approval.version_id)
        .where(Approval.mission_id == version.mission_id, Approval.decision == "approved",
               MissionVersion.number < version.number)
        .order_by(MissionVersion.number.desc(), Approval.id.desc()).limit(1))


@dataclass(frozen=True)
class Context:
    submission: Submission
    version: MissionVersion
    mission: Mission
    report: dict[str, Any]


def _context(db: DbSession, submission_id: int) -> Context:
    submission = get_submission(db, submission_id)
    version = db.get_one(MissionVersion, submission.version_id)
    mission = get_mission(db, version.mission_id)
    return Context(submission, version, mission, _report(db, version))


def _statement(db: DbSession, ctx: Context, *, decision: str, reason: str, supervisor: User,
               key_id: str, time: str, nonce: str, revokes: str | None = None) -> dict[str, Any]:
    orders = ctx.version.orders
    return build_statement(
        mission=ctx.mission.id, version=ctx.version.number, orders_digest=ctx.version.digest,
        decision=decision, reason=reason, submission=ctx.submission.id,
        report_digest=json_digest(ctx.report), paths=ctx.report.get("paths"),
        vehicle=orders.get("vehicle"), author=_username(db, ctx.version.author_id) or "",
        supervisor=supervisor.username, key_id=key_id, time=time, nonce=nonce, revokes=revokes,
        rehearsal_digest=ctx.submission.rehearsal_digest,
        probabilities=ctx.report.get("probabilities"))


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
        raise MissionError(f"a {decision.removesuffix('ed')}ion needs a reason"
                           if decision == "rejected" else "a revocation needs a reason")
    if len(reason) > MAX_REASON:
        raise MissionError(f"a reason has at most {MAX_REASON} characters")
    return reason


def prepare_decision(db: DbSession, *, submission_id: int, supervisor: User, decision: str,
                     reason: str, key_id: str) -> Prepared:
    """The exact statement the supervisor signs (the client signs its DSSE PAE)."""
    if decision not in ("approved", "rejected"):
        raise MissionError("decision is 'approved' or 'rejected'")
    ctx = _context(db, submission_id)
    _check_open(ctx)
    _check_duties(db, supervisor, ctx.version, ctx.submission)
    _usable_key(db, key_id, supervisor)
    statement = _statement(db, ctx, decision=decision, reason=_reason(decision, reason),
                           supervisor=supervisor, key_id=key_id, time=_now_text(),
                           nonce=secrets.token_hex(16))
    return Prepared(statement, statement_bytes(statement))


def _check_open(ctx: Context) -> None:
    if ctx.submission.state != "submitted":
        raise Stale(f"submission {ctx.submission.id} is {ctx.submission.state}; "
                    "there is nothing to decide")
    if ctx.report["findings"] and any(f["severity"] == "error" for f in ctx.report["findings"]):
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
    try:
        signed_at = datetime.fromisoformat(str(predicate.get("time")).replace("Z", "+00:00"))
        if signed_at.tzinfo is None:
            raise ValueError
    except ValueError:
        raise BadSignature("the statement's time is not an ISO 8601 UTC timestamp") from None
    now = utcnow()
    if not now - STATEMENT_MAX_AGE <= signed_at <= now + CLOCK_SKEW:
        raise Stale("the statement was prepared too long ago or in the future; prepare it again")
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


class LogUnvouched(MissionError):
    """The log signer refused to vouch for the log as the database holds it."""

    status = 503


def _checkpoint_now(db: DbSession, signer: LogSigner, *,
                    adopted: int | None = None) -> tuple[Checkpoint | None, str | None]:
    """The checkpoint of the committed log, signed now unless the latest one covers it, and
    why the signer refused to sign a newer one (None when it did not refuse). Only committed
    entries are signed, so a signed head is never rolled back with a failed transaction.
    A read-only session signs through a short write session."""
    if not db.info.get("write", True):
        from .db import database_of

        with database_of(db).session() as writer:
            return _checkpoint_now(writer, signer, adopted=adopted)
    tree = _committed_tree(db)
    latest = db.scalar(select(Checkpoint).where(Checkpoint.tree_size <= tree.size)
                       .order_by(Checkpoint.tree_size.desc()).limit(1))
    if tree.size == 0 or (latest is not None and latest.tree_size == tree.size):
        return latest, None
    head = signer.head()
    if tree.size < head.size:
        # Another process signed a newer head that this snapshot does not see yet.
        return latest, None
    receipts = dict(db.execute(select(LogReceipt.index, LogReceipt.receipt).where(
        LogReceipt.index >= head.size, LogReceipt.index < tree.size)).all())
    try:
        signed = signer.sign_head(tree, receipts, adopted)
    except SignerRefused as exc:
        return latest, str(exc)
    row = Checkpoint(tree_size=tree.size, root_hash=signed["root"], key_id=signed["key_id"],
                     public_key=signed["public_key"], note=signed["signed_note"],
                     signature=signed["signature"])
    db.add(row)
    db.flush()
    return row, None


def receipt_of(db: DbSession, approval: Approval) -> str | None:
    """The log signer's receipt for the approval's log entry."""
    index = log_index_of(db, approval.event_id)
    return None if index is None else db.scalar(
        select(LogReceipt.receipt).where(LogReceipt.index == index))


def _store(db: DbSession, ctx: Context, *, envelope_text: str, statement: dict[str, Any],
           key: SigningKey, supervisor: User, revokes: Approval | None,
           signer: LogSigner) -> Approval:
    predicate = statement["predicate"]
    decision = str(predicate["decision"])
    detail = {"decision": decision, "envelope_digest": dsse.envelope_digest(envelope_text),
              "payload_digest": json_digest(statement), "key_id": key.id,
              "submission": ctx.submission.id, "version": ctx.version.number,
              "orders_digest": ctx.version.digest, "reason": predicate["reason"],
              "revokes": revokes.id if revokes else None}
    event = record(db, kind=f"approval.{decision}", actor=supervisor, mission_id=ctx.mission.id,
                   after=ctx.version.digest, detail=detail)
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
           signer: LogSigner, password: str | None) -> Approval:
    """Verify a signed decision and store its envelope verbatim, or refuse with nothing kept.
    `password` is the supervisor's, entered again for this decision (store/reauth.py)."""
    # issue 14 (decisions): user verification first, then the row locks (store/decide_guard.py).
    confirm_password(db, username=supervisor.username, password_hash=supervisor.password_hash,
                     password=password)
    lock_submission(db, submission_id)
    ctx = _context(db, submission_id)
    _check_duties(db, supervisor, ctx.version, ctx.submission)
    _, statement, key, _ = _verified(db, envelope, supervisor)
    if statement["predicate"].get("submission") != submission_id:
        raise Stale(f"the statement is about submission {statement['predicate'].get('submission')}"
                    f", not {submission_id}")
    if statement["predicate"].get("decision") not in ("approved", "rejected"):
        raise BadSignature("a decision is approved or rejected")
    _check_open(ctx)
    _check_fresh(db, ctx, statement, supervisor, key)
    return _store(db, ctx, envelope_text=envelope, statement=statement, key=key,
                  supervisor=supervisor, revokes=None, signer=signer)


def get_approval(db: DbSession, approval_id: int) -> Approval:
    approval = db.get(Approval, approval_id)
    if approval is None:
        raise NotFound(f"no approval {approval_id}")
    return approval


def _revocable(db: DbSession, approval_id: int) -> tuple[Approval, Context]:
    approval = get_approval(db, approval_id)
    if approval.decision != "approved":
        raise Stale(f"approval {approval_id} is a {approval.decision} record; only approvals "
                    "can be revoked")
    ctx = _context(db, approval.submission_id)
    if ctx.submission.state != "approved":
        raise Stale(f"approval {approval_id} is {ctx.submission.state} already")
    return approval, ctx


def prepare_revocation(db: DbSession, *, approval_id: int, supervisor: User, reason: str,
                       key_id: str) -> Prepared:
    approval, ctx = _revocable(db, approval_id)
    _check_duties(db, supervisor, ctx.version, ctx.submission)
    _usable_key(db, key_id, supervisor)
    statement = _statement(db, ctx, decision="revoked", reason=_reason("revoked", reason),
                           supervisor=supervisor, key_id=key_id, time=_now_text(),
                           nonce=secrets.token_hex(16), revokes=approval.envelope_digest)
    return Prepared(statement, statement_bytes(statement))


def revoke(db: DbSession, *, approval_id: int, supervisor: User, envelope: str,
           signer: LogSigner, password: str | None) -> Approval:
    # issue 14 (decisions): user verification first, then the row locks (store/decide_guard.py).
    confirm_password(db, username=supervisor.username, password_hash=supervisor.password_hash,
                     password=password)
    lock_submission(db, get_approval(db, approval_id).submission_id)
    approval, ctx = _revocable(db, approval_id)
    _check_duties(db, supervisor, ctx.version, ctx.submission)
    _, statement, key, _ = _verified(db, envelope, supervisor)
    if statement["predicate"].get("decision") != "revoked":
        raise BadSignature("a revocation statement has decision 'revoked'")
    _check_fresh(db, ctx, statement, supervisor, key, revokes=approval.envelope_digest)
    return _store(db, ctx, envelope_text=envelope, statement=statement, key=key,
                  supervisor=supervisor, revokes=approval, signer=signer)


# --- the log --------------------------------------------------------------------------------

class _Cache:
    def __init__(self) -> None:
        self.lock = threading.Lock()
        self.trees: dict[str, Tree] = {}


_CACHE = _Cache()


def _committed_tree(db: DbSession) -> Tree:
    """The committed log as a Merkle tree, cached per database and extended incrementally.
    The log only grows: one query returns the last cached leaf (to check that the cache still
    matches the database; otherwise it is rebuilt) and any newer leaves. Cached trees are never
    mutated, only replaced, so concurrent readers may share them."""
    engine = db.get_bind().engine
    name = engine.url.render_as_string(hide_password=True)
    cached = _CACHE.trees.get(name)
    with engine.connect() as opened:
        # A reader of committed rows: never ask for SQLite's write lock (this request may hold it).
        connection = opened.execution_options(**{BEGIN_MODE: "DEFERRED"})
        since = cached.size - 1 if cached is not None and cached.size else 0
        rows = connection.execute(select(LogEntry.index, LogEntry.leaf_hash).where(
            LogEntry.index >= since).order_by(LogEntry.index)).all()
        if cached is not None and cached.size:
            if not rows or rows[0][0] != since or bytes.fromhex(rows[0][1]) != \
                    cached.levels[0][-1]:
                cached, since = None, 0
                rows = connection.execute(select(LogEntry.index, LogEntry.leaf_hash)
                                          .order_by(LogEntry.index)).all()
            else:
                rows = rows[1:]
        if cached is not None and not rows:
            return cached
        tree = cached.copy() if cached is not None else Tree()
        for _, leaf in rows:
            tree.append(bytes.fromhex(leaf))
    with _CACHE.lock:
        current = _CACHE.trees.get(name)
        if current is None or current.size <= tree.size:
            _CACHE.trees[name] = tree
    return tree


def log_tree(db: DbSession, *, pending: bool = False) -> Tree:
    """The log's tree; with `pending`, including entries this transaction appended."""
    tree = _committed_tree(db)
    if pending:
        rows = list(db.scalars(select(LogEntry.leaf_hash).where(LogEntry.index >= tree.size)
                               .order_by(LogEntry.index)))
        if rows:
            tree = tree.copy()
            for leaf in rows:
                tree.append(bytes.fromhex(leaf))
    return tree


def latest_checkpoint(db: DbSession, *, signer: LogSigner) -> Checkpoint:
    row, refusal = _checkpoint_now(db, signer)
    if row is None:
        raise LogUnvouched(refusal or "the log has no signed checkpoint yet")
    return row


def checkpoint_refusal(db: DbSession, *, signer: LogSigner) -> str | None:
    """Why the signer will not sign the log's current head (None when it signs)."""
    return _checkpoint_now(db, signer)[1]


def checkpoint_json(row: Checkpoint, cosignatures: list[str] | None = None) -> dict[str, Any]:
    body, signed = row.note, row.note
    if "\n\n" in row.note:  # a signed note (older rows hold only the body)
        body = row.note.split("\n\n", 1)[0] + "\n"
    else:
        signed = legacy_signed_note(row)
    if cosignatures:
        signed = signed + "".join(cosignatures)
    return {"size": row.tree_size, "root": row.root_hash, "note": body, "signed_note": signed,
            "origin": body.split("\n", 1)[0], "key_id": row.key_id,
            "public_key": row.public_key, "signature": row.signature,
            "created_at": row.created_at.isoformat()}


def legacy_signed_note(row: Checkpoint) -> str:
    """The signed note of a checkpoint signed before checkpoints were signed notes: its
    signature is the log key's Ed25519 signature over the body, which is what a note's
    signature line carries (so the old checkpoint verifies as a note, under its origin)."""
    origin = row.note.split("\n", 1)[0]
    try:
        public = dsse.raw_public(dsse.public_key(row.public_key))
        signature = dsse.unb64(row.signature, "the checkpoint signature")
    except dsse.SignatureError:
        return row.note  # left for the verifier to refuse
    return row.note + "\n" + signature_line(origin, public, signature)


def inclusion_proof(db: DbSession, *, index: int, size: int | None = None) -> dict[str, Any]:
    tree = _committed_tree(db)
    size = tree.size if size is None else size
    if not 0 <= index < size <= tree.size:
        raise NotFound(f"no log entry {index} in a tree of size {size} (the log has "
                       f"{tree.size} entries)")
    return {"index": index, "size": size, "leaf_hash": tree.levels[0][index].hex(),
            "root": tree.root(size).hex(),
            "hashes": [h.hex() for h in tree.inclusion_proof(index, size)]}


def consistency_proof(db: DbSession, *, first: int, second: int | None = None) -> dict[str, Any]:
    tree = _committed_tree(db)
    second = tree.size if second is None else second
    if not 0 < first <= second <= tree.size:
        raise NotFound(f"no consistency proof from size {first} to {second} (the log has "
                       f"{tree.size} entries)")
    return {"first": first, "second": second, "first_root": tree.root(first).hex(),
            "second_root": tree.root(second).hex(),
            "hashes": [h.hex() for h in tree.consistency_proof(first, second)]}


def log_index_of(db: DbSession, event_id: int) -> int | None:
    return db.scalar(select(LogEntry.index).where(LogEntry.event_id == event_id))


def entries(db: DbSession, *, start: int, limit: int) -> list[dict[str, Any]]:
    rows = list(db.scalars(select(LogEntry).where(LogEntry.index >= start)
                           .order_by(LogEntry.index).limit(limit)))
    receipts = dict(db.execute(select(LogReceipt.index, LogReceipt.receipt).where(
        LogReceipt.index.in_([r.index for r in rows]))).all()) if rows else {}
    return [{"index": r.index, "leaf_hash": r.leaf_hash, "entry": r.entry,
             "receipt": receipts.get(r.index)} for r in rows]


def _receipts(db: DbSession, size: int) -> list[str | None]:
    found = dict(db.execute(select(LogReceipt.index, LogReceipt.receipt)).all())
    return [found.get(i) for i in range(size)]


# --- audit ----------------------------------------------------------------------------------

@dataclass(frozen=True)
class Filters:
    mission: str | None = None
    operator: str | None = None
    supervisor: str | None = None
    vehicle: str | None = None
    decision: str | None = None
    since: datetime | None = None
    until: datetime | None = None


def approvals_query(filters: Filters) -> Select[Approval]:
    query = select(Approval).order_by(Approval.id.desc())
    if filters.mission:
        query = query.where(Approval.mission_id == filters.mission)
    if filters.vehicle:
        query = query.where(Approval.vehicle == filters.vehicle)
    if filters.decision:
        query = query.where(Approval.decision == filters.decision)
    if filters.since:
        query = query.where(Approval.created_at >= filters.since)
    if filters.until:
        query = query.where(Approval.created_at < filters.until)
    if filters.operator:
        author = aliased(User)
        query = query.join(author, author.id == Approval.author_id).where(
            author.username == filters.operator)
    if filters.supervisor:
        signer = aliased(User)
        query = query.join(signer, signer.id == Approval.supervisor_id).where(
            signer.username == filters.supervisor)
    return query


def approval_summary(db: DbSession, approval: Approval) -> dict[str, Any]:
    version = db.get_one(MissionVersion, approval.version_id)
    return {"id": approval.id, "mission": approval.mission_id, "version": version.number,
            "digest": approval.orders_digest, "vehicle": approval.vehicle,
            "decision": approval.decision, "reason": approval.reason,
            "revokes": approval.revokes, "operator": _username(db, approval.author_id),
            "supervisor": _username(db, approval.supervisor_id), "key_id": approval.key_id,
            "submission": approval.submission_id, "created_at": approval.created_at,
            "log_index": log_index_of(db, approval.event_id),
            # issue 14 item 5 (branch decisions): the row checked against its log entry.
            "integrity": approval_integrity(db, approval)}


def build_bundle(db: DbSession, *, signer: LogSigner,
                 mission: str | None = None) -> dict[str, Any]:
    """Everything an auditor needs to verify offline: the whole log, its checkpoints, the
    log key, the supervisors' keys, the envelopes with inclusion proofs and their orders."""
    if not db.info.get("write", True):
        # One transaction sees the log, signs its checkpoint and reads what it covers.
        from .db import database_of

        with database_of(db).session() as writer:
            return build_bundle(writer, signer=signer, mission=mission)
    latest, refusal = _checkpoint_now(db, signer)
    tree = log_tree(db, pending=True)
    covered = latest.tree_size if latest is not None else 0
    rows = list(db.scalars(approvals_query(Filters(mission=mission)).order_by(None)
                           .order_by(Approval.id)))
    indexes: dict[int, int] = {}
    for start in range(0, len(rows), 500):
        for event_id, index in db.execute(select(LogEntry.event_id, LogEntry.index).where(
                LogEntry.event_id.in_([a.event_id for a in rows[start:start + 500]]))):
            indexes[event_id] = index
    orders: dict[str, Any] = {}
    approvals = []
    cited: set[str] = set()
    for approval in rows:
        if approval.orders_digest not in orders:
            orders[approval.orders_digest] = db.get_one(MissionVersion, approval.version_id).orders
        submission = db.get_one(Submission, approval.submission_id)
        if submission.rehearsal_digest is not None:
            cited.add(submission.rehearsal_digest)
        index = indexes[approval.event_id]
        approvals.append({
            "id": approval.id, "mission": approval.mission_id, "decision": approval.decision,
            "log_index": index, "envelope": approval.envelope,
            "inclusion": {"index": index, "size": covered,
                          "hashes": [h.hex() for h in tree.inclusion_proof(index, covered)]
                          if index < covered else []},
        })
    keys = [{"key_id": k.id, "public_key": k.public_key, "user": _username(db, k.user_id),
             "created_at": k.created_at.isoformat(),
             "revoked_at": k.revoked_at.isoformat() if k.revoked_at else None}
            for k in db.scalars(select(SigningKey).order_by(SigningKey.created_at))]
    return {
        "format": BUNDLE_FORMAT,
        "created_at": _now_text(),
        # The mission the approvals were exported for (None: all); decisions of other
        # missions need no envelope in this bundle (approvals/log_rules.py).
        "scope": mission,
        "log_key": {"key_id": signer.key_id, "public_key": signer.public_text,
                    "origin": signer.origin, "verifier_key": signer.verifier_key},
        "entries": list(db.scalars(select(LogEntry.entry).order_by(LogEntry.index))),
        # The signer's receipt per entry (None where an entry has none: not appended by it).
        "receipts": _receipts(db, tree.size),
        "signer_refused": refusal,
        "checkpoints": [checkpoint_json(c) for c in db.scalars(
            select(Checkpoint).order_by(Checkpoint.tree_size))],
        "keys": keys,
        "orders": orders,
        "approvals": approvals,
        # Rehearsal records the approvals cite, by digest (replays: the record's replay URL).
        "rehearsals": {r.digest: r.record for r in db.scalars(
            select(RehearsalRecord).where(RehearsalRecord.digest.in_(sorted(cited))))}
        if cited else {},
    }
