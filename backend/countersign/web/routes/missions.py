"""Missions, drafts, versions, reports, paths, import and export."""

from __future__ import annotations

from typing import Annotated, Any

from fastapi import APIRouter, Header, HTTPException, Path, Query, Request, Response
from fastapi.concurrency import run_in_threadpool
from fastapi.responses import JSONResponse, PlainTextResponse, StreamingResponse
from pydantic import BaseModel, Field
from sqlalchemy.orm import Session as DbSession

from ...errors import Invalid, NotFound
from ...orders.canonical import orders_to_json
from ...orders.examples import example_bytes, example_names
from ...orders.model import Orders
from ...orders.reader import orders_from_data, read_bytes
from ...orders.writers import WRITERS
from ...rules.plain_orders import write_for_supervisor
from ...services import missions
from ...services.app import AppServices
from ...store import missions as service
from ...store.accounts import username_of
from ...store.tables import Mission
from ...verify.paths import trace_text
from ..deps import (
    EVERYONE,
    MAX_ROW_ID,
    OPERATORS,
    CurrentPrincipal,
    Db,
    RowId,
    Services,
    TransactionRoute,
    allow,
    computing,
    in_one_transaction,
)
from ..fair import with_limit
from .schemas import (
    FindingJson,
    LayoutJson,
    MissionDetail,
    MissionPage,
    MissionPathOut,
    MissionSummary,
    OrdersJson,
    PathPage,
    ReportOut,
    RequestBody,
    VersionOut,
    version_out,
)

router = APIRouter(prefix="/api", tags=["missions"], route_class=TransactionRoute)
MAX_PAGE = 200
MAX_PATH_PAGE = 1000


class DraftIn(RequestBody):
    orders: OrdersJson
    layout: LayoutJson | None = None


class Position(RequestBody):
    x: float = Field(allow_inf_nan=False)
    y: float = Field(allow_inf_nan=False)


class LayoutIn(RequestBody):
    layout: dict[Annotated[str, Field(max_length=100)], Position] = Field(
        max_length=service.MAX_LAYOUT_NODES)


class LayoutOut(BaseModel):
    layout: LayoutJson


def _orders(data: dict[str, Any]) -> Orders:
    return orders_from_data(data)


def _detail(db: DbSession, services: AppServices, mission: Mission, response: Response | None,
            import_findings: list[dict[str, Any]] | None = None) -> MissionDetail:
    fields = missions.detail(db, mission, reports=services.reports,
                             import_findings=import_findings)
    if response is not None:
        response.headers["ETag"] = _etag(mission)
    return MissionDetail(**fields)


def _etag(mission: Mission) -> str:
    """The draft's ETag, which a save's If-Match must send back."""
    return f'"{mission.revision}"'


@router.get("/missions", operation_id="listMissions", response_model=MissionPage,
            **allow(*EVERYONE))
def list_missions(
    db: Db,
    services: Services,
    q: Annotated[str | None, Query(max_length=200)] = None,
    status: Annotated[str | None, Query(max_length=16)] = None,
    vehicle: Annotated[str | None, Query(max_length=100)] = None,
    limit: Annotated[int, Query(ge=1, le=MAX_PAGE)] = 50,
    cursor: Annotated[str | None, Query(max_length=400)] = None,
) -> MissionPage:
    found = missions.list_missions(db, reports=services.reports, q=q, status=status,
                                   vehicle=vehicle, limit=limit, cursor=cursor)
    return MissionPage(items=[MissionSummary(**fields) for fields in found.items],
                       next_cursor=found.next_cursor)


@router.post("/missions", operation_id="createMission", status_code=201,
             response_model=MissionDetail, **with_limit(allow(*OPERATORS), None))
def create_mission(body: OrdersJson, response: Response, principal: CurrentPrincipal,
                   db: Db, services: Services) -> MissionDetail:
    mission = missions.create_mission(db, _orders(body), author=principal.user,
                                      database=services.database, reports=services.reports,
                                      signer=services.signer)
    return _detail(db, services, mission, response)


IMPORT_ROUTE = allow(*OPERATORS)
IMPORT_ROUTE["openapi_extra"]["requestBody"] = {"required": True, "content": {
    "application/json": {"schema": {"type": "object"}},
    "application/xml": {"schema": {"type": "string"}},
    "text/turtle": {"schema": {"type": "string"}}}}


@router.post("/import", operation_id="importMission", status_code=201,
             response_model=MissionDetail, **with_limit(IMPORT_ROUTE, "import"))
async def import_mission(request: Request, principal: CurrentPrincipal,
                         db: Db, services: Services) -> Response:
    data = await request.body()
    # Parsing, validation, the write and the answer's encoding run in a worker thread,
    # committed there: the event loop must never wait for a database lock, nor encode
    # megabytes of orders while every other request of the process waits.
    return await run_in_threadpool(in_one_transaction, db, _import, db, services, data,
                                   principal)


