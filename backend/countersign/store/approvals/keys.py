"""Supervisors' signing keys: registration, revocation and which key may sign."""

from __future__ import annotations

from sqlalchemy import func, select
from sqlalchemy.orm import Session as DbSession

from ...approvals import dsse
from ...approvals.dsse import SignatureError
from ...approvals.signer import LogSigner
from ...limits import MAX_REASON
from ..decide_guard import (
    logged_key_revocation,
)
from ..events import record
from ..logged_roles import decision_refusal_from_log
from ..login_throttle import check_password
from ..missions import Conflict, NotFound
from ..tables import (
    SigningKey,
    User,
    utcnow,
)
from .common import BadKey, Refused, Stale

# A supervisor rotates keys, never needs many at once: bound the unrevoked ones, so that the
# key list (which every reader gets whole: the audit verifies against every key) cannot grow
# with one person's registrations. Revoking one makes room.
MAX_LIVE_KEYS = 10


def _confirm_password(db: DbSession, user: User, password: str) -> None:
    # The one password throttle (login_throttle): called before anything is read or written
    # here, since it ends the transaction the request had begun.
    if not check_password(db, username=user.username, stored_hash=user.password_hash,
                          password=password):
        raise Refused("the password confirmation is wrong")


def register_key(db: DbSession, *, user: User, public_key: str, name: str,
                 password: str, signer: LogSigner | None) -> SigningKey:
    if user.role != "supervisor":
        raise Refused("only supervisors register signing keys")
    # The row's role is not evidence (a database writer can set it): the log's is.
    mismatch = decision_refusal_from_log(db, user, signer=signer)
    if mismatch is not None:
        raise Refused(mismatch)
    _confirm_password(db, user, password)
    try:
        kid = dsse.key_id(public_key)
    except SignatureError as exc:
        raise BadKey(str(exc)) from None
    if db.get(SigningKey, kid) is not None:
        raise Conflict(f"the key {kid} is registered already")
    live = db.scalar(select(func.count()).select_from(SigningKey).where(
        SigningKey.user_id == user.id, SigningKey.revoked_at.is_(None)))
    if live is not None and live >= MAX_LIVE_KEYS:
        raise Conflict(f"you have {live} signing keys that are not revoked (at most "
                       f"{MAX_LIVE_KEYS}); revoke one you no longer use first")
    key = SigningKey(id=kid, user_id=user.id, name=name[:100], public_key=public_key)
    db.add(key)
    db.flush()
    record(db, signer=signer, kind="key.registered", actor=user, detail={
        "key_id": kid, "public_key": public_key, "user": user.username, "name": key.name})
    return key


def revoke_key(db: DbSession, *, user: User, key_id: str, password: str,
               reason: str, signer: LogSigner | None) -> SigningKey:
    _confirm_password(db, user, password)
    key = db.get(SigningKey, key_id)
    if key is None:
        raise NotFound(f"no signing key {key_id!r}")
    if key.user_id != user.id and user.role != "admin":
        raise Refused("only the key's owner or an admin can revoke it")
    if key.revoked_at is not None:
        raise Stale(f"the key {key_id} is revoked already")
    key.revoked_at, key.revoke_reason = utcnow(), reason[:MAX_REASON]
    record(db, kind="key.revoked", actor=user, detail={"key_id": key_id, "reason": reason},
           signer=signer)
    return key


def key_status(db: DbSession, key: SigningKey) -> str:
    """From the log; a row that claims otherwise is reported by integrity."""
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
    # The log, not the row, says whether a key is revoked (a writer who
    # sets revoked_at back to NULL must not make the key usable again).
    logged = logged_key_revocation(db, key_id)
    if logged is not None:
        raise Refused(f"the key {key_id} was revoked (log entry {logged}); the signing_keys "
                      "row disagrees with the log")
    return key
