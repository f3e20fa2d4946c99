"""Users, sessions, API tokens and login rate limiting."""

from __future__ import annotations

import hashlib
import re
import secrets
from dataclasses import dataclass
from datetime import datetime, timedelta

from sqlalchemy import case, delete, func, or_, select, update
from sqlalchemy.orm import Session as DbSession

from ..approvals.signer import LogSigner
from ..errors import Conflict, Invalid, TooMany
from . import login_throttle
from .db import database_of, writable
from .events import record
from .hashing import HASHER, HashingBusy  # noqa: F401  (HashingBusy: raised by sign-in)
from .password_policy import password_problem
from .tables import ROLES, ApiToken, Session, User, utcnow

SESSION_LIFETIME = timedelta(hours=12)
SESSION_IDLE = timedelta(minutes=30)
# Verifying against a dummy hash makes unknown usernames cost as much as wrong passwords. It is
# a hash of a random password nobody kept, with HASHER's parameters (a test holds them equal):
# written here rather than made at import, which cost every server and command-line process a
# full-strength hash (~0.3 s of CPU) before it did anything.
_DUMMY_HASH = ("$argon2id$v=19$m=65536,t=3,p=4$xopFIMIyAe3lD8hV8AbGJg"
               "$H68E8icUmwot+fWFAHtwapgT+7b0krBwngjiHu6vnn4")


class AccountError(Invalid, ValueError):
    """A request about accounts that cannot be honoured; the message says why."""


class TooManyAttempts(TooMany, AccountError):
    def __init__(self, message: str, retry_after_s: int = 60) -> None:
        super().__init__(message)
        self.retry_after_s = retry_after_s


def username_of(db: DbSession, user_id: int, cache: dict[int, str] | None = None) -> str:
    """The user's name for display, `#id` for a row that is gone; `cache` spares a listing one
    lookup per repeated author."""
    if cache is not None and user_id in cache:
        return cache[user_id]
    user = db.get(User, user_id)
    name = user.username if user else f"#{user_id}"
    if cache is not None:
        cache[user_id] = name
    return name


USERNAME = re.compile(r"[A-Za-z0-9._-]{1,64}")


def token_hash(token: str) -> str:
    return hashlib.sha256(token.encode()).hexdigest()


def new_secret() -> str:
    return secrets.token_urlsafe(32)


def hash_password(password: str, *, username: str = "", display_name: str = "") -> str:
    problem = password_problem(password, username=username, display_name=display_name)
    if problem is not None:
        raise AccountError(problem)
    return HASHER.hash(password)


def create_user(
    db: DbSession, *, username: str, role: str, password: str, display_name: str = "",
    actor: User | None = None, signer: LogSigner | None,
) -> User:
    if role not in ROLES:
        raise AccountError(f"unknown role {role!r}; choose one of {', '.join(ROLES)}")
    # ASCII only, and unique whatever the case: a look-alike ('ａdmin', 'ADMIN') of another
    # account would read as that person in the log and on approvals.
    if not USERNAME.fullmatch(username):
        raise AccountError("a username has 1-64 ASCII letters, digits, '.', '-' or '_'")
    # Hashed before the first query: a write session's first query takes the write lock, and
    # argon2's tens of milliseconds (more on a loaded machine) would hold every other writer.
    password_hash = hash_password(password, username=username, display_name=display_name)
    taken = db.scalar(select(User.username).where(func.lower(User.username)
                                                   == username.lower()))
    if taken is not None:
        raise AccountError(f"the username {username!r} is taken"
                           + ("" if taken == username else f" (as {taken!r})"))
    user = User(username=username, role=role, display_name=display_name or username,
                password_hash=password_hash)
    db.add(user)
    db.flush()
    record(db, kind="user.created", actor=actor, detail={"user": username, "role": role},
           signer=signer)
    return user


