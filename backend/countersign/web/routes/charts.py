"""The chart registry (admins write, everyone signed in reads) and the plan view."""

from __future__ import annotations

from typing import Annotated, Any, Literal

from fastapi import APIRouter, HTTPException, Request, Response
from fastapi.concurrency import run_in_threadpool
from fastapi.responses import JSONResponse
from pydantic import BaseModel, ConfigDict, Field

from ...errors import Invalid, NotFound, Unprocessable
from ...orders.geo_formats import (
    KML_MEDIA_TYPE,
    MAX_BYTES,
    GeoFormatError,
    areas_to_geojson,
    charts_from_geojson,
    charts_from_kml,
    charts_to_kml,
)
from ...orders.model import Chart, ChartNorm
from ...orders.reader import read_json
from ...store.charts import all_charts, delete_chart, save_charts
from ...store.events import record
from ...store.vehicles import with_registry
from ...verify.plan_view import plan_view
from ..deps import (
    ADMINS,
    EVERYONE,
    CurrentPrincipal,
    Db,
    Services,
    TransactionRoute,
    allow,
    computing,
)
from .schemas import Number, RequestBody, SchemaOf

router = APIRouter(prefix="/api", tags=["charts"], route_class=TransactionRoute)


class ChartImport(RequestBody):
    format: Literal["geojson", "kml"]
    content: str = Field(max_length=MAX_BYTES)


class ChartsSaved(BaseModel):
    saved: list[str]


@router.get("/charts", operation_id="listCharts", response_model=list[Chart],
            **allow(*EVERYONE))
def list_charts(db: Db) -> list[Chart]:
    return all_charts(db)


# Numbers as computed: a coordinate given as an int stays one (a float field would add ".0").
Point = tuple[Number, Number]


class ChartProperties(BaseModel):
    title: str
    contexts: list[str]
    kind: str
    norms: list[ChartNorm]


class PolygonGeometry(BaseModel):
    """A GeoJSON Polygon: rings of [longitude, latitude], each closed (last point = first)."""

    type: Literal["Polygon"]
    coordinates: list[list[Point]]


class ChartFeature(BaseModel):
    """A chart as a GeoJSON Feature (orders/geo_formats.py, areas_to_geojson)."""

    type: Literal["Feature"]
    id: str
    properties: ChartProperties
    geometry: PolygonGeometry


class ChartsGeoJsonOut(BaseModel):
    """The registry as one GeoJSON FeatureCollection (RFC 7946), a Polygon feature per chart."""

    model_config = ConfigDict(extra="allow")
    type: Literal["FeatureCollection"]
    features: list[Annotated[dict[str, Any], SchemaOf(ChartFeature)]]


class PlanLegOut(BaseModel):
    goal: str
    outcome: str
    to: str
    start: Point
    end: Point
    length_m: Number


class PlanAreaOut(BaseModel):
    id: str
    title: str
    contexts: list[str]
    polygon: list[Point]


class PlanChartOut(BaseModel):
    id: str
    title: str
    kind: str
    contexts: list[str]
    polygon: list[Point]


class PlanPlaceOut(BaseModel):
    """Where a goal runs: its area, its behaviour and the start and end of its sweep."""

    goal: str
    area: str | None
    behavior: str | None
    start: Point
    end: Point


class PlanEdgeOut(BaseModel):
    goal: str
    outcome: str
    to: str


class PlanCrossingOut(BaseModel):
    """A GEO finding as drawn: the edge or goal that crosses and the area it crosses."""

    subjects: list[str]
    message: str
    area: str | None
    edge: PlanEdgeOut | None
    goal: str | None
    element: str | None


class PlanViewOut(BaseModel):
    """What the plan view draws: areas, charts, where each goal runs, each outcome edge's leg,
    the crossings (GEO findings) and a coastline from the land mask, in degrees."""

    areas: list[PlanAreaOut]
    charts: list[PlanChartOut]
    places: list[PlanPlaceOut]
    legs: list[PlanLegOut]
    crossings: list[PlanCrossingOut]
    coastline: list[tuple[Point, Point]]
    box: tuple[Number, Number, Number, Number] | None


