"""The procedure library: saved procedure versions and their signed decisions.

Operators save a procedure version once (a change is the next version); supervisors sign a
decision on a version with their registered key, after entering their password again, as they
sign a mission's (store/approvals/decisions.py). Every save and decision is a log entry. The
log is the source of truth: a row whose document, digest or decision disagrees with its log
entry (or whose envelope no longer verifies) is reported in `integrity`, is not copied into
orders and counts as no approval.
"""

from __future__ import annotations

import secrets
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

from sqlalchemy import func, select
from sqlalchemy.exc import IntegrityError
from sqlalchemy.orm import Session as DbSession

from ..approvals import dsse
from ..approvals.dsse import SignatureError
from ..approvals.procedure_statement import (
    build_procedure_statement,
    parse_procedure_statement,
)
from ..approvals.signer import LogSigner
from ..approvals.statement import json_digest, statement_bytes, subject_digest
from ..errors import Conflict, NotFound, Unprocessable
from ..limits import MAX_REASON
from ..orders.model import Orders
from ..orders.procedure import Procedure, procedure_from_data
from ..orders.reader import OrdersReadError
from ..verify import fingerprint
from ..verify.procedures import check_procedure, expand, expand_procedure, uses
from .approvals.common import (
    BadSignature,
    Refused,
    Stale,
    _now_text,
    _username,
    check_signed_time,
)
from .approvals.decisions import Prepared
from .approvals.keys import _usable_key
from .events import record
from .integrity import logged_event
from .logged_roles import decision_refusal_from_log
from .procedure_tables import ProcedureApproval, ProcedureRecord
from .reauth import confirm_password
from .tables import SigningKey, User, utcnow

MAX_LISTED = 200  # versions listed, decisions per version (each is checked against the log)
MAX_USES = 200  # procedure versions one mission's review lists
MAX_FINDINGS_SHOWN = 10


# --- reading, and the rows checked against the log -------------------------------------------

def get_procedure(db: DbSession, name: str, version: int) -> ProcedureRecord:
    row = db.get(ProcedureRecord, (name, version))
    if row is None:
        raise NotFound(f"the library has no procedure {name!r} version {version}")
    return row


def list_procedures(db: DbSession, name: str | None = None) -> list[ProcedureRecord]:
    query = select(ProcedureRecord)
    if name is not None:
        query = query.where(ProcedureRecord.name == name)
    return list(db.scalars(query.order_by(ProcedureRecord.name, ProcedureRecord.version.desc())
                           .limit(MAX_LISTED)))


def _document(row: ProcedureRecord) -> Procedure | None:
    try:
        return procedure_from_data(row.document)
    except OrdersReadError:
        return None


def procedure_integrity(db: DbSession, row: ProcedureRecord) -> list[str]:
    """How the row disagrees with itself and with the log entry that recorded its saving."""
    what = f"procedure {row.name} version {row.version}"
    problems: list[str] = []
    procedure = _document(row)
    if procedure is None:
        problems.append(f"{what}: the stored document is not a procedure")
    elif (procedure.name, procedure.version) != (row.name, row.version):
        problems.append(f"{what}: the stored document is {procedure.name} version "
                        f"{procedure.version}")
    elif procedure.digest != row.digest:
        problems.append(f"{what}: the stored document has digest {procedure.digest}, the "
                        f"table says {row.digest}")
    event = logged_event(db, row.event_id)
    if event is None:
        return [*problems, f"{what} has no log entry"]
    detail = event.get("detail") if isinstance(event.get("detail"), dict) else {}
    assert isinstance(detail, dict)
    logged = (event.get("kind"), detail.get("procedure"), detail.get("version"),
              detail.get("digest"))
    if logged != ("procedure.saved", row.name, row.version, row.digest):
        problems.append(f"{what}: the table says it was saved with digest {row.digest}, its "
                        f"log entry records {logged[0]} of {logged[1]} version {logged[2]} "
                        f"with digest {logged[3]}")
    return problems


