"""Sign-in, sign-out and who am I."""

from __future__ import annotations

from fastapi import APIRouter, HTTPException, Request, Response
from pydantic import BaseModel, Field

from ...store.accounts import authenticate, change_password, close_session, open_session
from ...store.tables import User
from ..deps import EVERYONE, SESSION_COOKIE, CurrentPrincipal, Db, Services, TransactionRoute, allow
from ..viewer_tickets import Credential
from .schemas import RequestBody, UserOut

router = APIRouter(prefix="/api/auth", tags=["auth"], route_class=TransactionRoute)


class LoginRequest(RequestBody):
    username: str = Field(min_length=1, max_length=64)
    password: str = Field(min_length=1, max_length=1024)


class SessionOut(BaseModel):
    user: UserOut
    csrf_token: str | None


@router.post("/login", operation_id="login", response_model=SessionOut,
             openapi_extra={"x-roles": ["anonymous"]})
def login(body: LoginRequest, request: Request, response: Response, db: Db) -> SessionOut:
    address = request.client.host if request.client else None
    user = authenticate(db, username=body.username, password=body.password, address=address)
    if user is None:
        raise HTTPException(401, "wrong username or password")
    session = open_session(db, user)
    response.set_cookie(SESSION_COOKIE, session.cookie, httponly=True, samesite="strict",
                        secure=_secure(request), path="/", expires=session.expires_at)
    return SessionOut(user=UserOut.of(user), csrf_token=session.csrf_token)


@router.post("/logout", operation_id="logout", status_code=204, **allow(*EVERYONE))
def logout(request: Request, response: Response, principal: CurrentPrincipal, db: Db) -> None:
    cookie = request.cookies.get(SESSION_COOKIE)
    if cookie:
        close_session(db, cookie)
        # The session's rehearsal viewers stop relaying now (other server processes notice
        # within viewer_tickets.SESSION_CHECK_S).
        request.app.state.rehearsals.viewers.credential_ended(Credential(cookie, None))
    # The same attributes as at sign-in, so that browsers treat it as the same cookie.
    response.delete_cookie(SESSION_COOKIE, path="/", httponly=True, samesite="strict",
                           secure=_secure(request))


def _secure(request: Request) -> bool:
    return request.url.scheme == "https" or bool(request.app.state.settings.secure_cookies)


@router.get("/me", operation_id="whoAmI", response_model=SessionOut, **allow(*EVERYONE))
def me(principal: CurrentPrincipal) -> SessionOut:
    return SessionOut(user=UserOut.of(principal.user), csrf_token=principal.csrf_token)


class PasswordChange(RequestBody):
    current_password: str = Field(min_length=1, max_length=1024)
    new_password: str = Field(min_length=1, max_length=1024)


@router.post("/password", operation_id="changePassword", status_code=204, **allow(*EVERYONE))
def password(body: PasswordChange, request: Request, principal: CurrentPrincipal,
             db: Db, services: Services) -> None:
    """Change your own password. Every other session and every API token of yours ends; the
    browser session that asked stays signed in."""
    user = db.get_one(User, principal.user.id)
    keep = request.cookies.get(SESSION_COOKIE) if principal.via == "cookie" else None
    change_password(db, user, current=body.current_password, new=body.new_password,
                    keep_session=keep, signer=services.signer)
