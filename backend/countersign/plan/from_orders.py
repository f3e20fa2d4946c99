"""A planning problem from mission orders: the areas to survey and the vehicle profile.

Positions become metres in a local frame centred on the start (equirectangular, ample for
survey distances). Each area's survey is a lawn-mower pattern over its bounding box, lanes
along the longer side, one lane per swath width; there are four passes, one entering at each
corner, and each exits where the pattern ends (the far side; the far end when the number of
lanes is odd). The survey energy is the track length (surface / swath, as the BUDGET
estimate uses) times the vehicle's consumption, `power_w / speed_mps` per metre; transit uses
the same rate. Rewards and mandatory areas come from the arguments or from `reward` and
`mandatory` fields on the areas themselves, else 1 and optional.
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Iterable, Mapping
from typing import Any

from pydantic import ValidationError

from ..orders.model import Area, Orders
from ..orders.reader import location_path
from .model import PlanProblem

EARTH_RADIUS_M = 6_371_000.0
DEFAULT_SWATH_M = 50.0
SWATH_PARAMS = ("sweep_width_m", "swath_width_m", "line_spacing_m")
LatLon = tuple[float, float]


class CannotBuildProblem(ValueError):
    """The orders lack what a planning problem needs (it says what)."""


def _local(origin: LatLon) -> Any:
    lat0, lon0 = origin
    scale = math.cos(math.radians(lat0))

    def to_metres(point: LatLon) -> tuple[float, float]:
        lat, lon = point
        return (
            math.radians(lon - lon0) * EARTH_RADIUS_M * scale,
            math.radians(lat - lat0) * EARTH_RADIUS_M,
        )

    return to_metres


def _swath(orders: Orders, area: Area, given: float | None) -> float:
    if given is not None:
        return given
    for goal in orders.goals:
        if goal.area == area.id:
            for name in SWATH_PARAMS:
                value = goal.params.get(name)
                if isinstance(value, int | float) and value > 0:
                    return float(value)
    return DEFAULT_SWATH_M


def lawnmower_passes(
    points: list[tuple[float, float]], swath_m: float, wh_per_m: float
) -> list[dict[str, Any]]:
    ring = [*points, points[0]]
    surface = abs(sum(a[0] * b[1] - b[0] * a[1] for a, b in itertools.pairwise(ring))) / 2
    xs, ys = [p[0] for p in points], [p[1] for p in points]
    low_x, high_x, low_y, high_y = min(xs), max(xs), min(ys), max(ys)
    along_x = (high_x - low_x) >= (high_y - low_y)
    across = (high_y - low_y) if along_x else (high_x - low_x)
    lanes = max(1, math.ceil(across / swath_m))
    survey_wh = surface / swath_m * wh_per_m
    passes = []
    for x, y in ((low_x, low_y), (high_x, low_y), (high_x, high_y), (low_x, high_y)):
        flip_x = (low_x + high_x) - x
        flip_y = (low_y + high_y) - y
        if along_x:
            exit_ = (flip_x if lanes % 2 else x, flip_y)
        else:
            exit_ = (flip_x, flip_y if lanes % 2 else y)
        passes.append({"entry": [x, y], "exit": list(exit_), "survey_wh": survey_wh,
                       "title": f"lawn-mower, {lanes} lanes of {swath_m:g} m"})
    return passes


def problem_from_orders(
    orders: Orders,
    *,
    start: LatLon,
    recovery: LatLon,
    battery_wh: float | None = None,
    reserve_wh: float = 0.0,
    areas: Iterable[str] | None = None,
    rewards: Mapping[str, float] | None = None,
    mandatory: Iterable[str] = (),
    swath_m: float | None = None,
    level: int = 2,
) -> PlanProblem:
    """The survey problem for `areas` (default: every area with a polygon) of the orders.

    `battery_wh` defaults to the vehicle's energy budget."""
    vehicle = orders.target_vehicle()
    if vehicle is None or vehicle.speed_mps is None or vehicle.power_w is None:
        raise CannotBuildProblem(
            "the orders' vehicle needs speed_mps and power_w to cost transit and surveys"
        )
    battery = battery_wh
    if battery is None:
        battery = vehicle.budget.energy_wh if vehicle.budget else None
    if battery is None:
        raise CannotBuildProblem("give battery_wh, or an energy budget on the vehicle")
    wh_per_m = vehicle.power_w / vehicle.speed_mps / 3600.0
    wanted = list(areas) if areas is not None else [
        a.id for a in orders.areas if len(a.polygon) >= 3
    ]
    to_metres = _local(start)
    index, must = orders.area_index(), set(mandatory)
    items = [_area_item(orders, index.get(area_id), area_id, to_metres, wh_per_m,
                        rewards=rewards, must=must, swath_m=swath_m) for area_id in wanted]
    # Inputs within their own bounds can still make a problem the model refuses (a start far
    # from the areas puts passes beyond the coordinate bound): say so rather than fail.
    try:
        return PlanProblem.model_validate({
        "format": "countersign.plan/1",
        "level": level,
        "start": list(to_metres(start)),
        "recovery": list(to_metres(recovery)),
        "vehicle": {"transit_wh_per_m": wh_per_m, "battery_wh": battery,
                    "reserve_wh": reserve_wh},
        "areas": items,
        })
    except ValidationError as exc:
        first = exc.errors(include_url=False)[0]
        where = location_path(tuple(first["loc"]))
        message = str(first["msg"]).removeprefix("Value error, ")
        raise CannotBuildProblem(f"the planning problem would not be valid: {where}: "
                                 f"{message}") from None


def _area_item(orders: Orders, area: Area | None, area_id: str, to_metres: Any,
               wh_per_m: float, *, rewards: Mapping[str, float] | None, must: set[str],
               swath_m: float | None) -> dict[str, Any]:
    """One area of the problem: its reward, whether it is mandatory, its lawnmower passes."""
    if area is None or len(area.polygon) < 3:
        raise CannotBuildProblem(f"area {area_id!r} is not in the orders or has no polygon")
    extra = area.model_extra or {}
    reward = (rewards or {}).get(area_id, extra.get("reward", 1.0))
    points = [to_metres(p) for p in area.polygon]
    return {
        "id": area.id,
        "title": area.title,
        "reward": reward,
        "mandatory": area_id in must or bool(extra.get("mandatory", False)),
        "passes": lawnmower_passes(points, _swath(orders, area, swath_m), wh_per_m),
    }
