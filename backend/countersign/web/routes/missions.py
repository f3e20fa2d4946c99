"""Missions, drafts, versions, reports, paths, import and export."""

from __future__ import annotations

import base64
import hashlib
from collections.abc import Iterator
from dataclasses import dataclass
from typing import Annotated, Any, Literal

from fastapi import APIRouter, Header, HTTPException, Path, Query, Request, Response
from fastapi.concurrency import run_in_threadpool
from fastapi.responses import JSONResponse, PlainTextResponse, StreamingResponse
from pydantic import BaseModel, Field
from sqlalchemy import func, or_, select
from sqlalchemy.orm import Session as DbSession
from sqlalchemy.orm import defer

from ...errors import Conflict, Invalid, NotFound
from ...orders.canonical import digest, orders_to_json
from ...orders.examples import example_bytes, example_names
from ...orders.model import Orders
from ...orders.reader import orders_from_data, read_bytes, read_json
from ...orders.writers import WRITERS
from ...rules.plain_orders import write_for_supervisor
from ...store import missions as service
from ...store.accounts import username_of
from ...store.db import database_of
from ...store.mission_status import mission_status, mission_statuses
from ...store.tables import Mission, MissionVersion, ValidationReport
from ...store.vehicles import registry_stamp, with_registry
from ...verify import fingerprint
from ...verify.path_search import UnknownNode, count_matching, iter_matching, path_query
from ...verify.paths import count_paths, iter_path_lines, iter_paths, trace_text
from ...verify.probability import declares_probabilities, path_probability_bounds
from ...verify.refine import checked_form
from ..deps import (
    EVERYONE,
    MAX_ROW_ID,
    OPERATORS,
    CurrentPrincipal,
    Db,
    RowId,
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
    counted_summary_fields,
    summary_fields,
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


@dataclass(frozen=True)
class Validated:
    """Orders about to be written: their digest, and their report if it is new (stored by
    `keep` in the write transaction that follows)."""

    digest: str
    new_report: dict[str, Any] | None

    def keep(self, db: DbSession) -> None:
        if self.new_report is not None:
            service.remember_report(db, self.new_report)


def _validate_first(db: DbSession, orders: Orders, mission_id: str | None = None,
                    expected_revision: int | None = None) -> Validated:
    """Validate orders about to be written before the write transaction begins. A writing
    request holds the write lock from its first query to its commit, so validating here (in
    a read transaction, without any lock) keeps that stretch short; the new report is then
    stored in the write transaction itself, so that neither this answer nor the next read
    validates again. An edit whose revision is already stale fails with 412 before paying
    for validation."""
    value = digest(orders)
    with database_of(db).session(write=False) as reader:
        if mission_id is not None and expected_revision is not None:
            current = reader.get(Mission, mission_id)
            if current is not None and current.revision != expected_revision:
                raise service.PreconditionFailed(
                    f"the draft changed since revision {expected_revision} (now "
                    f"{current.revision}); reload it and apply your edit again",
                    current.revision)
        found = service.lookup_report(reader, orders, value)
    return Validated(value, None if found.cached else found.report)


def _summary(db: DbSession, mission: Mission, names: dict[int, str],
             latest: int | Literal[False] | None = False,
             status: tuple[str, list[str]] | None = None) -> dict[str, Any]:
    # A writing request holds the write lock until it answers: it reports only what is cached
    # (ok/errors stay null otherwise) and leaves validation to the next read or /validate.
    if db.info.get("write", True):
        report = service.cached_report(db, mission.draft_digest)
    else:
        report = service.report_for(db, lambda: _orders(mission.draft), mission.draft_digest).report
    if latest is False:
        latest = db.scalar(select(func.max(MissionVersion.number))
                           .where(MissionVersion.mission_id == mission.id))
    return summary_fields(mission, report, latest, username_of(db, mission.updated_by, names),
                          status or mission_status(db, mission))


def _detail(db: DbSession, mission: Mission, response: Response | None,
            import_findings: list[dict[str, Any]] | None = None) -> MissionDetail:
    names: dict[int, str] = {}
    # The list needs no version's orders: select the four columns it shows.
    rows = db.execute(
        select(MissionVersion.number, MissionVersion.digest, MissionVersion.author_id,
               MissionVersion.created_at)
        .where(MissionVersion.mission_id == mission.id).order_by(MissionVersion.number)
    ).all()
    versions = [VersionOut(number=number, digest=value, author=username_of(db, author, names),
                           created_at=created_at)
                for number, value, author, created_at in rows]
    if response is not None:
        response.headers["ETag"] = f'"{mission.revision}"'
    latest = versions[-1].number if versions else None
    return MissionDetail(**_summary(db, mission, names, latest), orders=mission.draft,
                         layout=mission.layout, versions=versions,
                         import_findings=import_findings or [])


def _encode_cursor(value: str | int) -> str:
    return base64.urlsafe_b64encode(str(value).encode()).decode()


def _decode_cursor(cursor: str) -> str:
    try:
        return base64.b64decode(cursor.encode(), altchars=b"-_", validate=True).decode()
    except (ValueError, UnicodeDecodeError):
        raise Invalid("the cursor is not valid; start again without one") from None


@router.get("/missions", operation_id="listMissions", response_model=MissionPage,
            **allow(*EVERYONE))
def list_missions(
    db: Db,
    q: Annotated[str | None, Query(max_length=200)] = None,
    status: Annotated[str | None, Query(max_length=16)] = None,
    vehicle: Annotated[str | None, Query(max_length=100)] = None,
    limit: Annotated[int, Query(ge=1, le=MAX_PAGE)] = 50,
    cursor: Annotated[str | None, Query(max_length=400)] = None,
) -> MissionPage:
    # One query: each mission's row without its orders or layout, its draft report's summary
    # columns (never the report itself) and its latest version number (issue 36).
    latest = (select(func.max(MissionVersion.number))
              .where(MissionVersion.mission_id == Mission.id).scalar_subquery())
    query = (
        select(Mission, ValidationReport.ok, ValidationReport.errors, ValidationReport.warnings,
               latest)
        .options(defer(Mission.draft), defer(Mission.layout))
        .outerjoin(ValidationReport,
                   (ValidationReport.digest == Mission.draft_digest)
                   & (ValidationReport.checker_version == fingerprint.checker_fingerprint()))
        .order_by(Mission.id).limit(limit + 1)
    )
    if q:
        pattern = "%" + q.replace("\\", "\\\\").replace("%", "\\%").replace("_", "\\_") + "%"
        query = query.where(or_(Mission.id.ilike(pattern, escape="\\"),
                                Mission.title.ilike(pattern, escape="\\")))
    if status:
        query = query.where(Mission.status == status)
    if vehicle:
        query = query.where(Mission.vehicle == vehicle)
    if cursor:
        query = query.where(Mission.id > _decode_cursor(cursor))
    rows = db.execute(query).all()
    names: dict[int, str] = {}
    items = []
    statuses = mission_statuses(db, [row[0] for row in rows[:limit]])
    for mission, ok, errors, warnings, number in rows[:limit]:
        shown = statuses[mission.id]
        if errors is None or warnings is None:  # no current report yet: as the detail does
            fields = _summary(db, mission, names, number, shown)
        else:
            fields = counted_summary_fields(mission, ok, errors, warnings, number,
                                            username_of(db, mission.updated_by, names), shown)
        items.append(MissionSummary(**fields))
    following = _encode_cursor(rows[limit - 1][0].id) if len(rows) > limit else None
    return MissionPage(items=items, next_cursor=following)


@router.post("/missions", operation_id="createMission", status_code=201,
             response_model=MissionDetail, **with_limit(allow(*OPERATORS), None))
def create_mission(body: OrdersJson, response: Response, principal: CurrentPrincipal,
                   db: Db) -> MissionDetail:
    orders = with_registry(db, _orders(body))
    validated = _validate_first(db, orders)
    mission = service.create_mission(db, orders=orders, author=principal.user,
                                     orders_digest=validated.digest)
    validated.keep(db)
    return _detail(db, mission, response)


IMPORT_ROUTE = allow(*OPERATORS)
IMPORT_ROUTE["openapi_extra"]["requestBody"] = {"required": True, "content": {
    "application/json": {"schema": {"type": "object"}},
    "application/xml": {"schema": {"type": "string"}},
    "text/turtle": {"schema": {"type": "string"}}}}


@router.post("/import", operation_id="importMission", status_code=201,
             response_model=MissionDetail, **with_limit(IMPORT_ROUTE, "import"))
async def import_mission(request: Request, response: Response, principal: CurrentPrincipal,
                         db: Db) -> MissionDetail:
    data = await request.body()
    # Parsing, validation and the write run in a worker thread, committed there (the event
    # loop must never wait for a database lock).
    return await run_in_threadpool(in_one_transaction, db, _import, db, data, response,
                                   principal)


def _import(db: DbSession, data: bytes, response: Response,
            principal: CurrentPrincipal) -> MissionDetail:
    loaded = read_bytes(data, "the uploaded file")
    orders = with_registry(db, loaded.orders)
    validated = _validate_first(db, orders)
    mission = service.create_mission(db, orders=orders, author=principal.user,
                                     orders_digest=validated.digest)
    validated.keep(db)
    return _detail(db, mission, response, [f.to_json() for f in loaded.findings])


class ReadOrdersOut(BaseModel):
    """Orders read from a file without storing anything, with what reading them found."""

    orders: OrdersJson
    findings: list[FindingJson] = []


@router.post("/read", operation_id="readOrders", response_model=ReadOrdersOut,
             **with_limit(IMPORT_ROUTE, "read"))
async def read_orders(request: Request) -> ReadOrdersOut:
    """Reads JSON, AVCL XML or MEO Turtle into orders (the import route's reader) and stores
    nothing: the editor replaces its draft with them through the usual If-Match save."""
    data = await request.body()
    loaded = await run_in_threadpool(read_bytes, data, "the uploaded file")
    return ReadOrdersOut(orders=orders_to_json(loaded.orders),
                         findings=[f.to_json() for f in loaded.findings])


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
def get_mission(mission_id: str, response: Response, db: Db) -> MissionDetail:
    return _detail(db, service.get_mission_with_report(db, mission_id), response)


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
                 principal: CurrentPrincipal, db: Db,
                 if_match: Annotated[str | None, Header()] = None) -> MissionDetail:
    orders, expected = with_registry(db, _orders(body.orders)), _revision(if_match)
    validated = _validate_first(db, orders, mission_id, expected)
    mission = service.update_draft(
        db, mission_id=mission_id, orders=orders, layout=body.layout,
        expected_revision=expected, author=principal.user, orders_digest=validated.digest)
    validated.keep(db)
    return _detail(db, mission, response)


