"""Rehearsals: start one in viser, steer it, stop it into a stored record; viser's client and
websocket through the app (`/rehearsal/{id}/`).

Who may do what: operators and supervisors rehearse; a live rehearsal (its status, outcome and
fault controls, its viewer and websocket) belongs to the person who started it and nobody else
(other people's ids answer 404, as unknown ones do). Stored records are read by every role, and
auditors replay them offline."""

from __future__ import annotations

import hmac
import logging
from dataclasses import dataclass
from datetime import datetime
from typing import Annotated, Any, Literal
from urllib.parse import urlsplit

import anyio
from fastapi import APIRouter, Path, Query, Request, WebSocket
from fastapi.concurrency import run_in_threadpool
from fastapi.responses import RedirectResponse, Response
from pydantic import BaseModel, Field, StringConstraints
from sqlalchemy.orm import Session as DbSession

from ...errors import DomainError, Unprocessable
from ...orders.model import Chart, Orders
from ...orders.reader import orders_from_data
from ...store import rehearsals as records
from ...store.accounts import session_user, token_user
from ...store.db import Database
from ...store.events import record
from ...store.missions import Conflict, NotFound, get_mission, get_version
from ...store.tables import User
from .. import problems
from ..deps import EVERYONE, SESSION_COOKIE, CurrentPrincipal, Db, Services, TransactionRoute, allow
from ..rehearsal_hub import Live, RehearsalHub
from ..viewer_tickets import SESSION_CHECK_S, Credential, SocketLimit, Ticket
from ..viser_proxy import (
    REPLAY_CSP,
    ProxyStats,
    client_csp,
    client_index,
    open_upstream,
    relay,
)
from .rehearsal_schemas import RehearsalRecordJson, RehearsalStatusJson
from .schemas import RequestBody

router = APIRouter(prefix="/api", tags=["rehearsals"], route_class=TransactionRoute)
viewer = APIRouter(tags=["rehearsals"])
log = logging.getLogger("countersign.rehearsal")

REHEARSERS = ("operator", "supervisor")
RehearsalId = Annotated[str, Path(min_length=1, max_length=64, pattern=r"^[A-Za-z0-9_-]+$")]
TicketText = Annotated[str, Path(min_length=20, max_length=100, pattern=r"^[A-Za-z0-9_-]+$")]
RecordDigest = Annotated[str, Path(pattern=r"^sha256:[0-9a-f]{64}$")]
# `VEHICLE:` before a fault names one member of a team (without it: every member).
FaultName = Annotated[str, Field(min_length=1, max_length=110,
                                 pattern=r"^([A-Za-z0-9_.-]{1,64}:)?[a-z][a-z0-9_]*$")]
VehicleName = Annotated[str, StringConstraints(min_length=1, max_length=64,
                                               pattern=r"^[A-Za-z0-9_.-]+$")]
PathNumber = Annotated[int, Field(ge=1, le=2**62)]
FaultSpecText = Annotated[str, Field(
    min_length=1, max_length=210,
    pattern=r"^([A-Za-z0-9_.-]{1,64}:)?[a-z][a-z0-9_]*(@[A-Za-z0-9_.:-]{1,100})?$")]




class RehearsalIn(RequestBody):
    source: Literal["manual", "replay", "tour", "simulate"] = "manual"
    seed: int = Field(default=0, ge=0, le=2**31 - 1)
    path_index: int | None = Field(default=None, ge=1, le=2**62,
                                   description="the traversal path to replay (source replay), "
                                   "counted from 1 as in /paths")
    faults: list[FaultSpecText] = Field(default_factory=list, max_length=8,
                                        description="fault, fault@seconds or fault@goal")
    speed: float | None = Field(default=None, ge=0.1, le=100_000,
                                description="simulated seconds per wall second; omitted: the "
                                "auto pace (each goal's plan in about three seconds)")
    version: int | None = Field(default=None, ge=1, le=2**31 - 1,
                                description="the version to rehearse; omitted: the draft")
    member_paths: dict[VehicleName, PathNumber] = Field(
        default_factory=dict, max_length=8,
        description="a team's orders: members that replay one path of their own orders "
        "(numbered as their /paths), by vehicle; the others follow `source`")


class OutcomeIn(RequestBody):
    outcome: Literal["succeed", "fail", "violate"]


class FaultIn(RequestBody):
    fault: FaultName


class RehearsalOut(BaseModel):
    id: str
    mission: str
    version: int | None
    orders_digest: str
    source: str
    viewer: str
    status: RehearsalStatusJson