def trusted_procedure(db: DbSession, name: str, version: int) -> Procedure | None:
    """The library's procedure when its row agrees with itself and the log, else None."""
    row = db.get(ProcedureRecord, (name, version))
    if row is None or procedure_integrity(db, row):
        return None
    return _document(row)


def library_lookup(db: DbSession) -> Callable[[str, int], Procedure | None]:
    """The trusted library, each version looked up once however often the orders name it."""
    found: dict[tuple[str, int], Procedure | None] = {}

    def lookup(name: str, version: int) -> Procedure | None:
        if (name, version) not in found:
            found[(name, version)] = trusted_procedure(db, name, version)
        return found[(name, version)]

    return lookup


def with_library(db: DbSession, orders: Orders) -> Orders:
    """The orders with the bodies of the procedures they name copied in from the library."""
    if not uses(orders):
        return orders
    return expand(orders, library_lookup(db))


def approval_integrity(db: DbSession, approval: ProcedureApproval) -> list[str]:
    """How a decision row disagrees with its log entry or its own signed envelope."""
    what = f"procedure decision {approval.id}"
    problems: list[str] = []
    event = logged_event(db, approval.event_id)
    row = {"kind": f"procedure.{approval.decision}", "procedure": approval.name,
           "version": approval.version, "digest": approval.procedure_digest,
           "key_id": approval.key_id, "payload_digest": approval.payload_digest,
           "reason": approval.reason}
    if event is None:
        problems.append(f"{what} has no log entry")
    else:
        detail = event.get("detail") if isinstance(event.get("detail"), dict) else {}
        assert isinstance(detail, dict)
        logged = {**detail, "kind": event.get("kind")}
        problems.extend(f"{what}: the table says {field} = {value!r}, its log entry says "
                        f"{logged.get(field)!r}" for field, value in row.items()
                        if logged.get(field) != value)
    key = db.get(SigningKey, approval.key_id)
    try:
        envelope = dsse.parse_envelope(approval.envelope)
        if key is None or dsse.envelope_key_id(envelope) != key.id:
            raise SignatureError("its key is not the registered key it names")
        statement = parse_procedure_statement(
            dsse.verify_envelope(envelope, dsse.public_key(key.public_key)))
    except (SignatureError, ValueError) as exc:
        return [*problems, f"{what}: the stored envelope does not verify ({exc})"]
    predicate = statement["predicate"]
    signed = (subject_digest(statement), predicate.get("procedure"), predicate.get("version"),
              predicate.get("decision"), json_digest(statement))
    if signed != (approval.procedure_digest, approval.name, approval.version,
                  approval.decision, approval.payload_digest):
        problems.append(f"{what}: the table disagrees with the statement its envelope signs")
    return problems


def decisions_of(db: DbSession, name: str, version: int) -> list[ProcedureApproval]:
    return list(db.scalars(select(ProcedureApproval).where(
        ProcedureApproval.name == name, ProcedureApproval.version == version)
        .order_by(ProcedureApproval.id).limit(MAX_LISTED)))


def approved_by(db: DbSession, name: str, version: int, digest: str | None) -> str | None:
    """The supervisor whose signed approval of this version, at this digest, holds (its row
    agrees with the log and its envelope verifies, and the version's row does too)."""
    row = db.get(ProcedureRecord, (name, version))
    if row is None or digest is None or row.digest != digest or procedure_integrity(db, row):
        return None
    for approval in decisions_of(db, name, version):
        if (approval.decision == "approved" and approval.procedure_digest == digest
                and not approval_integrity(db, approval)):
            return _username(db, approval.supervisor_id)
    return None


@dataclass(frozen=True)
class ProcedureUse:
    name: str
    version: int
    digest: str | None
    in_library: bool
    approved_by: str | None


def procedure_uses(db: DbSession, orders: Orders) -> tuple[list[ProcedureUse], bool]:
    """Each procedure version the orders name (the first MAX_USES), whether a supervisor
    approved it, and whether more were left out."""
    named = uses(orders)
    return [ProcedureUse(name, version, digest, trusted_procedure(db, name, version) is not None,
                         approved_by(db, name, version, digest))
            for name, version, digest in named[:MAX_USES]], len(named) > MAX_USES