def authenticate(db: DbSession, *, username: str, password: str,
                 address: str | None = None) -> User | None:
    """The user for these credentials, or None; raises TooManyAttempts when throttled.

    The check goes through the one password throttle (login_throttle.check_password): the
    attempt is recorded and counted before the hash (argon2: tens of milliseconds of CPU by
    design) is checked, outside any write transaction. A full hashing queue refuses first
    (HashingBusy), before the attempt is counted."""
    with database_of(db).session(write=False) as reader:
        found = reader.scalar(select(User).where(User.username == username))
        stored_hash = found.password_hash if found else _DUMMY_HASH
        user_id = found.id if found is not None and not found.disabled else None
    try:
        valid = login_throttle.check_password(db, username=username, stored_hash=stored_hash,
                                              password=password, address=address)
    except login_throttle.Throttled as exc:
        raise TooManyAttempts(str(exc), exc.retry_after_s) from None
    user = db.get(User, user_id) if valid and user_id is not None else None
    if user is None or user.password_hash != stored_hash or user.disabled:
        return None
    if HASHER.check_needs_rehash(user.password_hash):
        user.password_hash = HASHER.hash(password)
    return user


@dataclass(frozen=True)
class NewSession:
    cookie: str
    csrf_token: str
    expires_at: datetime


def open_session(db: DbSession, user: User) -> NewSession:
    cookie, csrf = new_secret(), new_secret()
    expires = utcnow() + SESSION_LIFETIME
    db.add(Session(token_hash=token_hash(cookie), user_id=user.id, csrf_token=csrf,
                   expires_at=expires))
    # Opportunistic clean-up keeps the table small without a background job.
    db.execute(delete(Session).where(Session.expires_at < utcnow()))
    return NewSession(cookie, csrf, expires)


def session_user(db: DbSession, cookie: str) -> tuple[User, Session] | None:
    found = db.execute(
        select(Session, User).join(User, User.id == Session.user_id)
        .where(Session.token_hash == token_hash(cookie))
    ).first()
    if found is None:
        return None
    row, user = found
    now = utcnow()
    seen = row.last_seen_at or row.created_at
    # Absolute timeout (expires_at, 12 h from sign-in) and idle timeout (30 min unused).
    if row.expires_at < now or now - seen > SESSION_IDLE or user.disabled:
        return None
    if now - seen > timedelta(minutes=1):  # a minute's precision: reads stay mostly reads
        with writable(db) as writer:
            writer.execute(update(Session).where(Session.token_hash == row.token_hash)
                           .values(last_seen_at=now))
    return user, row


def close_session(db: DbSession, cookie: str) -> None:
    db.execute(delete(Session).where(Session.token_hash == token_hash(cookie)))


SCOPES = ("read", "write", "decide")
# A token's default life; the longest one may ask for (tokens never expired).
TOKEN_LIFETIME = timedelta(days=90)
MAX_TOKEN_LIFETIME = timedelta(days=366)
# Anyone signed in may make tokens (an auditor too): bound how many are alive at once, and the
# list (live ones first, then the latest ended), so that neither grows with one person's clicks.
MAX_LIVE_TOKENS = 50
MAX_LISTED_TOKENS = 200


def create_token(db: DbSession, *, user: User, name: str,
                 scopes: tuple[str, ...] = SCOPES,
                 lifetime: timedelta | None = TOKEN_LIFETIME,
                 signer: LogSigner | None) -> tuple[ApiToken, str]:
    unknown = sorted(set(scopes) - set(SCOPES))
    if unknown or not scopes:
        raise AccountError(f"scopes are some of {', '.join(SCOPES)}; not {unknown or 'none'}")
    if lifetime is not None and not timedelta(0) < lifetime <= MAX_TOKEN_LIFETIME:
        raise AccountError(f"a token lives at most {MAX_TOKEN_LIFETIME.days} days")
    live = db.scalar(select(func.count()).select_from(ApiToken).where(
        ApiToken.user_id == user.id, ApiToken.revoked.is_(False),
        or_(ApiToken.expires_at.is_(None), ApiToken.expires_at > utcnow())))
    if live is not None and live >= MAX_LIVE_TOKENS:
        raise Conflict(f"you have {live} live API tokens (at most {MAX_LIVE_TOKENS}); revoke "
                       "one you no longer use first")
    secret = "cst_" + new_secret()
    token = ApiToken(user_id=user.id, name=name[:100] or "token", token_hash=token_hash(secret),
                     scopes=" ".join(s for s in SCOPES if s in scopes),
                     expires_at=utcnow() + lifetime if lifetime is not None else None)
    db.add(token)
    db.flush()
    record(db, signer=signer, kind="token.created", actor=user,
           detail={"token": token.id, "name": token.name, "scopes": token.scopes})
    return token, secret