@router.put("/missions/{mission_id}/layout", operation_id="saveLayout",
            response_model=LayoutOut, **allow(*OPERATORS))
def save_layout(mission_id: str, body: LayoutIn, db: Db) -> LayoutOut:
    """Node positions of the graph editor: editor data, not orders (no revision, no If-Match)."""
    layout = {node: {"x": p.x, "y": p.y} for node, p in body.layout.items()}
    mission = service.save_layout(db, mission_id=mission_id, layout=layout)
    return LayoutOut(layout=mission.layout)


@router.delete("/missions/{mission_id}", operation_id="deleteMission", status_code=204,
               **allow(*OPERATORS))
def delete_mission(mission_id: str, principal: CurrentPrincipal, db: Db) -> None:
    service.delete_mission(db, mission_id=mission_id, actor=principal.user)


@router.post("/missions/{mission_id}/versions", operation_id="createVersion", status_code=201,
             response_model=VersionOut, **allow(*OPERATORS))
def create_version(mission_id: str, principal: CurrentPrincipal, db: Db) -> VersionOut:
    version = service.create_version(db, mission_id=mission_id, author=principal.user)
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
def get_report(mission_id: str, db: Db) -> Response:
    mission = service.get_mission(db, mission_id)
    # A report is answered as stored (it was made by this server): no model round trip.
    return JSONResponse(service.report_for(db, lambda: _orders(mission.draft),
                                           mission.draft_digest).report)


