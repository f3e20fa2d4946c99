"""GeoJSON and KML charts: round trips keep the polygons, bad input is refused by name."""

from __future__ import annotations

import json

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from countersign.orders.avcl import read_avcl
from countersign.orders.avcl_writer import write_avcl
from countersign.orders.canonical import digest
from countersign.orders.geo_formats import (
    GeoFormatError,
    areas_to_geojson,
    charts_from_geojson,
    charts_from_kml,
    charts_to_kml,
)
from countersign.orders.model import Chart, Orders
from countersign.orders.reader import OrdersReadError
from countersign.orders.turtle import read_turtle, write_turtle

lat = st.floats(-89.9, 89.9, allow_nan=False)
lon = st.floats(-179.9, 179.9, allow_nan=False)
rings = st.lists(st.tuples(lat, lon), min_size=3, max_size=12, unique=True)


def _chart(polygon: list[tuple[float, float]]) -> Chart:
    return Chart(id="Z1", title="Zone", polygon=polygon, contexts=["keep_out", "x"],
                 kind="keep_out", norms=[{"id": "n1", "forbidden": "behavior == 'transit'"}])


def _close(a: list[tuple[float, float]], b: list[tuple[float, float]]) -> bool:
    return len(a) == len(b) and all(
        abs(p[0] - q[0]) <= 1e-9 and abs(p[1] - q[1]) <= 1e-9 for p, q in zip(a, b, strict=True))


def _same_ring(back: list[tuple[float, float]], polygon: list[tuple[float, float]]) -> bool:
    """The same ring from the same first point, wound either way (the writers turn it
    counterclockwise)."""
    return _close(back, polygon) or _close(back, [polygon[0], *reversed(polygon[1:])])


@settings(max_examples=60, deadline=None)
@given(rings)
def test_geojson_round_trip_keeps_polygon(polygon: list[tuple[float, float]]) -> None:
    if polygon[0] == polygon[-1]:
        polygon = polygon[:-1]
    chart = _chart(polygon)
    back = charts_from_geojson(json.dumps(areas_to_geojson([chart])))
    assert len(back) == 1 and _same_ring(back[0].polygon, chart.polygon)
    assert back[0].contexts == chart.contexts and back[0].norms == chart.norms


@settings(max_examples=60, deadline=None)
@given(rings)
def test_kml_round_trip_keeps_polygon(polygon: list[tuple[float, float]]) -> None:
    if polygon[0] == polygon[-1]:
        polygon = polygon[:-1]
    chart = _chart(polygon)
    back = charts_from_kml(charts_to_kml([chart]))
    assert len(back) == 1 and _same_ring(back[0].polygon, chart.polygon)
    assert (back[0].kind, back[0].contexts, back[0].norms) == ("keep_out", chart.contexts,
                                                                chart.norms)


def test_geojson_is_lon_lat_and_closed() -> None:
    data = areas_to_geojson([_chart([(10.0, 20.0), (11.0, 20.0), (11.0, 21.0)])])
    ring = data["features"][0]["geometry"]["coordinates"][0]
    assert ring[0] == [20.0, 10.0] and ring[-1] == ring[0]


def test_kml_with_entities_is_refused_before_expansion() -> None:
    bomb = ('<?xml version="1.0"?><!DOCTYPE kml [<!ENTITY a "aaaaaaaaaa">'
            '<!ENTITY b "&a;&a;&a;&a;&a;&a;&a;&a;&a;&a;">]>'
            '<kml xmlns="http://www.opengis.net/kml/2.2"><Document><name>&b;</name>'
            '</Document></kml>')
    with pytest.raises(GeoFormatError, match="EntitiesForbidden"):
        charts_from_kml(bomb)


def test_kml_forbids_shortcut_and_multipolygon() -> None:
    kml = ('<kml xmlns="http://www.opengis.net/kml/2.2"><Document><Folder>'
           '<Placemark id="mpa"><name>Reserve</name><ExtendedData>'
           '<Data name="contexts"><value>marine_protected_area</value></Data>'
           '<Data name="forbids"><value>transit, sample</value></Data></ExtendedData>'
           '<MultiGeometry><Polygon><outerBoundaryIs><LinearRing><coordinates>'
           '0,0 1,0 1,1 0,0</coordinates></LinearRing></outerBoundaryIs></Polygon>'
           '<Polygon><outerBoundaryIs><LinearRing><coordinates>'
           '5,5 6,5 6,6 5,5</coordinates></LinearRing></outerBoundaryIs></Polygon>'
           '</MultiGeometry></Placemark></Folder></Document></kml>')
    charts = charts_from_kml(kml)
    assert [c.id for c in charts] == ["mpa-1", "mpa-2"]
    assert [n.forbidden for n in charts[0].norms] == ["behavior == 'transit'",
                                                      "behavior == 'sample'"]
    assert charts[1].polygon == [(5.0, 5.0), (5.0, 6.0), (6.0, 6.0)]


