"""Revoking an approval with a signed revocation."""

from __future__ import annotations

import secrets

from sqlalchemy.orm import Session as DbSession

from ...approvals.signer import LogSigner
from ...approvals.statement import (
    statement_bytes,
)
from ..decide_guard import (
    lock_submission,
)
from ..reauth import confirm_password
from ..report_service import ReportService
from ..tables import (
    Approval,
    User,
)
from .common import BadSignature, Stale, _now_text
from .decisions import (
    Context,
    Prepared,
    _check_fresh,
    _context,
    _reason,
    _statement,
    _store,
    _verified,
    get_approval,
)
from .duties import _check_duties
from .keys import _usable_key


def _revocable(db: DbSession, approval_id: int,
               reports: ReportService) -> tuple[Approval, Context]:
    approval = get_approval(db, approval_id)
    if approval.decision != "approved":
        raise Stale(f"approval {approval_id} is a {approval.decision} record; only approvals "
                    "can be revoked")
    ctx = _context(db, approval.submission_id, reports)
    if ctx.submission.state != "approved":
        raise Stale(f"approval {approval_id} is {ctx.submission.state} already")
    return approval, ctx


def prepare_revocation(db: DbSession, *, approval_id: int, supervisor: User, reason: str,
                       key_id: str, reports: ReportService, signer: LogSigner | None) -> Prepared:
    approval, ctx = _revocable(db, approval_id, reports)
    _check_duties(db, supervisor, ctx.version, ctx.submission, signer=signer)
    _usable_key(db, key_id, supervisor)
    statement = _statement(db, ctx, decision="revoked", reason=_reason("revoked", reason),
                           supervisor=supervisor, key_id=key_id, time=_now_text(),
                           nonce=secrets.token_hex(16), revokes=approval.envelope_digest)
    return Prepared(statement, statement_bytes(statement))


def revoke(db: DbSession, *, approval_id: int, supervisor: User, envelope: str,
           password: str | None, reports: ReportService, signer: LogSigner | None) -> Approval:
    # User verification first, then the row locks (store/decide_guard.py).
    confirm_password(db, username=supervisor.username, password_hash=supervisor.password_hash,
                     password=password)
    lock_submission(db, get_approval(db, approval_id).submission_id)
    approval, ctx = _revocable(db, approval_id, reports)
    _check_duties(db, supervisor, ctx.version, ctx.submission, signer=signer)
    _, statement, key, _ = _verified(db, envelope, supervisor)
    if statement["predicate"].get("decision") != "revoked":
        raise BadSignature("a revocation statement has decision 'revoked'")
    _check_fresh(db, ctx, statement, supervisor, key, revokes=approval.envelope_digest)
    return _store(db, ctx, signer=signer, envelope_text=envelope, statement=statement, key=key,
                  supervisor=supervisor, revokes=approval)