def _import(db: DbSession, services: AppServices, data: bytes,
            principal: CurrentPrincipal) -> Response:
    loaded = read_bytes(data, "the uploaded file")
    mission = missions.create_mission(db, loaded.orders, author=principal.user,
                                      database=services.database, reports=services.reports,
                                      signer=services.signer)
    detail = _detail(db, services, mission, None, [f.to_json() for f in loaded.findings])
    return JSONResponse(detail.model_dump(mode="json"), status_code=201,
                        headers={"ETag": _etag(mission)})


class ReadOrdersOut(BaseModel):
    """Orders read from a file without storing anything, with what reading them found."""

    orders: OrdersJson
    findings: list[FindingJson] = []


@router.post("/read", operation_id="readOrders", response_model=ReadOrdersOut,
             **with_limit(IMPORT_ROUTE, "read"))
async def read_orders(request: Request) -> Response:
    """Reads JSON, AVCL XML or MEO Turtle into orders (the import route's reader) and stores
    nothing: the editor replaces its draft with them through the usual If-Match save."""
    data = await request.body()
    # The answer is made and encoded in the worker thread too: megabytes of orders encoded on
    # the event loop would stall every other request of this process.
    return await run_in_threadpool(_read_orders, data)


def _read_orders(data: bytes) -> Response:
    loaded = read_bytes(data, "the uploaded file")
    out = ReadOrdersOut(orders=orders_to_json(loaded.orders),
                        findings=[f.to_json() for f in loaded.findings])
    return JSONResponse(out.model_dump(mode="json"))


class ExampleOut(BaseModel):
    name: str
    id: str
    title: str
    goals: int


@router.get("/examples", operation_id="listExamples", response_model=list[ExampleOut],
            **allow(*EVERYONE))
def list_examples() -> list[ExampleOut]:
    items = []
    for name in example_names():
        orders = read_bytes(example_bytes(name), name).orders
        items.append(ExampleOut(name=name, id=orders.id, title=orders.title or "",
                                goals=len(orders.goals)))
    return items


@router.get("/examples/{name}", operation_id="getExample", response_model=OrdersJson,
            **allow(*EVERYONE))
def get_example(name: Annotated[str, Path(max_length=100)]) -> dict[str, Any]:
    if name not in example_names():
        raise NotFound(f"no built-in example named {name!r}")
    return orders_to_json(read_bytes(example_bytes(name), name).orders)


@router.get("/missions/{mission_id}", operation_id="getMission", response_model=MissionDetail,
            **with_limit(allow(*EVERYONE), None))
def get_mission(mission_id: str, response: Response, db: Db,
                services: Services) -> MissionDetail:
    return _detail(db, services, service.get_mission(db, mission_id), response)


def _revision(if_match: str | None) -> int:
    if if_match is None:
        raise HTTPException(428, "send If-Match with the ETag of the draft you edited")
    try:
        return int(if_match.strip().removeprefix("W/").strip('"'))
    except ValueError:
        raise HTTPException(412, f"If-Match {if_match!r} is not an ETag of this API") from None


@router.put("/missions/{mission_id}/draft", operation_id="updateDraft",
            response_model=MissionDetail, **with_limit(allow(*OPERATORS), None))
def update_draft(mission_id: str, body: DraftIn, response: Response,
                 principal: CurrentPrincipal, db: Db, services: Services,
                 if_match: Annotated[str | None, Header()] = None) -> MissionDetail:
    orders, expected = _orders(body.orders), _revision(if_match)
    mission = missions.update_draft(
        db, orders, mission_id=mission_id, layout=body.layout, expected_revision=expected,
        author=principal.user, database=services.database, reports=services.reports,
        signer=services.signer)
    return _detail(db, services, mission, response)


@router.put("/missions/{mission_id}/layout", operation_id="saveLayout",
            response_model=LayoutOut, **allow(*OPERATORS))
def save_layout(mission_id: str, body: LayoutIn, db: Db) -> LayoutOut:
    """Node positions of the graph editor: editor data, not orders (no revision, no If-Match)."""
    layout = {node: {"x": p.x, "y": p.y} for node, p in body.layout.items()}
    mission = service.save_layout(db, mission_id=mission_id, layout=layout)
    return LayoutOut(layout=mission.layout)


@router.delete("/missions/{mission_id}", operation_id="deleteMission", status_code=204,
               **allow(*OPERATORS))
def delete_mission(mission_id: str, principal: CurrentPrincipal, db: Db,
                   services: Services) -> None:
    service.delete_mission(db, signer=services.signer, mission_id=mission_id, actor=principal.user)


@router.post("/missions/{mission_id}/versions", operation_id="createVersion", status_code=201,
             response_model=VersionOut, **allow(*OPERATORS))
def create_version(mission_id: str, principal: CurrentPrincipal, db: Db,
                   services: Services) -> VersionOut:
    version = service.create_version(db, mission_id=mission_id, author=principal.user,
                                     signer=services.signer)
    return version_out(version, principal.user.username, True)


@router.get("/missions/{mission_id}/versions/{number}", operation_id="getVersion",
            response_model=VersionOut, **allow(*EVERYONE))
