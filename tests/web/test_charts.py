"""The chart registry over the API: admins write, everyone reads, missions use and sign it."""

from __future__ import annotations

import asyncio
import json
from typing import Any

import pytest
from sqlalchemy.orm import Session

from countersign.orders.examples import example_bytes
from countersign.orders.model import Orders
from countersign.web.routes import charts as chart_routes

from .conftest import World
from .described import assert_described
from .write_lock import record_opens

# A keep-out box across the exemplar's legs from G4 (and G2 on fail) to G5.
KEEP_OUT = {"type": "FeatureCollection", "features": [{
    "type": "Feature", "id": "RANGE",
    "properties": {"title": "Firing range", "kind": "keep_out", "contexts": ["keep_out"]},
    "geometry": {"type": "Polygon", "coordinates": [[
        [-121.845, 36.75], [-121.825, 36.75], [-121.825, 36.77], [-121.845, 36.77],
        [-121.845, 36.75]]]}}]}


def _import(world: World, role: str, content: str, fmt: str = "geojson") -> object:
    return world.client(role).post("/api/charts/import",
                                   json={"format": fmt, "content": content})


def test_only_admins_write_and_everyone_reads(world: World) -> None:
    assert _import(world, "operator", json.dumps(KEEP_OUT)).status_code == 403  # type: ignore[attr-defined]
    saved = _import(world, "admin", json.dumps(KEEP_OUT))
    assert saved.status_code == 200, saved.text  # type: ignore[attr-defined]
    assert saved.json() == {"saved": ["RANGE"]}  # type: ignore[attr-defined]
    for role in ("operator", "supervisor", "auditor"):
        listed = world.client(role).get("/api/charts").json()
        assert [c["id"] for c in listed] == ["RANGE"] and listed[0]["kind"] == "keep_out"
    exported = world.client("auditor").get("/api/charts/geojson").json()
    assert exported["features"][0]["id"] == "RANGE"
    _assert_whole_geojson(world, exported)
    assert world.client("operator").delete("/api/charts/RANGE").status_code == 403
    assert world.client("admin").delete("/api/charts/RANGE").status_code == 204
    assert world.client("admin").get("/api/charts").json() == []


def _assert_whole_geojson(world: World, exported: dict[str, Any]) -> None:
    """The export is what areas_to_geojson makes of the registry, and ChartFeature describes
    each of its features exactly."""
    from countersign.orders.geo_formats import areas_to_geojson
    from countersign.store.charts import all_charts
    from countersign.web.routes.charts import ChartFeature

    with world.database.session() as db:
        expected = areas_to_geojson(all_charts(db))
    assert exported == expected
    assert_described(list[ChartFeature], expected["features"])


def test_bad_chart_files_are_problems_naming_where(world: World) -> None:
    bad = {"type": "FeatureCollection", "features": [{
        "type": "Feature", "id": "x", "properties": {},
        "geometry": {"type": "LineString", "coordinates": [[0, 0], [1, 1]]}}]}
    response = _import(world, "admin", json.dumps(bad))
    assert response.status_code == 422  # type: ignore[attr-defined]
    assert "feature 0" in response.json()["detail"]  # type: ignore[attr-defined]
    bomb = '<!DOCTYPE kml [<!ENTITY a "b">]><kml>&a;</kml>'
    response = _import(world, "admin", bomb, "kml")
    assert response.status_code == 422 and "Traceback" not in response.text  # type: ignore[attr-defined]


def test_charts_in_use_are_checked_and_copied_into_the_version(world: World) -> None:
    assert _import(world, "admin", json.dumps(KEEP_OUT)).status_code == 200  # type: ignore[attr-defined]
    client = world.client("operator")
    report = client.post("/api/validate", content=example_bytes("search-and-sample")).json()
    geo = sorted(tuple(f["subjects"]) for f in report["findings"] if f["code"] == "GEO")
    assert geo == [("G2", "fail", "RANGE"), ("G4", "fail", "RANGE"),
                   ("G4", "succeed", "RANGE"), ("G4", "violate", "RANGE")]
    assert report["ok"] is False
    orders = json.loads(example_bytes("search-and-sample"))
    orders["id"] = "charted"
    # Leaving the chart out of the orders does not leave it out of the check.
    orders["charts"] = []
    assert client.post("/api/missions", json=orders).status_code == 201
    draft = client.get("/api/missions/charted").json()["orders"]
    assert [c["id"] for c in draft["charts"]] == ["RANGE"]
    assert client.post("/api/missions/charted/versions").status_code == 201
    version = client.get("/api/missions/charted/versions/1").json()
    assert [c["id"] for c in version["orders"]["charts"]] == ["RANGE"]


