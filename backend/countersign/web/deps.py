"""Request dependencies: database session, the app's services, the signed-in principal, role
guards, CSRF."""

from __future__ import annotations

import functools
import hmac
import inspect
from collections.abc import Callable, Coroutine, Iterable, Iterator
from dataclasses import dataclass
from typing import Annotated, Any

from fastapi import Depends, HTTPException, Path, Request, Response
from fastapi.routing import APIRoute
from sqlalchemy.orm import Session as DbSession

from ..services.app import AppServices
from ..store.accounts import session_user, token_lookup
from ..store.db import Database, writes
from ..store.tables import User
from .strict_body import strict_handler
from .token_scopes import token_refusal

SESSION_COOKIE = "countersign_session"
CSRF_HEADER = "X-CSRF-Token"
SAFE_METHODS = {"GET", "HEAD", "OPTIONS"}

EVERYONE = ("operator", "supervisor", "auditor", "admin")
OPERATORS = ("operator",)
ADMINS = ("admin",)
LOG_READERS = ("supervisor", "auditor", "admin")


def computes_only() -> None:
    """Declares a POST route that only computes (its body is input, not a change): its session
    is opened without the write lock. CSRF and token scopes still treat it as a POST."""


def computing(route: dict[str, Any]) -> dict[str, Any]:
    """Route keyword arguments (allow(...)'s) plus the computes_only declaration."""
    return {**route, "dependencies": [*route.get("dependencies", ()), Depends(computes_only)]}


def opens_for_writing(request: Request) -> bool:
    """Whether the request's session takes the write lock: a write method on a route that does
    not declare computes_only (the route is matched before its dependencies run)."""
    if request.method in SAFE_METHODS:
        return False
    declared = getattr(request.scope.get("route"), "dependencies", ())
    return not any(d.dependency is computes_only for d in declared)


def get_db(request: Request) -> Iterator[DbSession]:
    """The request's session. Its transaction begins at the first query and, for synchronous
    routes, is committed by TransactionRoute in the worker thread that ran the route."""
    database: Database = request.app.state.database
    with database.open(write=opens_for_writing(request)) as session:
        yield session


class TransactionRoute(APIRoute):
    """Routes that commit (or roll back) their request's transaction in the same worker thread
    that ran them, before returning.

    FastAPI runs each synchronous dependency, the route and each dependency's exit in separate
    trips to the thread pool. A write transaction left open until get_db's exit would hold the
    write lock (SQLite's, or PostgreSQL's row and advisory locks) while its request waits for a
    free thread; when every thread is taken by writers waiting for that lock, nothing moves
    until the waiters time out (the 30 s writes and 503 "busy" answers seen under load). Committing
    here makes each write transaction one uninterrupted stretch of work in one thread."""

    def __init__(self, path: str, endpoint: Callable[..., Any], **kwargs: Any) -> None:
        if not inspect.iscoroutinefunction(endpoint) and not inspect.isgeneratorfunction(
                endpoint):
            endpoint = _committing(endpoint)
        super().__init__(path, endpoint, **kwargs)

    # JSON bodies are parsed under the one JSON policy (see strict_body).
    def get_route_handler(self) -> Callable[[Request], Coroutine[Any, Any, Response]]:
        return strict_handler(super().get_route_handler())


def in_one_transaction(db: DbSession, action: Callable[..., Any], *args: Any) -> Any:
    """Run `action(*args)` and commit `db` (roll back on error), in the calling thread."""
    try:
        result = action(*args)
    except BaseException:
        db.rollback()
        raise
    db.commit()
    return result


def _committing(endpoint: Callable[..., Any]) -> Callable[..., Any]:
    signature = inspect.signature(endpoint, eval_str=True)

    @functools.wraps(endpoint)
    def run(*args: Any, **kwargs: Any) -> Any:
        sessions = [value for value in kwargs.values() if isinstance(value, DbSession)]
        try:
            result = endpoint(*args, **kwargs)
        except BaseException:
            for session in sessions:
                session.rollback()
            raise
        for session in sessions:
            session.commit()
        return result

    run.__signature__ = signature  # type: ignore[attr-defined]
    return run


# "function" scope commits before the response is sent: a client that sees 200 can rely on it.
# Row ids and numbers in URLs: bounded so that no database is asked for a number it cannot store.
MAX_ROW_ID = 2**31 - 1
RowId = Annotated[int, Path(ge=1, le=MAX_ROW_ID)]

Db = Annotated[DbSession, Depends(get_db, scope="function")]


def get_services(request: Request) -> AppServices:
    """The app's services (services/app.py), built once by the app factory."""
    services: AppServices = request.app.state.services
    return services


Services = Annotated[AppServices, Depends(get_services)]


@dataclass(frozen=True)
class Principal:
    user: User
    via: str  # "cookie" or "token"
    csrf_token: str | None


def current_principal(request: Request, db: Db) -> Principal:
    if writes(db):
        # Who is asking is read in a short transaction of its own, so that a writing request
        # takes its write lock only when its route starts writing (see TransactionRoute).
        database: Database = request.app.state.database
        with database.session(write=False) as reader:
            return _principal(request, reader)
    return _principal(request, db)


def _principal(request: Request, db: DbSession) -> Principal:
    header = request.headers.get("Authorization", "")
    if header.lower().startswith("bearer "):
        live = token_lookup(db, header[7:].strip())
        if live is None:
            raise HTTPException(401, "the API token is unknown, revoked or expired, or its "
                                     "user is disabled")
        user, token = live
        # scopes, and no minting of tokens by tokens (see token_scopes).
        refusal = token_refusal(request, token.scopes)
        if refusal is not None:
            raise HTTPException(403, refusal)
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