class RecordOut(BaseModel):
    digest: str
    mission: str
    version: int | None
    orders_digest: str
    source: str
    owner: str | None
    created_at: datetime
    replay_digest: str
    replay: str


class RecordDetail(RecordOut):
    record: RehearsalRecordJson


def hub_of(request: Request | WebSocket) -> RehearsalHub:
    hub: RehearsalHub = request.app.state.rehearsals
    return hub


def _out(live: Live) -> RehearsalOut:
    r = live.rehearsal
    return RehearsalOut(id=r.id, mission=live.mission_id, version=live.version,
                        orders_digest=r.orders_digest, source=live.source,
                        viewer=f"/rehearsal/{r.id}/", status=r.status())


def _to_rehearse(db: DbSession, mission_id: str, version: int | None
                 ) -> tuple[Orders, str, list[Chart]]:
    """The orders (the draft, or one version), their stored digest, and the registry's charts
    in use, drawn in the scene as the plan view draws them (the orders stay as stored)."""
    from ...store.charts import charts_in
    from ...verify.charts import mission_box

    mission = get_mission(db, mission_id)
    if version is not None:
        stored = get_version(db, mission_id, version)
        data, digest = stored.orders, stored.digest
    else:
        data, digest = mission.draft, mission.draft_digest
    orders = orders_from_data(data)
    region = mission_box(orders)
    return orders, digest, list(charts_in(db, region)) if region is not None else []


@router.post("/missions/{mission_id}/rehearsals", operation_id="startRehearsal",
             status_code=201, response_model=RehearsalOut, **allow(*REHEARSERS))
def start_rehearsal(mission_id: str, body: RehearsalIn, request: Request,
                    principal: CurrentPrincipal, db: Db, services: Services) -> RehearsalOut:
    """Start a rehearsal of the draft or of one version; watch it at `viewer`."""
    # Read in a session of its own, and `db` first touched for the event once the rehearsal
    # runs: starting one takes a second or more, and other writers must not wait for it.
    with services.database.session(write=False) as reader:
        orders, digest, charts = _to_rehearse(reader, mission_id, body.version)
    # A team's orders rehearse every member in one scene (rehearse/team_rehearsal.py), with
    # outcomes from each member's simulation: other sources are refused below (422).
    from ...rehearse.manager import RehearsalOptions

    if body.member_paths and orders.team is None:
        raise Unprocessable("the rehearsal cannot start: member paths are for a team's orders; "
                            "these are one vehicle's (give path_index)")
    options = RehearsalOptions(source=body.source, seed=body.seed, path_index=body.path_index,
                               faults=tuple(body.faults), speed=body.speed)
    try:
        live = hub_of(request).start(orders, user_id=principal.user.id, mission_id=mission_id,
                                     version=body.version, options=options, charts=charts,
                                     paths=body.member_paths)
    except ValueError as exc:
        raise Unprocessable(f"the rehearsal cannot start: {exc}") from None
    if live.rehearsal.orders_digest != digest:
        log.warning("rehearsal %s digests %s, stored %s", live.rehearsal.id,
                    live.rehearsal.orders_digest, digest)
    record(db, kind="rehearsal.started", actor=principal.user, mission_id=mission_id,
           after=live.rehearsal.orders_digest, detail={
               "rehearsal": live.rehearsal.id, "version": body.version, "source": body.source,
               "seed": body.seed, "path_index": body.path_index, "faults": body.faults,
               **({"member_paths": body.member_paths} if body.member_paths else {})},
           signer=services.signer)
    return _out(live)


@router.get("/rehearsals/{rehearsal_id}", operation_id="getRehearsal",
            response_model=RehearsalOut, **allow(*REHEARSERS))
def get_rehearsal(rehearsal_id: RehearsalId, request: Request,
                  principal: CurrentPrincipal) -> RehearsalOut:
    return _out(hub_of(request).get(rehearsal_id, user_id=principal.user.id))


@router.post("/rehearsals/{rehearsal_id}/outcome", operation_id="chooseOutcome",
             response_model=RehearsalOut, **allow(*REHEARSERS))
def choose_outcome(rehearsal_id: RehearsalId, body: OutcomeIn, request: Request,
                   principal: CurrentPrincipal, db: Db, services: Services) -> RehearsalOut:
    """End the current goal with this outcome (manual rehearsals)."""
    live = hub_of(request).get(rehearsal_id, user_id=principal.user.id)
    goal = live.rehearsal.status().get("current_goal")
    try:
        live.rehearsal.choose(body.outcome)
    except ValueError as exc:
        raise Conflict(str(exc)) from None
    record(db, kind="rehearsal.outcome", actor=principal.user, mission_id=live.mission_id,
           detail={"rehearsal": rehearsal_id, "goal": goal, "outcome": body.outcome},
           signer=services.signer)
    return _out(live)


