"""Users, sessions, API tokens and login rate limiting."""

from __future__ import annotations

import hashlib
import secrets
from dataclasses import dataclass
from datetime import datetime, timedelta

from argon2.exceptions import InvalidHashError, VerificationError
from sqlalchemy import delete, func, select, update
from sqlalchemy.orm import Session as DbSession

from .db import database_of, writable
from .events import record
from .hashing import BoundedHasher
from .tables import ROLES, ApiToken, LoginAttempt, Session, User, utcnow

HASHER = BoundedHasher()
SESSION_LIFETIME = timedelta(hours=12)
LOGIN_WINDOW = timedelta(minutes=15)
LOGIN_MAX_FAILURES = 10
MIN_PASSWORD_LENGTH = 10
# Verifying against a dummy hash makes unknown usernames cost as much as wrong passwords.
_DUMMY_HASH = HASHER.hash("countersign-timing-equaliser")


class AccountError(ValueError):
    """A request about accounts that cannot be honoured; the message says why."""


class TooManyAttempts(AccountError):
    pass


def token_hash(token: str) -> str:
    return hashlib.sha256(token.encode()).hexdigest()


def new_secret() -> str:
    return secrets.token_urlsafe(32)


def hash_password(password: str) -> str:
    if len(password) < MIN_PASSWORD_LENGTH:
        raise AccountError(f"a password needs at least {MIN_PASSWORD_LENGTH} characters")
    if len(password) > 1024:
        raise AccountError("a password may have at most 1024 characters")
    return HASHER.hash(password)


def create_user(
    db: DbSession, *, username: str, role: str, password: str, display_name: str = "",
    actor: User | None = None,
) -> User:
    if role not in ROLES:
        raise AccountError(f"unknown role {role!r}; choose one of {', '.join(ROLES)}")
    if not username or len(username) > 64 or not username.replace("-", "").replace(
        "_", "").replace(".", "").isalnum():
        raise AccountError("a username has 1-64 letters, digits, '.', '-' or '_'")
    if db.scalar(select(User).where(User.username == username)) is not None:
        raise AccountError(f"the username {username!r} is taken")
    user = User(username=username, role=role, display_name=display_name or username,
                password_hash=hash_password(password))
    db.add(user)
    db.flush()
    record(db, kind="user.created", actor=actor, detail={"user": username, "role": role})
    return user


def authenticate(db: DbSession, *, username: str, password: str) -> User | None:
    """The user for these credentials, or None; raises TooManyAttempts when rate limited.

    The rate limit is read and the password checked (argon2: tens of milliseconds of CPU by
    design) in a read transaction of their own: on SQLite a writing session holds the one
    write lock from its first query, and every other writer would wait for the hash."""
    since = utcnow() - LOGIN_WINDOW
    with database_of(db).session(write=False) as reader:
        failures = reader.scalar(
            select(func.count()).select_from(LoginAttempt)
            .where(LoginAttempt.username == username, LoginAttempt.at >= since)
        ) or 0
        if failures >= LOGIN_MAX_FAILURES:
            raise TooManyAttempts(
                f"too many failed sign-ins for {username!r}; try again in "
                f"{int(LOGIN_WINDOW.total_seconds() // 60)} minutes"
            )
        found = reader.scalar(select(User).where(User.username == username))
        stored_hash = found.password_hash if found else _DUMMY_HASH
        user_id = found.id if found is not None and not found.disabled else None
    try:
        HASHER.verify(stored_hash, password)
        valid = user_id is not None
    except (VerificationError, InvalidHashError):
        valid = False
    user = db.get(User, user_id) if valid and user_id is not None else None
    if user is None or user.password_hash != stored_hash or user.disabled:
        db.add(LoginAttempt(username=username[:64]))
        return None
    if HASHER.check_needs_rehash(user.password_hash):
        user.password_hash = HASHER.hash(password)
    db.execute(delete(LoginAttempt).where(LoginAttempt.username == username))
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
    if row.expires_at < utcnow() or user.disabled:
        return None
    return user, row


def close_session(db: DbSession, cookie: str) -> None:
    db.execute(delete(Session).where(Session.token_hash == token_hash(cookie)))


def create_token(db: DbSession, *, user: User, name: str) -> tuple[ApiToken, str]:
    secret = "cst_" + new_secret()
    token = ApiToken(user_id=user.id, name=name[:100] or "token", token_hash=token_hash(secret))
    db.add(token)
    db.flush()
    record(db, kind="token.created", actor=user, detail={"token": token.id, "name": token.name})
    return token, secret


def token_user(db: DbSession, secret: str) -> User | None:
    # One indexed query (api_tokens.token_hash is unique) for the token and its user.
    found = db.execute(
        select(ApiToken, User).join(User, User.id == ApiToken.user_id)
        .where(ApiToken.token_hash == token_hash(secret))
    ).first()
    if found is None:
        return None
    token, user = found
    if token.revoked or user.disabled:
        return None
    now = utcnow()
    # Recording every use would turn each read into a write; a minute's precision is enough,
    # written in a transaction of its own so that read-only requests stay read-only.
    if token.last_used_at is None or now - token.last_used_at > timedelta(minutes=1):
        with writable(db) as writer:
            writer.execute(update(ApiToken).where(ApiToken.id == token.id)
                           .values(last_used_at=now))
    return user
