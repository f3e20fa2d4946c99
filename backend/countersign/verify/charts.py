"""Which registry charts a mission uses, copied into its orders (as the vehicle profile is).

A chart is in use when its box meets the mission's box widened by MARGIN_DEG (legs run between
the mission's areas, and loiters and sweeps stay near them). The registry's copy wins over one
the orders carry under the same id, and orders that carry no charts still get every chart in
use: an author cannot leave a keep-out zone out of what is checked and signed.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence

from ..orders.model import Chart, Orders

MARGIN_DEG = 0.5
Box = tuple[float, float, float, float]  # south, west, north, east
ChartLookup = Callable[[Box], Sequence[Chart]]


def box_of(points: Sequence[tuple[float, float]]) -> Box | None:
    if not points:
        return None
    lats = [p[0] for p in points]
    lons = [p[1] for p in points]
    return (min(lats), min(lons), max(lats), max(lons))


def mission_box(orders: Orders, margin: float = MARGIN_DEG) -> Box | None:
    found = box_of([p for area in orders.areas for p in area.polygon])
    if found is None:
        return None
    south, west, north, east = found
    return (max(-90.0, south - margin), max(-180.0, west - margin),
            min(90.0, north + margin), min(180.0, east + margin))


def with_charts(orders: Orders, lookup: ChartLookup | None) -> Orders:
    region = mission_box(orders)
    if lookup is None or region is None:
        return orders
    registry = sorted(lookup(region), key=lambda c: c.id)
    if not registry:
        return orders
    ids = {c.id for c in registry}
    merged = [c for c in orders.charts if c.id not in ids] + list(registry)
    if "charts" in orders.model_fields_set and merged == list(orders.charts):
        return orders
    return orders.model_copy(update={"charts": merged})
