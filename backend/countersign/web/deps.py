"""Request dependencies: database session, the signed-in principal, role guards, CSRF."""

from __future__ import annotations

import hmac
from collections.abc import Iterable, Iterator
from dataclasses import dataclass
from typing import Annotated, Any

from fastapi import Depends, HTTPException, Path, Request
from sqlalchemy.orm import Session as DbSession

from ..store.accounts import session_user, token_user
from ..store.db import Database
from ..store.tables import User

SESSION_COOKIE = "countersign_session"
CSRF_HEADER = "X-CSRF-Token"
SAFE_METHODS = {"GET", "HEAD", "OPTIONS"}

EVERYONE = ("operator", "supervisor", "auditor", "admin")
OPERATORS = ("operator",)
ADMINS = ("admin",)
LOG_READERS = ("supervisor", "auditor", "admin")


# POST routes that only compute (their body is input, not a change): no write lock needed.
READ_ONLY_POSTS = frozenset({"/api/validate"})


def get_db(request: Request) -> Iterator[DbSession]:
    database: Database = request.app.state.database
    write = request.method not in SAFE_METHODS and request.url.path not in READ_ONLY_POSTS
    with database.session(write=write) as session:
        yield session


# "function" scope commits before the response is sent: a client that sees 200 can rely on it.
# Row ids in URLs: bounded so that no database is asked for a number it cannot store.
RowId = Annotated[int, Path(ge=1, le=2**31 - 1)]

Db = Annotated[DbSession, Depends(get_db, scope="function")]


@dataclass(frozen=True)
class Principal:
    user: User
    via: str  # "cookie" or "token"
    csrf_token: str | None


def current_principal(request: Request, db: Db) -> Principal:
    header = request.headers.get("Authorization", "")
    if header.lower().startswith("bearer "):
        user = token_user(db, header[7:].strip())
        if user is None:
            raise HTTPException(401, "the API token is unknown, revoked or its user is disabled")
        return Principal(user, "token", None)
    cookie = request.cookies.get(SESSION_COOKIE)
    found = session_user(db, cookie) if cookie else None
    if found is None:
        raise HTTPException(401, "sign in first")
    user, session = found
    if request.method not in SAFE_METHODS:
        sent = request.headers.get(CSRF_HEADER, "")
        if not hmac.compare_digest(sent.encode(), session.csrf_token.encode()):
            raise HTTPException(403, f"missing or wrong {CSRF_HEADER} header")
    return Principal(user, "cookie", session.csrf_token)


CurrentPrincipal = Annotated[Principal, Depends(current_principal)]


class RoleGuard:
    def __init__(self, roles: Iterable[str]) -> None:
        self.roles = tuple(roles)

    def __call__(self, principal: CurrentPrincipal) -> Principal:
        if principal.user.role not in self.roles:
            raise HTTPException(
                403, f"the {principal.user.role} role may not do this "
                f"(allowed: {', '.join(self.roles)})"
            )
        return principal


def allow(*roles: str) -> dict[str, Any]:
    """Route keyword arguments: the role check, and the roles recorded in the OpenAPI document
    (`x-roles`) so that tests and clients read the same declaration the server enforces."""
    return {"dependencies": [Depends(RoleGuard(roles))],
            "openapi_extra": {"x-roles": list(roles)}}
