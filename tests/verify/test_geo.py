"""GEO: every outcome edge's leg, sweep and loiter against areas, charts and land."""

from __future__ import annotations

import math
from typing import Any

from hypothesis import given, settings
from hypothesis import strategies as st
from shapely.geometry import LineString, box

from countersign.orders.model import Orders
from countersign.verify.geo import check_geo, crosses
from countersign.verify.legs import leg_lengths
from countersign.verify.report import validate


def _box(south: float, west: float, north: float, east: float) -> list[list[float]]:
    return [[north, west], [north, east], [south, east], [south, west]]


def _orders(**extra: Any) -> Orders:
    """A west area, an east area and a north area; between west and east lies a strip."""
    data: dict[str, Any] = {
        "id": "geo", "start": "G1",
        "goals": [
            {"id": "G1", "behavior": "transit", "area": "W",
             "next": {"succeed": "G2", "fail": "G3", "violate": "G2"}},
            {"id": "G2", "behavior": "transit", "area": "E",
             "next": {"succeed": "COMPLETE", "fail": "ABORT", "violate": "ABORT"}},
            {"id": "G3", "behavior": "transit", "area": "N",
             "next": {"succeed": "G2", "fail": "ABORT", "violate": "ABORT"}},
        ],
        "areas": [
            {"id": "W", "polygon": _box(36.70, -122.30, 36.72, -122.28)},
            {"id": "E", "polygon": _box(36.70, -122.10, 36.72, -122.08)},
            {"id": "N", "polygon": _box(36.90, -122.30, 36.92, -122.28)},
        ],
    }
    for key, value in extra.items():
        data[key] = data.get(key, []) + value if isinstance(value, list) else value
    return Orders.model_validate(data)


STRIP = {"id": "K", "title": "Range", "polygon": _box(36.60, -122.20, 36.80, -122.18)}


def _geo(orders: Orders) -> list[tuple[str, ...]]:
    return sorted(f.subjects for f in check_geo(orders) if f.code == "GEO")


def test_keep_out_chart_breaks_exactly_the_edges_that_cross_it() -> None:
    # W centre (36.71, -122.29) to E centre (36.71, -122.09) runs through the strip at
    # -122.20..-122.18; W to N runs north at -122.29 and misses it; N to E runs from
    # (36.91, -122.29) to (36.71, -122.09): at -122.19 it is at 36.81, north of the strip.
    orders = _orders(charts=[{**STRIP, "kind": "keep_out"}])
    assert _geo(orders) == [("G1", "succeed", "K"), ("G1", "violate", "K")]


def test_leg_finding_names_edge_area_and_a_path_that_takes_it() -> None:
    orders = _orders(areas=[{**STRIP, "contexts": ["keep_out"]}])
    finding = next(f for f in check_geo(orders) if f.subjects == ("G1", "succeed", "K"))
    assert finding.severity == "error"
    assert finding.details["edge"] == {"goal": "G1", "outcome": "succeed", "to": "G2"}
    path = finding.details["path"]
    assert path["goals"][:2] == ["G1", "G2"] and path["outcomes"][0] == "succeed"
    assert path["terminal"] in {"COMPLETE", "ABORT"}
    assert "G1 succeed, G2" in finding.message
    assert any(f.code == "GEO" for f in validate(orders).findings)


def test_norm_forbidding_transit_of_a_protected_area_breaks_only_crossing_edges() -> None:
    # The reserve spans 36.75..36.95 at -122.20..-122.18: N to E crosses it (36.81 there),
    # W to E passes south of it, W to N stays west of it.
    reserve = {"id": "MPA", "polygon": _box(36.75, -122.20, 36.95, -122.18),
               "contexts": ["marine_protected_area"]}
    norm = {"id": "N1", "context": "marine_protected_area",
            "forbidden": "behavior == 'transit'", "text": "No transit of the reserve"}
    assert _geo(_orders(areas=[reserve], norms=[norm])) == [("G3", "succeed", "MPA")]
    # A norm on another behaviour, or no norm, forbids no leg.
    other = {**norm, "forbidden": "behavior == 'sample'"}
    assert _geo(_orders(areas=[reserve], norms=[other])) == []
    assert _geo(_orders(areas=[reserve])) == []


def test_chart_norm_forbids_the_behaviour_of_a_sweep_through_it() -> None:
    orders = _orders(charts=[{"id": "C", "polygon": _box(36.705, -122.295, 36.715, -122.285),
                              "kind": "protected_area",
                              "norms": [{"id": "no-search",
                                         "forbidden": "behavior == 'area_search'"}]}])
    searching = orders.model_copy(update={"goals": [
        orders.goals[0].model_copy(update={"behavior": "area_search"}), *orders.goals[1:]]})
    assert _geo(orders) == []
    assert _geo(searching) == [("G1", "C")]