# --- saving ----------------------------------------------------------------------------------

def _check_next_version(db: DbSession, procedure: Procedure) -> None:
    name, version = procedure.name, procedure.version
    if db.get(ProcedureRecord, (name, version)) is not None:
        raise Conflict(f"procedure {name!r} version {version} is saved already and never "
                       "changes: save your change as the next version")
    latest = db.scalar(select(func.max(ProcedureRecord.version))
                       .where(ProcedureRecord.name == name)) or 0
    if version != latest + 1:
        raise Conflict(f"the next version of procedure {name!r} is {latest + 1}, not {version}")


def checked_procedure(db: DbSession, procedure: Procedure) -> Procedure:
    """The procedure with the library versions it names copied in, checked like a refinement
    (Unprocessable naming its errors). Only reads: give it a read session, as the check takes
    seconds at the largest size and a writer would hold the write lock all that time."""
    _check_next_version(db, procedure)
    expanded = expand_procedure(procedure, library_lookup(db))
    findings, _paths = check_procedure(expanded)
    errors = [f for f in findings if f.severity == "error"]
    if errors:
        shown = "; ".join(f"{f.code} [{', '.join(f.subjects)}]: {f.message}"
                          for f in errors[:MAX_FINDINGS_SHOWN])
        more = f" (and {len(errors) - MAX_FINDINGS_SHOWN} more)" \
            if len(errors) > MAX_FINDINGS_SHOWN else ""
        raise Unprocessable(f"procedure {procedure.name!r} version {procedure.version} has "
                            f"errors and is not saved: {shown}{more}")
    return expanded


def save_procedure(db: DbSession, *, procedure: Procedure, author: User,
                   signer: LogSigner | None) -> ProcedureRecord:
    """Save a new version that checked_procedure returned: the next number of its name
    (checked again here, under the write lock: another request may have saved it since)."""
    name, version = procedure.name, procedure.version
    _check_next_version(db, procedure)
    event = record(db, signer=signer, kind="procedure.saved", actor=author, detail={
        "procedure": name, "version": version, "digest": procedure.digest})
    row = ProcedureRecord(name=name, version=version, document=procedure.to_json(),
                          digest=procedure.digest, author_id=author.id, event_id=event.id,
                          updated_at=utcnow())
    db.add(row)
    try:
        db.flush()
    except IntegrityError:
        raise Conflict(f"procedure {name!r} version {version} was saved by another request "
                       "just now") from None
    return row


# --- signed decisions --------------------------------------------------------------------------

def _check_duties(db: DbSession, supervisor: User, row: ProcedureRecord, *,
                  signer: LogSigner | None) -> None:
    if supervisor.role != "supervisor":
        raise Refused(f"the {supervisor.role} role may not sign decisions")
    mismatch = decision_refusal_from_log(db, supervisor, signer=signer)
    if mismatch is not None:
        raise Refused(mismatch)
    if supervisor.id == row.author_id:
        raise Refused("separation of duties: you saved this procedure version, so another "
                      "supervisor must decide on it")


def _check_open(db: DbSession, row: ProcedureRecord) -> Procedure:
    problems = procedure_integrity(db, row)
    if problems:
        raise Stale("the stored procedure disagrees with the log, so it cannot be signed: "
                    + "; ".join(problems))
    if decisions_of(db, row.name, row.version):
        raise Stale(f"procedure {row.name!r} version {row.version} has a decision already")
    procedure = _document(row)
    assert procedure is not None
    return procedure


def _statement(db: DbSession, row: ProcedureRecord, procedure: Procedure, *, decision: str,
               reason: str, supervisor: User, key_id: str, time: str, nonce: str
               ) -> dict[str, Any]:
    findings, paths = check_procedure(procedure)
    if any(f.severity == "error" for f in findings):
        raise Stale("the procedure has errors under this server's checks")
    return build_procedure_statement(
        name=row.name, version=row.version, procedure_digest=row.digest, decision=decision,
        reason=reason, paths=paths.to_json() if paths is not None else None,
        author=_username(db, row.author_id) or "", supervisor=supervisor.username,
        key_id=key_id, time=time, nonce=nonce, checker=fingerprint.checker_fingerprint())


