"""Users, API tokens, vehicle profiles and the event log."""

from __future__ import annotations

from datetime import datetime, timedelta
from typing import Annotated, Any, Literal

from fastapi import APIRouter, Query
from pydantic import BaseModel, Field
from sqlalchemy import func, select

from ...errors import Invalid, NotFound
from ...orders.model import Vehicle
from ...store import draft_bursts
from ...store.accounts import (
    AccountError,
    create_token,
    create_user,
    listed_tokens,
    revoke_credentials,
    set_password,
)
from ...store.events import record
from ...store.integrity import event_integrity, log_indexes
from ...store.role_change import GRANTING_ROLES, confirm_grant, confirm_role_change
from ...store.tables import ApiToken, Event, User, VehicleProfile
from ...store.vehicles import refresh_drafts, save_vehicle
from ..deps import (
    ADMINS,
    EVERYONE,
    LOG_READERS,
    CurrentPrincipal,
    Db,
    RowId,
    Services,
    TransactionRoute,
    allow,
)
from .instants import UtcInstant
from .schemas import EventOut, RequestBody, UserOut, VehicleJson

router = APIRouter(prefix="/api", tags=["administration"], route_class=TransactionRoute)


class UserIn(RequestBody):
    username: str = Field(min_length=1, max_length=64)
    display_name: str = Field(default="", max_length=200)
    role: str = Field(max_length=16)
    password: str = Field(min_length=1, max_length=1024)
    # A new supervisor or admin is confirmed with the acting admin's password, entered again.
    admin_password: str | None = Field(default=None, max_length=1024)


class UserPatch(RequestBody):
    role: str | None = Field(default=None, max_length=16)
    disabled: bool | None = None
    password: str | None = Field(default=None, max_length=1024)
    display_name: str | None = Field(default=None, max_length=200)
    # A role change or a password reset is confirmed with the admin's own password, entered
    # again: either can hand someone a supervisor's power.
    admin_password: str | None = Field(default=None, max_length=1024)


class TokenIn(RequestBody):
    name: str = Field(min_length=1, max_length=100)
    scopes: list[Literal["read", "write", "decide"]] = Field(
        default=["read", "write"], min_length=1, max_length=3)
    expires_in_days: int = Field(default=90, ge=1, le=366)
    # Your own password, entered again: needed for a token with the `decide` scope.
    password: str | None = Field(default=None, max_length=1024)


class TokenOut(BaseModel):
    id: int
    name: str
    token: str | None = None
    revoked: bool = False
    scopes: list[str] = Field(default_factory=list)
    expires_at: datetime | None = None


@router.get("/users", operation_id="listUsers", response_model=list[UserOut], **allow(*ADMINS))
def list_users(db: Db) -> list[UserOut]:
    return [UserOut.of(u) for u in db.scalars(select(User).order_by(User.username))]


@router.post("/users", operation_id="createUser", status_code=201, response_model=UserOut,
             **allow(*ADMINS))
def add_user(body: UserIn, principal: CurrentPrincipal, db: Db, services: Services) -> UserOut:
    if body.role in GRANTING_ROLES:
        confirm_grant(db, principal.user, body.admin_password, action=f"creating a {body.role}",
                      undone="no user was created")
    user = create_user(db, username=body.username, role=body.role, password=body.password,
                       display_name=body.display_name, actor=principal.user, signer=services.signer)
    return UserOut.of(user)


@router.patch("/users/{user_id}", operation_id="updateUser", response_model=UserOut,
              **allow(*ADMINS))
def change_user(user_id: RowId, body: UserPatch, principal: CurrentPrincipal, db: Db,
                services: Services) -> UserOut:
    user = db.get(User, user_id)
    if user is None:
        raise NotFound(f"no user {user_id}")
    changes: dict[str, Any] = {}
    role_changes = body.role is not None and body.role != user.role
    # One check for both (argon2 is slow); the reset's words when both are asked.
    if body.password is not None:
        confirm_grant(db, principal.user, body.admin_password, action="a password reset",
                      undone="no password was reset")
    elif role_changes:
        confirm_role_change(db, principal.user, body.admin_password)
    if role_changes:
        changes["previous_role"] = user.role
    if body.role is not None:
        from ...store.tables import ROLES

        if body.role not in ROLES:
            raise AccountError(f"unknown role {body.role!r}; choose one of {', '.join(ROLES)}")
        if user.id == principal.user.id and body.role != "admin":
            raise AccountError("you cannot remove your own admin role")
        user.role = changes["role"] = body.role
    if body.disabled is not None:
        if user.id == principal.user.id and body.disabled:
            raise AccountError("you cannot disable your own account")
        user.disabled = changes["disabled"] = body.disabled
    if body.display_name is not None:
        user.display_name = changes["display_name"] = body.display_name
    if body.password is not None:
        # An admin's reset: every session and API token of that user ends.
        set_password(db, user, body.password, actor=principal.user,
                     signer=services.signer)
        changes["password"] = "reset"
    if body.disabled:
        revoke_credentials(db, user)
    record(db, signer=services.signer, kind="user.updated", actor=principal.user,
           detail={"user": user.username, **changes})
    return UserOut.of(user)


@router.get("/tokens", operation_id="listTokens", response_model=list[TokenOut],
            **allow(*EVERYONE))
def list_tokens(principal: CurrentPrincipal, db: Db) -> list[TokenOut]:
    rows = listed_tokens(db, principal.user)
    return [TokenOut(id=t.id, name=t.name, revoked=t.revoked, scopes=t.scopes.split(),
                     expires_at=t.expires_at) for t in rows]