def get_version(mission_id: str, number: RowId, db: Db) -> VersionOut:
    version = service.get_version(db, mission_id, number)
    author = username_of(db, version.author_id)
    return version_out(version, author, True)


# Reports are stored as JSON and answered as stored: the model describes them in the OpenAPI
# document and drops nothing (exclude_unset keeps absent optional fields absent).
REPORT_ROUTE: dict[str, Any] = {"response_model": ReportOut,
                                "response_model_exclude_unset": True}


@router.get("/missions/{mission_id}/report", operation_id="getReport", **REPORT_ROUTE,
            **with_limit(allow(*EVERYONE), None))
def get_report(mission_id: str, db: Db, services: Services) -> Response:
    # A report is answered as stored (it was made by this server): no model round trip.
    return JSONResponse(missions.draft_report(db, reports=services.reports,
                                              mission_id=mission_id))


VALIDATE_ROUTE = allow(*EVERYONE)
# The body is read raw (the same bytes again skip parsing), so its schema is stated here.
VALIDATE_ROUTE["openapi_extra"]["requestBody"] = {"required": True, "content": {
    "application/json": {"schema": {"$ref": "#/components/schemas/Orders"}}}}
VALIDATE_ROUTE["responses"] = {422: {"description": "Validation Error", "content": {
    "application/json": {"schema": {"$ref": "#/components/schemas/HTTPValidationError"}}}}}


@router.post("/validate", operation_id="validateOrders", **REPORT_ROUTE,
             **computing(with_limit(VALIDATE_ROUTE, "validate")))
async def validate_orders(request: Request, db: Db, services: Services) -> Response:
    data = await request.body()
    return await run_in_threadpool(in_one_transaction, db, _validate_body, db, services, data)


def _validate_body(db: DbSession, services: AppServices, data: bytes) -> Response:
    # Read errors (duplicate keys, bad UTF-8, bad JSON) are 422 problems.
    return JSONResponse(missions.validate_body(db, reports=services.reports, data=data))


PATHS_ROUTE = allow(*EVERYONE)
PATHS_ROUTE["responses"] = {200: {"content": {
    "application/x-ndjson": {"schema": {"type": "string", "description":
                             "one path per line, as the items of the JSON page"}},
    "text/plain": {"schema": {"type": "string", "description": "traces, one per path"}}}}}


@router.get("/missions/{mission_id}/paths", operation_id="listPaths", response_model=PathPage,
            **PATHS_ROUTE)
def list_paths(
    mission_id: str, request: Request, db: Db,
    limit: Annotated[int, Query(ge=1, le=MAX_PATH_PAGE)] = 100,
    cursor: Annotated[str | None, Query(max_length=2000)] = None,
    format: Annotated[str, Query(pattern="^(json|ndjson|trace)$")] = "json",
    version: Annotated[int | None, Query(ge=1, le=MAX_ROW_ID, description=(
        "list the paths of this stored version instead of the draft"))] = None,
    goal: Annotated[str | None, Query(max_length=200, description=(
        "only the paths through this goal (JSON pages and traces)"))] = None,
    terminal: Annotated[str | None, Query(max_length=200, description=(
        "only the paths ending at this terminal (JSON pages and traces)"))] = None,
) -> PathPage | StreamingResponse | PlainTextResponse:
    """The paths in the order of Figure 6, a page at a time (`next_cursor`). With `goal` or
    `terminal`, only the matching paths (`matching` counts them), each keeping its index in the
    full list; the cursor then counts matches."""
    listing = missions.path_listing(db, mission_id=mission_id, version=version, goal=goal,
                                    terminal=terminal, cursor=cursor)
    if format == "ndjson" or "application/x-ndjson" in request.headers.get("accept", ""):
        if listing.searching:
            raise Invalid("goal and terminal apply to JSON pages and traces; "
                          "stream every path without them")
        return StreamingResponse(listing.lines(), media_type="application/x-ndjson")
    page = listing.page(limit)
    if format == "trace":
        return PlainTextResponse("\n".join(trace_text(listing.graph, p) for p in page) + "\n")
    return PathPage(count=listing.counts.total, by_terminal=listing.counts.by_terminal,
                    matching=listing.matching if listing.searching else None,
                    items=[MissionPathOut(index=p.index, goals=list(p.goals),
                                          outcomes=list(p.outcomes), terminal=p.terminal,
                                          probability=p.probability)
                           for p in page],
                    next_cursor=listing.next_cursor(len(page)))


@router.get("/missions/{mission_id}/export", operation_id="exportMission",
            response_class=PlainTextResponse, **allow(*EVERYONE))
def export_mission(
    mission_id: str, db: Db,
    format: Annotated[str, Query(pattern="^(json|dot|plain|turtle|nps-turtle|avcl)$")] = "json",
) -> Response:
    mission = service.get_mission(db, mission_id)
    _, media_type, suffix = WRITERS[format]
    text = write_for_supervisor(_orders(mission.draft), format)
    return Response(text, media_type=media_type, headers={
        "Content-Disposition": f'attachment; filename="{mission.id}.{suffix}"'})