def _reason(decision: str, reason: str) -> str:
    reason = reason.strip()
    if decision == "rejected" and not reason:
        raise Unprocessable("a rejection needs a reason")
    if len(reason) > MAX_REASON:
        raise Unprocessable(f"a reason has at most {MAX_REASON} characters")
    return reason


def prepare_procedure_decision(db: DbSession, *, name: str, version: int, supervisor: User,
                               decision: str, reason: str, key_id: str,
                               signer: LogSigner | None) -> Prepared:
    """The exact statement the supervisor signs (the client signs its DSSE PAE)."""
    if decision not in ("approved", "rejected"):
        raise Unprocessable("decision is 'approved' or 'rejected'")
    row = get_procedure(db, name, version)
    _check_duties(db, supervisor, row, signer=signer)
    procedure = _check_open(db, row)
    _usable_key(db, key_id, supervisor)
    statement = _statement(db, row, procedure, decision=decision,
                           reason=_reason(decision, reason), supervisor=supervisor,
                           key_id=key_id, time=_now_text(), nonce=secrets.token_hex(16))
    return Prepared(statement, statement_bytes(statement))


def decide_procedure(db: DbSession, *, name: str, version: int, supervisor: User,
                     envelope: str, password: str | None,
                     signer: LogSigner | None) -> ProcedureApproval:
    """Verify a signed decision on a procedure version and store its envelope verbatim."""
    confirm_password(db, username=supervisor.username, password_hash=supervisor.password_hash,
                     password=password)
    row = get_procedure(db, name, version)
    _check_duties(db, supervisor, row, signer=signer)
    procedure = _check_open(db, row)
    try:
        parsed = dsse.parse_envelope(envelope)
    except SignatureError as exc:
        raise BadSignature(str(exc)) from None
    key = _usable_key(db, dsse.envelope_key_id(parsed), supervisor)
    try:
        statement = parse_procedure_statement(
            dsse.verify_envelope(parsed, dsse.public_key(key.public_key)))
    except (SignatureError, ValueError) as exc:
        raise BadSignature(str(exc)) from None
    payload_digest = json_digest(statement)
    if db.scalar(select(ProcedureApproval.id).where(
            ProcedureApproval.payload_digest == payload_digest)) is not None:
        raise Stale("this signed statement was used already; replay refused")
    predicate = statement["predicate"]
    check_signed_time(predicate.get("time"))
    decision = predicate.get("decision")
    if decision not in ("approved", "rejected"):
        raise BadSignature("the statement's decision is not approved or rejected")
    if subject_digest(statement) != row.digest:
        raise Stale(f"the statement signs {subject_digest(statement)}, but procedure "
                    f"{name!r} version {version} is {row.digest}")
    expected = _statement(db, row, procedure, decision=str(decision),
                          reason=str(predicate.get("reason")), supervisor=supervisor,
                          key_id=key.id, time=str(predicate.get("time")),
                          nonce=str(predicate.get("nonce")))
    if expected != statement:
        differing = sorted(k for k in expected["predicate"]
                           if expected["predicate"][k] != predicate.get(k)) or ["subject"]
        raise Stale("the signed statement does not match this procedure version as stored "
                    f"({', '.join(differing)} differ); prepare it again")
    reason = str(predicate.get("reason"))
    event = record(db, signer=signer, kind=f"procedure.{decision}", actor=supervisor, detail={
        "procedure": name, "version": version, "digest": row.digest, "decision": decision,
        "key_id": key.id, "payload_digest": payload_digest, "reason": reason})
    approval = ProcedureApproval(
        name=name, version=version, procedure_digest=row.digest, decision=str(decision),
        reason=reason, supervisor_id=supervisor.id, key_id=key.id, envelope=envelope,
        payload_digest=payload_digest, event_id=event.id, created_at=utcnow())
    db.add(approval)
    try:
        db.flush()
    except IntegrityError:
        raise Stale(f"procedure {name!r} version {version} was decided by another request "
                    "just now") from None
    return approval