@router.post("/tokens", operation_id="createToken", status_code=201, response_model=TokenOut,
             **allow(*EVERYONE))
def add_token(body: TokenIn, principal: CurrentPrincipal, db: Db, services: Services) -> TokenOut:
    if "decide" in body.scopes:
        confirm_grant(db, principal.user, body.password,
                      action="a token with the 'decide' scope", undone="no token was created",
                      field="password")
    token, secret = create_token(db, signer=services.signer, user=principal.user, name=body.name,
                                 scopes=tuple(body.scopes),
                                 lifetime=timedelta(days=body.expires_in_days))
    return TokenOut(id=token.id, name=token.name, token=secret, scopes=token.scopes.split(),
                    expires_at=token.expires_at)


@router.delete("/tokens/{token_id}", operation_id="revokeToken", status_code=204,
               **allow(*EVERYONE))
def revoke_token(token_id: RowId, principal: CurrentPrincipal, db: Db, services: Services) -> None:
    token = db.get(ApiToken, token_id)
    if token is None or token.user_id != principal.user.id:
        raise NotFound(f"you have no token {token_id}")
    token.revoked = True
    record(db, kind="token.revoked", actor=principal.user, detail={"token": token_id},
           signer=services.signer)


@router.get("/vehicles", operation_id="listVehicles", response_model=list[VehicleJson],
            **allow(*EVERYONE))
def list_vehicles(db: Db) -> list[dict[str, Any]]:
    return [v.profile for v in db.scalars(select(VehicleProfile).order_by(VehicleProfile.id))]


@router.put("/vehicles/{vehicle_id}", operation_id="putVehicle", response_model=VehicleJson,
            **allow(*ADMINS))
def put_vehicle(vehicle_id: str, body: Vehicle, principal: CurrentPrincipal,
                db: Db, services: Services) -> dict[str, Any]:
    if body.id != vehicle_id:
        raise Invalid(f"the profile's id {body.id!r} differs from {vehicle_id!r}")
    before = db.get(VehicleProfile, vehicle_id)
    previous = dict(before.profile) if before is not None else None
    profile, number = save_vehicle(db, body, principal.user)
    db.flush()
    record(db, signer=services.signer, kind="vehicle.saved", actor=principal.user,
           detail={"vehicle": vehicle_id, "version": number})
    # Drafts that use the vehicle are checked against the new profile from their next read.
    refresh_drafts(db, vehicle_id, previous, principal.user, signer=services.signer)
    return profile


@router.get("/events", operation_id="listEvents", response_model=list[EventOut],
            **allow(*LOG_READERS))
def list_events(
    db: Db,
    services: Services,
    mission: Annotated[str | None, Query(max_length=100)] = None,
    kind: Annotated[str | None, Query(max_length=64, description=(
        "an event kind ('user.updated'), or a family without a dot ('user')"))] = None,
    actor: Annotated[str | None, Query(max_length=64, description="the actor's username; "
                                       "'system' for events without one")] = None,
    target: Annotated[str | None, Query(max_length=200, description=(
        "words the event's target contains ('alice', 'mission survey v2'), any case"))] = None,
    since: Annotated[UtcInstant | None, Query(description="events at or after")] = None,
    until: Annotated[UtcInstant | None, Query(description="events before")] = None,
    order: Annotated[Literal["oldest", "newest"], Query()] = "oldest",
    after: Annotated[int, Query(ge=0, le=2**62, description="oldest first: ids above")] = 0,
    before: Annotated[int | None, Query(ge=1, le=2**62,
                                        description="newest first: ids below")] = None,
    limit: Annotated[int, Query(ge=1, le=1000)] = 100,
) -> list[EventOut]:
    """The event log, filtered and paged by the server (at most `limit` rows a call). Each
    event carries `index`, its entry's index in the transparency log: the number to show."""
    # Editing bursts that ended are listed.
    draft_bursts.flush_quiet_before_reading(db, signer=services.signer)
    query = select(Event)
    if order == "newest":
        query = query.order_by(Event.id.desc())
        if before is not None:
            query = query.where(Event.id < before)
    else:
        query = query.where(Event.id > after).order_by(Event.id)
    if mission:
        query = query.where(Event.mission_id == mission)
    if kind:
        query = query.where(Event.kind == kind if "." in kind else Event.kind.like(
            _like_prefix(kind) + ".%", escape="\\"))
    if actor == "system":
        query = query.where(Event.actor_id.is_(None))
    elif actor:
        query = query.where(Event.actor_id.in_(
            select(User.id).where(User.username == actor)))
    if target:
        query = query.where(func.lower(Event.target).like(
            "%" + _like_prefix(target.lower()) + "%", escape="\\"))
    if since is not None:
        query = query.where(Event.at >= since)
    if until is not None:
        query = query.where(Event.at < until)
    names: dict[int, str] = {}
    events = list(db.scalars(query.limit(limit)))
    for event in events:
        if event.actor_id is not None and event.actor_id not in names:
            user = db.get(User, event.actor_id)
            names[event.actor_id] = user.username if user else f"#{event.actor_id}"
    # The log is the source of truth: a row edited behind the app's back is reported.
    integrity = event_integrity(db, events, names)
    indexes = log_indexes(db, [e.id for e in events])
    return [EventOut.of(e, names.get(e.actor_id) if e.actor_id is not None else None,
                        integrity[e.id], indexes.get(e.id)) for e in events]


def _like_prefix(text: str) -> str:
    return text.replace("\\", "\\\\").replace("%", "\\%").replace("_", "\\_")