@router.post("/rehearsals/{rehearsal_id}/faults", operation_id="injectFault",
             response_model=RehearsalOut, **allow(*REHEARSERS))
def inject_fault(rehearsal_id: RehearsalId, body: FaultIn, request: Request,
                 principal: CurrentPrincipal, db: Db, services: Services) -> RehearsalOut:
    from ...rehearse.sim_model import UnknownFault  # loaded with the live rehearsal

    live = hub_of(request).get(rehearsal_id, user_id=principal.user.id)
    try:
        live.rehearsal.inject(body.fault)
    except UnknownFault as exc:
        raise Unprocessable(str(exc)) from None
    except ValueError as exc:  # the rehearsal's state: stopped, finished, already injected
        raise Conflict(str(exc)) from None
    record(db, kind="rehearsal.fault", actor=principal.user, mission_id=live.mission_id,
           detail={"rehearsal": rehearsal_id, "fault": body.fault}, signer=services.signer)
    return _out(live)


@router.post("/rehearsals/{rehearsal_id}/skip", operation_id="skipRehearsal",
             response_model=RehearsalOut, **allow(*REHEARSERS))
def skip_rehearsal(rehearsal_id: RehearsalId, request: Request,
                   principal: CurrentPrincipal) -> RehearsalOut:
    """Run to the next decision (the next outcome chosen or asked for) at once."""
    live = hub_of(request).get(rehearsal_id, user_id=principal.user.id)
    try:
        live.rehearsal.skip()
    except ValueError as exc:
        raise Conflict(str(exc)) from None
    return _out(live)


@router.post("/rehearsals/{rehearsal_id}/stop", operation_id="stopRehearsal",
             response_model=RecordOut, **allow(*REHEARSERS))
def stop_rehearsal(rehearsal_id: RehearsalId, request: Request, principal: CurrentPrincipal,
                   db: Db, services: Services) -> RecordOut:
    """Stop the rehearsal and store its record and standalone replay."""
    hub = hub_of(request)
    live, finished = hub.stop(rehearsal_id, user_id=principal.user.id)
    try:
        replay = finished.replay_html() if finished.has_replay else b""
        row = records.save_record(
            db, digest=finished.digest, record=finished.to_json(), replay_html=replay,
            mission_id=live.mission_id, version=live.version,
            orders_digest=live.rehearsal.orders_digest, source=live.source,
            owner=principal.user, rehearsal_id=rehearsal_id, signer=services.signer)
        out = RecordOut(**records.record_summary(db, row))
        db.commit()  # stored before the rehearsal is forgotten: a failure here can be retried
    except BaseException:
        hub.recorded(rehearsal_id, None)
        raise
    hub.recorded(rehearsal_id, finished.digest)
    return out


@router.get("/missions/{mission_id}/rehearsal-records", operation_id="listRehearsalRecords",
            response_model=list[RecordOut], **allow(*EVERYONE))
def list_rehearsal_records(mission_id: str, db: Db,
                           limit: Annotated[int, Query(ge=1, le=200)] = 50) -> list[RecordOut]:
    get_mission(db, mission_id)
    return [RecordOut(**records.record_summary(db, r))
            for r in records.list_records(db, mission_id=mission_id, limit=limit)]


@router.get("/rehearsal-records/{digest}", operation_id="getRehearsalRecord",
            response_model=RecordDetail, **allow(*EVERYONE))
def get_rehearsal_record(digest: RecordDigest, db: Db) -> RecordDetail:
    row = records.get_record(db, digest)
    return RecordDetail(**records.record_summary(db, row), record=row.record)


@router.get("/rehearsal-records/{digest}/replay.html", operation_id="getRehearsalReplay",
            response_class=Response, responses={200: {"content": {"text/html": {}}}},
            **allow(*EVERYONE))
def get_rehearsal_replay(digest: RecordDigest, db: Db) -> Response:
    """viser's standalone replay of the rehearsal (self-contained HTML; works offline)."""
    row = records.get_record(db, digest, with_replay=True)
    if not row.replay_html:
        raise NotFound(f"the rehearsal record {digest} has no scene recording")
    return Response(row.replay_html, media_type="text/html; charset=utf-8", headers={
        "Content-Security-Policy": REPLAY_CSP, "X-Frame-Options": "SAMEORIGIN",
        "Content-Disposition": f'inline; filename="rehearsal-{digest[7:19]}.html"'})