VALIDATE_ROUTE = allow(*EVERYONE)
# The body is read raw (the same bytes again skip parsing), so its schema is stated here.
VALIDATE_ROUTE["openapi_extra"]["requestBody"] = {"required": True, "content": {
    "application/json": {"schema": {"$ref": "#/components/schemas/Orders"}}}}
VALIDATE_ROUTE["responses"] = {422: {"description": "Validation Error", "content": {
    "application/json": {"schema": {"$ref": "#/components/schemas/HTTPValidationError"}}}}}


@router.post("/validate", operation_id="validateOrders", **REPORT_ROUTE,
             **computing(with_limit(VALIDATE_ROUTE, "validate")))
async def validate_orders(request: Request, db: Db) -> Response:
    data = await request.body()
    return await run_in_threadpool(in_one_transaction, db, _validate_body, db, data)


def _validate_body(db: DbSession, data: bytes) -> Response:
    # The same body sent again (an editor re-checking, a CI job) skips parsing and
    # canonicalising: the report service remembers the orders digest of recent bodies. The
    # registry's profiles and charts are copied into the orders, so they are part of the key.
    reports = database_of(db).reports
    key = hashlib.sha256(registry_stamp(db) + b"\0" + data).digest()
    known = reports.body_digest(key)
    if known is not None:
        stored = service.cached_report(db, known)
        if stored is not None:
            return JSONResponse(stored)
    # The importer's JSON reader: duplicate keys, bad UTF-8 and bad JSON are 422 problems.
    report = service.report_for(db, with_registry(db, read_json(data))).report
    reports.remember_body(key, report["digest"])
    return JSONResponse(report)


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
    if version is not None:
        orders = _orders(service.get_version(db, mission_id, version).orders)
    else:
        orders = _orders(service.get_mission(db, mission_id).draft)
    if orders.team is not None:
        # A team has one path list per member; its joint executions are counted in the report.
        raise Conflict("these orders are a team's: each member has its own paths, "
                       "and the report counts the joint executions")
    # Refined goals run as their refinements: the paths are those of the flat mission.
    orders, graph = checked_form(orders)
    counts = count_paths(graph)
    bounds = (path_probability_bounds(orders, graph)
              if declares_probabilities(orders) else None)
    if counts is None:
        raise Conflict("the paths cannot be counted until the structural errors "
                       "in the report are fixed")
    searching = bool(goal or terminal)
    try:
        query = path_query(graph, goal, terminal)
    except UnknownNode as e:
        raise Invalid(f"{e}: search by one of its goal or terminal ids") from None
    matching = count_matching(graph, query) if searching else counts.total
    assert matching is not None  # counted above
    offset = 0
    if cursor:
        try:
            offset = int(_decode_cursor(cursor))
        except ValueError:
            raise Invalid("the cursor is not valid") from None
        if not 0 <= offset <= matching:  # e.g. "LTE=", which decodes to -1
            raise Invalid("the cursor is not valid")
    if format == "ndjson" or "application/x-ndjson" in request.headers.get("accept", ""):
        if searching:
            raise Invalid("goal and terminal apply to JSON pages and traces; "
                          "stream every path without them")
        def lines() -> Iterator[str]:
            for line in iter_path_lines(graph, counts, offset, probabilities=bounds):
                yield line + "\n"
        return StreamingResponse(lines(), media_type="application/x-ndjson")
    if searching:
        page = list(iter_matching(graph, counts, query, offset, limit, probabilities=bounds))
    else:
        page = list(iter_paths(graph, counts, offset, limit, probabilities=bounds))
    if format == "trace":
        return PlainTextResponse("\n".join(trace_text(graph, p) for p in page) + "\n")
    following = offset + len(page)
    return PathPage(count=counts.total, by_terminal=counts.by_terminal,
                    matching=matching if searching else None,
                    items=[MissionPathOut(index=p.index, goals=list(p.goals),
                                          outcomes=list(p.outcomes), terminal=p.terminal,
                                          probability=p.probability)
                           for p in page],
                    next_cursor=_encode_cursor(following) if following < matching else None)


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