@pytest.mark.parametrize(("text", "words"), [
    ('{"type": "FeatureCollection", "features": [{"type": "Feature", "properties": {},'
     ' "geometry": {"type": "Point", "coordinates": [1, 2]}}]}', "not Point"),
    ('{"type": "FeatureCollection", "features": [{"type": "Feature", "id": "a",'
     ' "properties": {}, "geometry": {"type": "Polygon", "coordinates":'
     ' [[[0,0],[1,0],[1,1],[0,0]], [[0.1,0.1],[0.2,0.1],[0.2,0.2],[0.1,0.1]]]}}]}', "holes"),
    ('{"type": "FeatureCollection", "features": [{"type": "Feature", "id": "a",'
     ' "properties": {}, "geometry": {"type": "Polygon", "coordinates":'
     ' [[[0,0],[1,0],[1,100],[0,0]]]}}]}', "latitude"),
    ("[1, 2", "not JSON"),
    ('{"type": "Topology"}', "FeatureCollection"),
    ('{"type": "Feature", "id": "a", "properties": {},'
     ' "geometry": {"type": "MultiPolygon", "coordinates": []}}', "feature 0: no polygon"),
    ('{"type": "Feature", "id": "a", "properties": {},'
     ' "geometry": {"type": "Polygon", "coordinates": []}}', "feature 0: polygon 0 has no ring"),
    ('{"type": "Feature", "id": "a", "properties": {},'
     ' "geometry": {"type": "MultiPolygon", "coordinates": [[[[0,0],[1,0],[1,1],[0,0]]], []]}}',
     "feature 0: polygon 1 has no ring"),
])
def test_bad_geojson_names_what_and_where(text: str, words: str) -> None:
    with pytest.raises(GeoFormatError, match=words):
        charts_from_geojson(text)


CHARTS = [
    {"id": "K1", "title": "Range <west> & \"quoted\"", "kind": "keep_out",
     "polygon": [[36.8, -122.2], [36.8, -122.18], [36.6, -122.18], [36.6, -122.2]],
     "contexts": ["range"], "norms": [{"id": "N1", "forbidden": "behavior == 'transit'"}]},
    {"id": "K2", "polygon": [[36.1, -122.1], [36.2, -122.1], [36.2, -122.0]]},
]


def _charted() -> Orders:
    return Orders.model_validate({
        "id": "charted", "title": "Charted", "start": "G1", "charts": CHARTS,
        "goals": [{"id": "G1", "title": "Go", "behavior": "transit",
                   "next": {"succeed": "COMPLETE", "fail": "ABORT", "violate": "ABORT"}}],
    })


def test_turtle_carries_the_charts() -> None:
    orders = _charted()
    back = read_turtle(write_turtle(orders).encode()).orders
    assert back.charts == orders.charts
    assert digest(back) == digest(orders)


def test_avcl_carries_the_charts() -> None:
    orders = _charted()
    back = read_avcl(write_avcl(orders).encode()).orders
    assert [c.model_dump() for c in back.charts] == [c.model_dump() for c in orders.charts]


def test_an_avcl_chart_that_is_not_json_is_named() -> None:
    written = write_avcl(_charted())
    text = written.replace("&quot;id&quot;:&quot;K2", "&quot;id&quot; &quot;K2")
    assert text != written
    with pytest.raises(OrdersReadError, match="chart is not JSON"):
        read_avcl(text.encode())


def test_geojson_nested_two_thousand_deep_is_refused_by_name() -> None:
    # The plain parser recursed into a RecursionError (a 500 over the API).
    deep = '{"type": "FeatureCollection", "features": ' + "[" * 2000 + "]" * 2000 + "}"
    with pytest.raises(GeoFormatError, match="nested"):
        charts_from_geojson(deep)


def test_multipolygon_of_many_parts_is_refused_not_split_into_charts() -> None:
    square = [[[0.0, 0.0], [0.001, 0.0], [0.001, 0.001], [0.0, 0.0]]]
    feature = {"type": "Feature", "id": "MANY", "properties": {"kind": "keep_out"},
               "geometry": {"type": "MultiPolygon", "coordinates": [square] * 1001}}
    with pytest.raises(GeoFormatError, match="polygons"):
        charts_from_geojson(json.dumps(feature))


def _kml_placemarks(count: int, ring: str = "0,0 0.001,0 0.001,0.001 0,0") -> str:
    marks = "".join(f'<Placemark id="p{n}"><Polygon><outerBoundaryIs><LinearRing><coordinates>'
                    f"{ring}</coordinates></LinearRing></outerBoundaryIs></Polygon></Placemark>"
                    for n in range(count))
    return f'<kml xmlns="http://www.opengis.net/kml/2.2"><Document>{marks}</Document></kml>'


def test_kml_placemarks_are_bounded_like_geojson_parts() -> None:
    # a KML import's placemarks had only the 10,000-feature bound.
    assert len(charts_from_kml(_kml_placemarks(3))) == 3
    with pytest.raises(GeoFormatError, match="1,000 polygons"):
        charts_from_kml(_kml_placemarks(1001))
    many_vertices = " ".join(f"{i / 1e6},0" for i in range(100_001)) + " 0,0.001 0,0"
    with pytest.raises(GeoFormatError, match="100,000 vertices"):
        charts_from_kml(_kml_placemarks(1, many_vertices))
