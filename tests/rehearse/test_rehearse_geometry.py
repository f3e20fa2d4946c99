"""Geometry and constraint monitors of the rehearsal simulation."""

from __future__ import annotations

import pytest

from countersign.orders.examples import load_example
from countersign.rehearse.geo import (
    centroid,
    contains,
    distance_to_polygon,
)
from countersign.rehearse.monitor import GoalFacts, compile_expr, monitors_of
from countersign.verify.expressions import parse

SQUARE = ((0.0, 0.0), (1000.0, 0.0), (1000.0, 400.0), (0.0, 400.0))


def test_the_world_is_in_the_verifiers_frame() -> None:
    """The rehearsal's geography is verify/legs.py's, not a flat frame of its own."""
    import random

    from countersign.rehearse.world import World
    from countersign.verify.legs import mission_legs

    orders = load_example("search-and-sample")
    world = World(orders, random.Random(0))
    frame, places, legs = mission_legs(orders)
    assert world.frame == frame and world.legs == legs and world.places == places
    area = orders.areas[0]
    xs, ys = frame.to_xy([p[0] for p in area.polygon], [p[1] for p in area.polygon])
    assert world.areas[area.id].polygon[0] == pytest.approx((xs[0], ys[0]))
    lat, lon = world.to_latlon(world.areas[area.id].polygon[0])
    assert (lat, lon) == pytest.approx(area.polygon[0], abs=1e-9)


def test_polygon_helpers() -> None:
    assert centroid(SQUARE) == pytest.approx((500.0, 200.0))
    assert contains(SQUARE, (10.0, 10.0)) and not contains(SQUARE, (-1.0, 10.0))
    assert distance_to_polygon(SQUARE, (500.0, 200.0)) == 0.0
    assert distance_to_polygon(SQUARE, (1300.0, 800.0)) == pytest.approx(500.0)
    assert not contains(SQUARE[:2], (0.0, 0.0))


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