def test_plan_view_has_legs_crossings_and_coastline(world: World) -> None:
    assert _import(world, "admin", json.dumps(KEEP_OUT)).status_code == 200  # type: ignore[attr-defined]
    view = world.client("supervisor").post(
        "/api/plan-view", content=example_bytes("search-and-sample")).json()
    assert len(view["legs"]) == 12 and view["charts"][0]["id"] == "RANGE"
    crossed = {(c["edge"]["goal"], c["edge"]["outcome"]) for c in view["crossings"]}
    assert crossed == {("G2", "fail"), ("G4", "succeed"), ("G4", "fail"), ("G4", "violate")}
    assert view["coastline"], "Monterey Bay has a coast within the view"


def test_plan_view_answer_is_the_whole_plan_view(world: World) -> None:
    """The route's response model documents the plan view for the front end's types; it must not
    drop or retype a field (a response model filters what it does not declare, silently)."""
    from countersign.orders.reader import orders_from_data
    from countersign.verify.plan_view import plan_view

    assert _import(world, "admin", json.dumps(KEEP_OUT)).status_code == 200  # type: ignore[attr-defined]
    answer = world.client("operator").post(
        "/api/plan-view", content=example_bytes("search-and-sample"))
    assert answer.status_code == 200, answer.text
    charts = world.client("operator").get("/api/charts").json()
    orders = json.loads(example_bytes("search-and-sample"))
    expected = plan_view(orders_from_data({**orders, "charts": charts}))
    # Compared as text too: a coordinate given as an int stays an int (no ".0" added).
    assert answer.json() == expected
    assert answer.text == json.dumps(expected, separators=(",", ":"), ensure_ascii=False)
    assert answer.json()["places"] and answer.json()["crossings"][0]["element"]


def test_charts_export_as_counterclockwise_geojson_and_the_same_kml(world: World) -> None:
    import warnings

    from shapely.geometry import LinearRing

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # fastkml's notice that lxml is absent
        from fastkml import kml

    clockwise = json.loads(json.dumps(KEEP_OUT))
    feature = clockwise["features"][0]
    ring = feature["geometry"]["coordinates"][0]
    ring[1:-1] = reversed(ring[1:-1])
    assert not LinearRing(ring).is_ccw
    feature["properties"]["title"] = "Firing <range> & co"
    assert _import(world, "admin", json.dumps(clockwise)).status_code == 200  # type: ignore[attr-defined]
    geojson = world.client("auditor").get("/api/charts/geojson").json()
    out = geojson["features"][0]["geometry"]["coordinates"][0]
    assert LinearRing(out).is_ccw and out[0] == ring[0] and out[-1] == out[0]
    assert world.client().get("/api/charts/kml").status_code == 401
    for role in ("operator", "supervisor", "auditor", "admin"):
        response = world.client(role).get("/api/charts/kml")
        assert response.status_code == 200, response.text
        assert response.headers["content-type"] == "application/vnd.google-earth.kml+xml"
        assert response.headers["x-content-type-options"] == "nosniff"
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        (mark,) = kml.KML.from_string(response.text, strict=True).features[0].features
    assert (mark.id, mark.name) == ("RANGE", "Firing <range> & co")
    assert [list(p) for p in mark.geometry.exterior.coords] == out


def test_geojson_nested_two_thousand_deep_is_a_422_naming_nesting(world: World) -> None:
    deep = '{"type": "FeatureCollection", "features": ' + "[" * 2000 + "]" * 2000 + "}"
    response = _import(world, "admin", deep)
    assert response.status_code == 422, response.text  # type: ignore[attr-defined]
    assert "nested" in response.text  # type: ignore[attr-defined]


def test_the_plan_view_reads_off_the_event_loop_and_takes_no_write_lock(
        world: World, monkeypatch: pytest.MonkeyPatch) -> None:
    """Reading up to 9 MiB of orders on the event loop stalled every request of the process,
    and the plan view's session took the write lock (on SQLite, waited for on the event loop
    itself) though it stores nothing."""
    opened = record_opens(world, monkeypatch)
    on_the_loop: list[bool] = []
    real_registry = chart_routes.with_registry

    def registry(db: Session, orders: Orders) -> Orders:
        try:
            asyncio.get_running_loop()
            on_the_loop.append(True)
        except RuntimeError:
            on_the_loop.append(False)
        return real_registry(db, orders)

    monkeypatch.setattr(chart_routes, "with_registry", registry)
    viewed = world.client("auditor").post("/api/plan-view",
                                          content=example_bytes("search-and-sample"))
    assert viewed.status_code == 200, viewed.text
    assert (opened, on_the_loop) == ([False], [False])
