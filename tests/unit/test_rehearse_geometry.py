"""Geometry and constraint monitors of the rehearsal simulation."""

from __future__ import annotations

import math

import pytest

from countersign.orders.examples import load_example
from countersign.rehearse.geo import (
    LocalFrame,
    centroid,
    contains,
    distance_to_polygon,
    lawnmower,
    path_length,
)
from countersign.rehearse.monitor import GoalFacts, compile_expr, monitors_of
from countersign.verify.expressions import parse

SQUARE = ((0.0, 0.0), (1000.0, 0.0), (1000.0, 400.0), (0.0, 400.0))


def test_local_frame_is_metric() -> None:
    frame = LocalFrame(36.7, -121.9)
    x, y = frame.to_xy(36.7 + 0.01, -121.9)
    assert x == pytest.approx(0.0) and y == pytest.approx(1112.0, rel=1e-3)
    x, _ = frame.to_xy(36.7, -121.9 + 0.01)
    assert x == pytest.approx(1112.0 * math.cos(math.radians(36.7)), rel=1e-3)


def test_polygon_helpers() -> None:
    assert centroid(SQUARE) == pytest.approx((500.0, 200.0))
    assert contains(SQUARE, (10.0, 10.0)) and not contains(SQUARE, (-1.0, 10.0))
    assert distance_to_polygon(SQUARE, (500.0, 200.0)) == 0.0
    assert distance_to_polygon(SQUARE, (1300.0, 800.0)) == pytest.approx(500.0)
    assert not contains(SQUARE[:2], (0.0, 0.0))


def test_lawnmower_covers_with_the_swath_and_is_bounded() -> None:
    legs = lawnmower(SQUARE, 100.0)
    assert len(legs) == 8  # 4 legs along the long side, 100 m apart
    assert {round(y) for _, y in legs} == {50, 150, 250, 350}
    assert all(contains(SQUARE, p) for p in legs)
    assert path_length(legs) == pytest.approx(4 * 900 + 3 * 100)
    assert len(lawnmower(SQUARE, 0.001, max_legs=50)) == 100


@pytest.mark.parametrize(("expr", "values", "expected"), [
    ("lane_distance_m >= 1000 or depth_m >= 20", {"lane_distance_m": 500.0, "depth_m": 25.0},
     True),
    ("lane_distance_m >= 1000 or depth_m >= 20", {"lane_distance_m": 500.0, "depth_m": 5.0},
     False),
    ("3 <= depth_m <= 12", {"depth_m": 13.0}, False),
    ("not safety_equipment_ok implies surfaced", {"safety_equipment_ok": False,
                                                  "surfaced": False}, False),
    ("depth_m * 2 - 10 / 2 > 0", {"depth_m": 3.0}, True),
    ("depth_m >= 20", {}, None),  # unknown quantity: no verdict
    ("unknown_m >= 1 or depth_m >= 20", {"depth_m": 30.0}, True),
    ("behavior == 'sample' implies not context('marine_protected_area')", {}, False),
])
def test_compiled_monitors(expr: str, values: dict[str, float | bool], expected: bool | None
                           ) -> None:
    facts = GoalFacts("sample", "A", frozenset({"marine_protected_area"}))
    assert compile_expr(parse(expr))(values, facts) == expected


def test_monitors_of_the_exemplar() -> None:
    monitors, skipped = monitors_of(load_example("search-and-sample"))
    assert [m.constraint_id for m in monitors] == [f"C{i}" for i in range(1, 8)]
    assert skipped == []
    c7 = monitors[-1]
    assert c7.applies("G5") and not c7.applies("G1")