# --- viser's client and websocket, through the app -------------------------------------------

def _viewer_user(database: Database, cookie: str | None, bearer: str | None) -> User | None:
    with database.session(write=False) as db:
        if bearer:
            return token_user(db, bearer)
        found = session_user(db, cookie) if cookie else None
        return found[0] if found else None


def _bearer(headers: Any) -> str | None:
    value = str(headers.get("authorization", ""))
    return value[7:].strip() if value.lower().startswith("bearer ") else None


def _origin_ok(origin: str | None, host: str | None, *, cookie_auth: bool) -> bool:
    """Cookie sessions need the browser's Origin to be this app (no cross-site websocket
    hijacking); a bearer token carries no ambient authority, but a foreign Origin is refused."""
    if origin is None:
        return not cookie_auth
    if not host:
        return False
    netloc = urlsplit(origin).netloc
    return bool(netloc) and hmac.compare_digest(netloc.lower().encode(), host.lower().encode())


def _authorize(database: Database, hub: RehearsalHub, rehearsal_id: str, cookie: str | None,
               bearer: str | None) -> tuple[int, str] | Live:
    user = _viewer_user(database, cookie, bearer)
    if user is None:
        return 401, "sign in first"
    if user.role not in REHEARSERS:
        return 403, f"the {user.role} role may not watch live rehearsals"
    try:
        return hub.get(rehearsal_id, user_id=user.id)
    except DomainError as exc:
        return problems.status_of(exc), str(exc)


@viewer.get("/rehearsal/{rehearsal_id}", include_in_schema=False)
def viewer_redirect(rehearsal_id: RehearsalId) -> Response:
    return RedirectResponse(f"/rehearsal/{rehearsal_id}/", status_code=308)


@viewer.get("/rehearsal/{rehearsal_id}/", include_in_schema=False)
def viewer_page(rehearsal_id: RehearsalId, request: Request) -> Response:
    """The signed-in owner's way in: a ticket for this rehearsal's viewer, and the frame sent
    to the viewer's ticket URL (viewer_tickets.py)."""
    credential = Credential(request.cookies.get(SESSION_COOKIE), _bearer(request.headers))
    hub = hub_of(request)
    checked = _authorize(request.app.state.database, hub, rehearsal_id, credential.cookie,
                         credential.bearer)
    if not isinstance(checked, Live):
        return problems.problem(checked[0], checked[1], request)
    ticket = hub.viewers.mint(rehearsal_id, checked.user_id, credential)
    return RedirectResponse(f"/rehearsal/{rehearsal_id}/t/{ticket}/", status_code=303,
                            headers={"Cache-Control": "no-store"})


@viewer.get("/rehearsal/{rehearsal_id}/t/{ticket}/", include_in_schema=False)
def viewer_client(rehearsal_id: RehearsalId, ticket: TicketText, request: Request) -> Response:
    """viser's bundled client, in an opaque origin (CLIENT_CSP), for a live ticket."""
    checked = _redeem(request.app.state.database, hub_of(request), rehearsal_id, ticket)
    if isinstance(checked, Denied):
        return problems.problem(checked.status, checked.detail, request)
    return Response(client_index(), media_type="text/html; charset=utf-8", headers={
        "Content-Security-Policy": client_csp(request.headers.get("host")),
        "X-Frame-Options": "SAMEORIGIN",
        "Cache-Control": "no-store"})


@viewer.get("/rehearsal/{rehearsal_id}/{rest:path}", include_in_schema=False)
def viewer_other(rehearsal_id: RehearsalId, rest: str, request: Request) -> Response:
    return problems.problem(404, "viser's client is one file; nothing else is served here",
                            request)


@dataclass(frozen=True)
class Denied:
    status: int
    detail: str


@dataclass(frozen=True)
class Admitted:
    live: Live
    ticket: Ticket


def _redeem(database: Database, hub: RehearsalHub, rehearsal_id: str,
            ticket: str) -> Denied | Admitted:
    found = hub.viewers.redeem(rehearsal_id, ticket)
    if found is None:
        return Denied(403, "the viewer's ticket is unknown or expired; reopen the rehearsal")
    checked = _authorize(database, hub, rehearsal_id, found.credential.cookie,
                         found.credential.bearer)
    if not isinstance(checked, Live):
        return Denied(*checked)
    if checked.user_id != found.user_id:
        return Denied(403, "the viewer's ticket is not yours")
    return Admitted(checked, found)


