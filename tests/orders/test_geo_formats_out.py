"""Charts written out: GeoJSON as RFC 7946 asks (judged by geojson-validator and GEOS through
shapely), KML with the same rings and the user's text as text (read back by fastkml)."""

from __future__ import annotations

import json
import warnings
from typing import Any

import geojson_validator
import pytest
from defusedxml.ElementTree import fromstring
from hypothesis import given, settings
from hypothesis import strategies as st
from shapely.geometry import LinearRing, Polygon

from countersign.orders.geo_formats import areas_to_geojson, charts_to_kml
from countersign.orders.model import Chart

with warnings.catch_warnings():
    warnings.simplefilter("ignore")  # fastkml's notice that lxml is absent
    from fastkml import containers, data, features, kml

geojson_validator.configure_logging(enabled=False)

# (latitude, longitude) as orders hold them; longitudes over 90 so that a ring written as
# (latitude, longitude) would leave the valid range and be caught.
CLOCKWISE = [(10.0, 120.0), (11.0, 120.0), (11.0, 121.0), (10.0, 121.0)]
COUNTERCLOCKWISE = [(10.0, 120.0), (10.0, 121.0), (11.0, 121.0), (11.0, 120.0)]
TITLE = '<b>Range</b> & "quoted" ]]> <!-- not a comment -->'


def _chart(polygon: list[tuple[float, float]], chart_id: str = "Z1") -> Chart:
    return Chart(id=chart_id, title=TITLE, polygon=polygon, kind="keep_out",
                 contexts=["keep_out", "a<b>"],
                 norms=[{"id": "n1", "forbidden": "behavior == 'transit'", "text": "<no>"}])


def _rings(collection: dict[str, Any]) -> list[list[tuple[float, float]]]:
    return [[tuple(p) for p in f["geometry"]["coordinates"][0]]  # type: ignore[misc]
            for f in collection["features"]]


def test_geojson_out_is_rfc_7946_whatever_the_winding_in() -> None:
    collection = areas_to_geojson([_chart(CLOCKWISE, "CW"), _chart(COUNTERCLOCKWISE, "CCW")])
    verdict = geojson_validator.validate_geometries(json.loads(json.dumps(collection)))
    assert verdict["invalid"] == {}, verdict  # unclosed, too few points, exterior_not_ccw
    assert "outside_lat_lon_boundaries" not in verdict["problematic"], verdict
    assert geojson_validator.validate_structure(collection) == {}
    for ring in _rings(collection):
        assert ring[0] == (120.0, 10.0) and ring[-1] == ring[0]  # lon/lat, closed
        assert LinearRing(ring).is_ccw


lat = st.floats(-80, 80, allow_nan=False)
lon = st.floats(-170, 170, allow_nan=False)


@settings(max_examples=60, deadline=None)
@given(st.lists(st.tuples(lat, lon), min_size=3, max_size=10, unique=True))
def test_every_ring_out_is_counterclockwise_in_both_formats(
        polygon: list[tuple[float, float]]) -> None:
    chart = _chart(polygon)
    ring = _rings(areas_to_geojson([chart]))[0]
    # Collinear, or crossing or touching itself, a ring has no winding to check (CI drew one
    # whose last point lay 1.9e-183 from its first edge: GEOS calls it clockwise both ways).
    assert LinearRing(ring).is_ccw or Polygon(ring).area == 0 or not Polygon(ring).is_valid
    assert ring[0] == (polygon[0][1], polygon[0][0]) and ring[-1] == ring[0]
    assert _kml_placemarks(charts_to_kml([chart]))[0].geometry.exterior.coords == tuple(ring)


def _kml_placemarks(text: str) -> list[Any]:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        document = kml.KML.from_string(text, strict=True)
    (folder,) = document.features
    assert isinstance(folder, containers.Document)
    return [f for f in folder.features if isinstance(f, features.Placemark)]


def test_kml_out_has_the_geojson_geometry_and_text_as_text() -> None:
    charts = [_chart(CLOCKWISE, "CW"), _chart(COUNTERCLOCKWISE, "CCW")]
    text = charts_to_kml(charts)
    marks = _kml_placemarks(text)
    assert [m.id for m in marks] == ["CW", "CCW"]
    assert [m.geometry.exterior.coords for m in marks] == \
        [tuple(r) for r in _rings(areas_to_geojson(charts))]
    for mark in marks:
        assert mark.name == TITLE  # the markup came back as the characters typed
        values = {d.name: d.value for d in mark.extended_data.elements
                  if isinstance(d, data.Data)}
        assert values["contexts"] == "keep_out,a<b>" and values["kind"] == "keep_out"
        assert json.loads(values["norms"])[0]["text"] == "<no>"
    # Only the elements we wrote: no element or comment came out of the user's text.
    tags = {element.tag.split("}")[-1] for element in fromstring(text).iter()}
    assert tags == {"kml", "Document", "Placemark", "name", "ExtendedData", "Data", "value",
                    "Polygon", "outerBoundaryIs", "LinearRing", "coordinates"}


@pytest.mark.parametrize("polygon", [CLOCKWISE, COUNTERCLOCKWISE], ids=["cw", "ccw"])
def test_the_orders_keep_the_ring_they_were_given(polygon: list[tuple[float, float]]) -> None:
    chart = _chart(polygon)
    areas_to_geojson([chart])
    charts_to_kml([chart])
    assert chart.polygon == polygon  # turned on the way out only