@router.get("/charts/geojson", operation_id="exportCharts", response_model=ChartsGeoJsonOut,
            response_model_exclude_unset=True, **allow(*EVERYONE))
def export_charts(db: Db) -> Response:
    # Built as plain JSON and answered as is: validating 10,000 features against the response
    # model again took seconds; ChartsGeoJsonOut still documents it, and
    # tests/web/test_charts.py checks that the answer matches it.
    return JSONResponse(areas_to_geojson(all_charts(db)))


@router.get("/charts/kml", operation_id="exportChartsKml", response_class=Response,
            responses={200: {"content": {KML_MEDIA_TYPE: {"schema": {"type": "string"}}}}},
            **allow(*EVERYONE))
def export_charts_kml(db: Db) -> Response:
    """The registry as one KML document, a Polygon placemark per chart with the same
    counterclockwise (longitude, latitude) rings as the GeoJSON export."""
    return Response(charts_to_kml(all_charts(db)), media_type=KML_MEDIA_TYPE, headers={
        "Content-Disposition": 'attachment; filename="charts.kml"',
        "X-Content-Type-Options": "nosniff"})


@router.put("/charts/{chart_id}", operation_id="putChart", response_model=Chart,
            **allow(*ADMINS))
def put_chart(chart_id: str, body: Chart, principal: CurrentPrincipal, db: Db,
              services: Services) -> Chart:
    if body.id != chart_id:
        raise Invalid(f"the chart's id {body.id!r} differs from {chart_id!r}")
    if len(body.polygon) < 3:
        raise Unprocessable(f"chart {chart_id}: a polygon needs at least three points")
    save_charts(db, [body])
    record(db, kind="chart.saved", actor=principal.user, detail={"charts": [chart_id]},
           signer=services.signer)
    return body


@router.post("/charts/import", operation_id="importCharts", response_model=ChartsSaved,
             **allow(*ADMINS))
def import_charts(body: ChartImport, principal: CurrentPrincipal, db: Db,
                  services: Services) -> ChartsSaved:
    try:
        reader = charts_from_kml if body.format == "kml" else charts_from_geojson
        charts = reader(body.content)
    except GeoFormatError as exc:
        raise Unprocessable(f"{body.format} charts: {exc}") from None
    saved = save_charts(db, charts)
    record(db, kind="chart.saved", actor=principal.user, detail={"charts": saved[:1000]},
           signer=services.signer)
    return ChartsSaved(saved=saved)


@router.delete("/charts/{chart_id}", operation_id="deleteChart", status_code=204,
               **allow(*ADMINS))
def remove_chart(chart_id: str, principal: CurrentPrincipal, db: Db, services: Services) -> None:
    if not delete_chart(db, chart_id):
        raise NotFound(f"there is no chart {chart_id!r}")
    record(db, kind="chart.deleted", actor=principal.user, detail={"charts": [chart_id]},
           signer=services.signer)


PLAN_ROUTE = allow(*EVERYONE)
# The body is read raw (its size bounded first), so its schema is stated here: the orders.
PLAN_ROUTE["openapi_extra"]["requestBody"] = {"required": True, "content": {
    "application/json": {"schema": {"$ref": "#/components/schemas/Orders"}}}}


@router.post("/plan-view", operation_id="planView", response_model=PlanViewOut,
             **computing(PLAN_ROUTE))
async def post_plan_view(request: Request, db: Db) -> dict[str, Any]:
    """The plan view of orders (with the registry's charts in use copied in, as validation)."""
    data = await request.body()
    if len(data) > 20 * MAX_BYTES:
        raise HTTPException(413, "the orders are too large for a plan view")
    # Reading megabytes of orders and the registry is no work for the event loop: it would
    # stall every other request of this process meanwhile.
    return await run_in_threadpool(_plan_view, db, data)


def _plan_view(db: Db, data: bytes) -> dict[str, Any]:
    return plan_view(with_registry(db, read_json(data)))