def listed_tokens(db: DbSession, user: User) -> list[ApiToken]:
    """The user's tokens, oldest first: every live one and the latest ended ones, at most
    MAX_LISTED_TOKENS in all."""
    ended = case((ApiToken.revoked.is_(True), 1), (ApiToken.expires_at <= utcnow(), 1), else_=0)
    rows = db.scalars(select(ApiToken).where(ApiToken.user_id == user.id)
                      .order_by(ended, ApiToken.id.desc()).limit(MAX_LISTED_TOKENS))
    return sorted(rows, key=lambda token: token.id)


def token_user(db: DbSession, secret: str) -> User | None:
    found = token_lookup(db, secret)
    return found[0] if found else None


def token_lookup(db: DbSession, secret: str) -> tuple[User, ApiToken] | None:
    """The live token for this secret and its user: not revoked, not expired, user enabled."""
    # One indexed query (api_tokens.token_hash is unique) for the token and its user.
    found = db.execute(
        select(ApiToken, User).join(User, User.id == ApiToken.user_id)
        .where(ApiToken.token_hash == token_hash(secret))
    ).first()
    if found is None:
        return None
    token, user = found
    now = utcnow()
    if token.revoked or user.disabled or (token.expires_at is not None
                                          and token.expires_at <= now):
        return None
    # Recording every use would turn each read into a write; a minute's precision is enough,
    # written in a transaction of its own so that read-only requests stay read-only.
    if token.last_used_at is None or now - token.last_used_at > timedelta(minutes=1):
        with writable(db) as writer:
            writer.execute(update(ApiToken).where(ApiToken.id == token.id)
                           .values(last_used_at=now))
    return user, token


def revoke_credentials(db: DbSession, user: User, *, keep_session: str | None = None) -> None:
    """End every session and revoke every API token of `user` (after a password change or
    reset, or when the account is disabled); `keep_session` is a cookie left signed in."""
    query = delete(Session).where(Session.user_id == user.id)
    if keep_session is not None:
        query = query.where(Session.token_hash != token_hash(keep_session))
    db.execute(query)
    db.execute(update(ApiToken).where(ApiToken.user_id == user.id, ApiToken.revoked.is_(False))
               .values(revoked=True))


def change_password(db: DbSession, user: User, *, current: str, new: str,
                    keep_session: str | None = None, signer: LogSigner | None) -> None:
    """The user's own change: the current password is checked first."""
    if not login_throttle.check_password(db, username=user.username,
                                         stored_hash=user.password_hash, password=current):
        raise AccountError("the current password is wrong")
    set_password(db, user, new, actor=user, keep_session=keep_session, signer=signer)


def set_password(db: DbSession, user: User, new: str, *, actor: User,
                 keep_session: str | None = None, signer: LogSigner | None) -> None:
    """Set a password (own change or an admin's reset); every other credential ends."""
    user.password_hash = hash_password(new, username=user.username,
                                       display_name=user.display_name)
    revoke_credentials(db, user, keep_session=keep_session)
    record(db, signer=signer, kind="user.password_changed", actor=actor,
           detail={"user": user.username, "by": "self" if actor.id == user.id else "admin"})
