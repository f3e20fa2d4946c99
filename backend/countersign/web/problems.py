"""RFC 9457 problem documents for every error the API returns."""

from __future__ import annotations

from typing import Any

from fastapi import FastAPI, HTTPException, Request
from fastapi.exceptions import RequestValidationError
from fastapi.responses import JSONResponse
from sqlalchemy.exc import OperationalError
from sqlalchemy.exc import TimeoutError as SqlTimeout

from ..errors import (
    Conflict,
    DomainError,
    Forbidden,
    Gone,
    Invalid,
    NotFound,
    PreconditionFailed,
    TooMany,
    Unavailable,
    Unprocessable,
)
from ..orders.reader import OrdersReadError
from ..store.accounts import TooManyAttempts
from .strict_body import BodyPolicyError

PROBLEM = "application/problem+json"
TITLES = {400: "Bad request", 401: "Not signed in", 403: "Forbidden", 404: "Not found",
          409: "Conflict", 412: "Precondition failed", 413: "Payload too large",
          415: "Unsupported media type", 422: "Unprocessable content",
          428: "Precondition required", 429: "Too many requests",
          500: "Internal server error", 503: "Service unavailable"}


# Each kind of domain error (countersign.errors) and its status; the most specific kind wins.
STATUS_OF: dict[type[DomainError], int] = {
    Unprocessable: 422, Invalid: 400, Forbidden: 403, NotFound: 404, Conflict: 409,
    Gone: 410, PreconditionFailed: 412, TooMany: 429, Unavailable: 503, DomainError: 400,
}


def status_of(exc: DomainError) -> int:
    """The HTTP status of a domain error: that of the nearest kind in its class's ancestry."""
    for kind in type(exc).__mro__:
        if kind in STATUS_OF:
            return STATUS_OF[kind]
    return 400


def problem(status: int, detail: str, request: Request | None = None, **extra: Any) -> JSONResponse:
    body: dict[str, Any] = {"type": "about:blank", "title": TITLES.get(status, "Error"),
                            "status": status, "detail": detail}
    if request is not None:
        body["instance"] = request.url.path
    body.update(extra)
    headers = {"WWW-Authenticate": "Bearer"} if status == 401 else None
    return JSONResponse(body, status_code=status, media_type=PROBLEM, headers=headers)


def _location(loc: tuple[Any, ...]) -> str:
    path = "$"
    for part in loc[1:] if loc and loc[0] in ("body", "query", "path", "header") else loc:
        path += f"[{part}]" if isinstance(part, int) else f".{part}"
    return path


def install(app: FastAPI) -> None:
    @app.exception_handler(HTTPException)
    async def _http(request: Request, exc: HTTPException) -> JSONResponse:
        response = problem(exc.status_code, str(exc.detail), request)
        # Headers the route chose (Retry-After of a 429) travel with the problem.
        for name, value in (exc.headers or {}).items():
            response.headers[name] = value
        return response

    @app.exception_handler(BodyPolicyError)
    async def _body(request: Request, exc: BodyPolicyError) -> JSONResponse:
        return problem(422, str(exc.detail), request, errors=exc.errors)

    @app.exception_handler(RequestValidationError)
    async def _validation(request: Request, exc: RequestValidationError) -> JSONResponse:
        errors = [{"path": _location(tuple(e.get("loc", ()))), "message": str(e.get("msg"))}
                  for e in exc.errors()[:20]]
        return problem(422, "the request is not valid", request, errors=errors)

    @app.exception_handler(OrdersReadError)
    async def _orders(request: Request, exc: OrdersReadError) -> JSONResponse:
        errors = [{"path": p.path, "message": p.message} for p in exc.problems]
        return problem(422, "the orders cannot be read", request, errors=errors,
                       total_errors=exc.total)

    @app.exception_handler(PreconditionFailed)
    async def _stale(request: Request, exc: PreconditionFailed) -> JSONResponse:
        response = problem(412, str(exc), request, current_revision=exc.current_revision)
        response.headers["ETag"] = f'"{exc.current_revision}"'
        return response

    @app.exception_handler(DomainError)
    async def _domain(request: Request, exc: DomainError) -> JSONResponse:
        response = problem(status_of(exc), str(exc), request)
        retry_after = getattr(exc, "retry_after_s", None)  # e.g. a full password-hash queue
        if isinstance(retry_after, int):
            response.headers["Retry-After"] = str(retry_after)
        return response

    @app.exception_handler(OperationalError)
    @app.exception_handler(SqlTimeout)
    async def _busy(request: Request, exc: Exception) -> JSONResponse:
        # Lock or pool exhaustion under load: the client may retry; nothing was changed.
        response = problem(503, "the database is busy; retry in a moment", request)
        response.headers["Retry-After"] = "1"
        return response

    @app.exception_handler(TooManyAttempts)
    async def _rate(request: Request, exc: TooManyAttempts) -> JSONResponse:
        response = problem(429, str(exc), request)
        response.headers["Retry-After"] = str(exc.retry_after_s)
        return response