@viewer.websocket("/rehearsal/{rehearsal_id}/t/{ticket}")
async def viewer_ticket_socket(websocket: WebSocket, rehearsal_id: str, ticket: str) -> None:
    """viser's websocket from the sandboxed viewer (Origin `null`, no cookie): the ticket in
    its URL is the authority. A foreign Origin is refused all the same."""
    origin = websocket.headers.get("origin")
    if origin not in (None, "null") and not _origin_ok(origin, websocket.headers.get("host"),
                                                       cookie_auth=True):
        await _deny(websocket, 403, "the websocket's Origin is not this app")
        return
    if not _plain_id(rehearsal_id) or len(ticket) > 100:
        await _deny(websocket, 404, "no such rehearsal")
        return
    checked = await run_in_threadpool(_redeem, websocket.app.state.database, hub_of(websocket),
                                      rehearsal_id, ticket)
    if isinstance(checked, Denied):
        await _deny(websocket, checked.status, checked.detail)
        return
    await _proxy(websocket, checked.live, checked.ticket.credential)


@viewer.websocket("/rehearsal/{rehearsal_id}")
async def viewer_socket(websocket: WebSocket, rehearsal_id: str) -> None:
    """viser's websocket for API clients, after the session (cookie or bearer token), the
    Origin and the ownership of the rehearsal are checked; refused before the upgrade
    otherwise."""
    hub = hub_of(websocket)
    credential = Credential(websocket.cookies.get(SESSION_COOKIE), _bearer(websocket.headers))
    if not _origin_ok(websocket.headers.get("origin"), websocket.headers.get("host"),
                      cookie_auth=credential.bearer is None):
        await _deny(websocket, 403, "the websocket's Origin is not this app")
        return
    if not _plain_id(rehearsal_id):
        await _deny(websocket, 404, "no such rehearsal")
        return
    checked = await run_in_threadpool(_authorize, websocket.app.state.database, hub,
                                      rehearsal_id, credential.cookie, credential.bearer)
    if not isinstance(checked, Live):
        await _deny(websocket, checked[0], checked[1])
        return
    await _proxy(websocket, checked, credential)


def _plain_id(rehearsal_id: str) -> bool:
    return len(rehearsal_id) <= 64 and rehearsal_id.replace("-", "").replace("_", "").isalnum()


async def _proxy(websocket: WebSocket, live: Live, credential: Credential) -> None:
    """Relay viser's websocket within the socket caps, until either side closes or the
    credential that opened it is gone (signed out, revoked, expired) or the rehearsal ends."""
    hub = hub_of(websocket)
    rehearsal_id = live.rehearsal.id
    try:
        socket = hub.viewers.open(rehearsal_id, live.user_id, credential.key)
    except SocketLimit as exc:
        await _deny(websocket, 429, str(exc))
        return
    try:
        try:
            upstream = await open_upstream(live.rehearsal.port,
                                           list(websocket.scope.get("subprotocols", [])),
                                           live.rehearsal.viewer_secret)
        except OSError as exc:
            log.info("rehearsal %s: viser not reachable: %s", rehearsal_id, exc)
            await _deny(websocket, 410, f"the rehearsal {rehearsal_id} has ended")
            return
        await websocket.accept(subprotocol=upstream.subprotocol)
        stats = ProxyStats()
        live.sockets += 1
        proxied: list[ProxyStats] = websocket.app.state.rehearsal_proxies
        proxied.append(stats)
        del proxied[:-200]
        database = websocket.app.state.database

        async def watch() -> str:
            while True:
                with anyio.move_on_after(SESSION_CHECK_S):
                    await socket.ended.wait()
                    return socket.reason or "signed out"
                still = await run_in_threadpool(_authorize, database, hub, rehearsal_id,
                                                credential.cookie, credential.bearer)
                if not isinstance(still, Live):
                    return "the session or the rehearsal has ended"

        try:
            await relay(websocket, upstream, stats, watch)
        finally:
            live.sockets -= 1
    finally:
        hub.viewers.close(socket)


async def _deny(websocket: WebSocket, status: int, detail: str) -> None:
    """Refuse the upgrade with an HTTP problem (or close, on servers without denial
    responses, which clients see as 403)."""
    try:
        await websocket.send_denial_response(problems.problem(status, detail))
    except RuntimeError:
        await websocket.close(code=1008, reason=detail[:120])