def test_leg_across_land_is_geo_and_coastal_legs_are_not() -> None:
    # Across the Florida peninsula at 27 N, from the Gulf to the Atlantic.
    florida = Orders.model_validate({
        "id": "fl", "start": "G1",
        "goals": [{"id": "G1", "area": "GULF",
                   "next": {"succeed": "G2", "fail": "ABORT", "violate": "ABORT"}},
                  {"id": "G2", "area": "ATL",
                   "next": {"succeed": "COMPLETE", "fail": "ABORT", "violate": "ABORT"}}],
        "areas": [{"id": "GULF", "polygon": _box(26.99, -83.01, 27.01, -82.99)},
                  {"id": "ATL", "polygon": _box(26.99, -79.81, 27.01, -79.79)}],
    })
    assert _geo(florida) == [("G1", "succeed", "land")]
    assert _geo(_orders()) == []  # off Monterey, at sea


def test_budget_counts_the_geodesic_leg() -> None:
    orders = _orders(vehicles=[{"id": "v", "speed_mps": 2.0,
                                "budget": {"duration_s": 1_000_000}}], vehicle="v")
    data = orders.model_dump(mode="json", exclude_unset=True)
    for goal in data["goals"]:
        goal["cost"] = {"duration_s": 0, "energy_wh": 0}
    orders = Orders.model_validate(data)
    lengths = leg_lengths(orders)
    report = validate(orders)
    assert report.costs is not None
    worst = report.costs["duration_s"]
    expected = max(lengths[("G1", "succeed")],
                   lengths[("G1", "fail")] + lengths[("G3", "succeed")]) / 2.0
    assert math.isclose(worst.total, expected, rel_tol=1e-9)
    # Independent check of the geodesic length: haversine on the mean radius within 0.5 %.
    lat = math.radians(36.71)
    haversine = 6_371_008.8 * math.radians(0.2) * math.cos(lat)
    assert abs(lengths[("G1", "succeed")] - haversine) / haversine < 0.005


square = st.tuples(st.floats(-1e4, 1e4), st.floats(-1e4, 1e4), st.floats(10, 1e4))


@settings(max_examples=200, deadline=None)
@given(square, st.floats(0, 1), st.floats(0, 1), st.floats(0, 1), st.floats(0, 1))
def test_leg_entirely_inside_is_not_a_crossing(
    sq: tuple[float, float, float], a: float, b: float, c: float, d: float
) -> None:
    x, y, size = sq
    shape = box(x, y, x + size, y + size)
    leg = LineString([(x + a * size, y + b * size), (x + c * size, y + d * size)])
    assert not crosses(leg, shape)


@settings(max_examples=200, deadline=None)
@given(square, st.floats(-2, 3), st.floats(-2, 3), st.integers(0, 3))
def test_leg_touching_an_edge_only_is_not_a_crossing(
    sq: tuple[float, float, float], s: float, t: float, side: int
) -> None:
    x, y, size = sq
    shape = box(x, y, x + size, y + size)
    # Along one side's line (possibly beyond the corners), or touching from outside at a point.
    ends = {0: ((x + s * size, y), (x + t * size, y)),
            1: ((x + size, y + s * size), (x + size, y + t * size)),
            2: ((x + s * size, y + size), (x + t * size, y + size)),
            3: ((x - size, y - size * (1 + abs(s))), (x, y))}[side]
    if ends[0] == ends[1]:
        return
    assert not crosses(LineString(ends), shape)


@settings(max_examples=200, deadline=None)
@given(square, st.floats(0.01, 0.99), st.floats(0.01, 0.99), st.floats(1.01, 5))
def test_leg_from_inside_to_outside_is_a_crossing(
    sq: tuple[float, float, float], a: float, b: float, far: float
) -> None:
    x, y, size = sq
    shape = box(x, y, x + size, y + size)
    assert crosses(LineString([(x + a * size, y + b * size), (x + far * size, y + b * size)]),
                   shape)


def test_the_frame_projects_as_pyproj_chooses_bit_for_bit() -> None:
    """legs._forward writes out the pipeline PROJ chooses from EPSG:4326 to the frame's
    azimuthal equidistant CRS (to skip PROJ's database): the same metres and degrees, bit for
    bit, both ways, for frames anywhere (poles and antimeridian too) and points around them."""
    import random

    from pyproj import CRS, Transformer

    from countersign.verify.legs import _forward

    rng = random.Random(20261204)
    frames = [(90.0, 0.0), (-90.0, 180.0), (0.0, -180.0), (36.75, -121.9), (1e-05, -0.0001)]
    frames += [(round(rng.uniform(-90, 90), 4), round(rng.uniform(-180, 180), 4))
               for _ in range(40)]
    for lat0, lon0 in frames:
        crs = CRS.from_dict({"proj": "aeqd", "lat_0": lat0, "lon_0": lon0, "datum": "WGS84",
                             "units": "m"})
        chosen = Transformer.from_crs("EPSG:4326", crs, always_xy=True)
        ours = _forward(lat0, lon0)
        lons = [lon0 + rng.uniform(-2, 2) for _ in range(50)]
        lats = [max(-90.0, min(90.0, lat0 + rng.uniform(-2, 2))) for _ in range(50)]
        xy = chosen.transform(lons, lats)
        assert ours.transform(lons, lats) == xy, (lat0, lon0)
        assert (ours.transform(*xy, direction="INVERSE")
                == chosen.transform(*xy, direction="INVERSE")), (lat0, lon0)
