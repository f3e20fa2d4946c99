"""Benchmark of: 500 goals against 200 chart polygons, GEO with an STRtree, beside a
naive all-pairs test of every leg against every chart measured in this same process.

Run: .venv/bin/python -m tests.bench.bench_geo [--goals 500] [--charts 200]

The mission lies offshore (all sea) so the land-mask sampling of every leg is included. The
target is under 1 s for the whole GEO check (legs, sweeps, loiters, land, charts).
"""

from __future__ import annotations

import argparse
import gc
import random
import time
from collections.abc import Callable
from typing import Any

import numpy as np
import shapely

from countersign.orders.model import Orders
from countersign.verify.geo import check_geo, regions
from countersign.verify.legs import mission_legs

LAT0, LON0 = 34.0, -126.0  # Pacific, west of California: no land


def _box(lat: float, lon: float, size: float) -> list[list[float]]:
    return [[lat, lon], [lat, lon + size], [lat + size, lon + size], [lat + size, lon]]


def mission(goals: int, charts: int, seed: int = 21) -> Orders:
    rng = random.Random(seed)
    behaviors = ["transit", "area_search", "sample", "loiter"]
    goal_list: list[dict[str, Any]] = []
    areas = []
    for i in range(goals):
        lat, lon = LAT0 + rng.uniform(0, 2), LON0 + rng.uniform(0, 2)
        areas.append({"id": f"A{i}", "polygon": _box(lat, lon, 0.01)})

        def target(k: int) -> str:
            return f"G{k}" if k < goals else "COMPLETE"

        goal_list.append({"id": f"G{i}", "area": f"A{i}", "behavior": rng.choice(behaviors),
                          "params": {"sweep_width_m": 200},
                          "next": {"succeed": target(i + 1), "fail": target(i + 2),
                                   "violate": target(i + 3) if i % 3 else "ABORT"}})
    chart_list = []
    for j in range(charts):
        lat, lon = LAT0 + rng.uniform(0, 2), LON0 + rng.uniform(0, 2)
        kind = rng.choice(["keep_out", "protected_area", "shipping_lane", "anchorage"])
        chart_list.append({"id": f"C{j}", "polygon": _box(lat, lon, rng.uniform(0.01, 0.05)),
                           "kind": kind, "contexts": [kind],
                           "norms": [{"id": "n", "forbidden": "behavior == 'transit'"}]
                           if kind == "protected_area" else []})
    return Orders.model_validate({"id": "bench-geo", "start": "G0", "goals": goal_list,
                                  "areas": areas, "charts": chart_list})


def naive_crossings(orders: Orders) -> int:
    """Every leg against every chart, one predicate call each, no index."""
    frame, _, legs = mission_legs(orders)
    assert frame is not None
    zones = regions(orders, frame)
    found = 0
    for leg in legs:
        for zone in zones:
            if leg.line.crosses(zone.shape):
                found += 1
    return found


def indexed_crossings(orders: Orders) -> int:
    frame, _, legs = mission_legs(orders)
    assert frame is not None
    zones = regions(orders, frame)
    tree = shapely.STRtree([z.shape for z in zones])
    lines = np.array([leg.line for leg in legs], dtype=object)
    shapes = np.array([z.shape for z in zones], dtype=object)
    a, b = tree.query(lines, predicate="intersects")  # as check_geo: box filter, then exact
    return int(shapely.crosses(lines[a], shapes[b]).sum())


def best_of(runs: int, action: Callable[[], object]) -> tuple[float, object]:
    best, result = float("inf"), None
    for _ in range(runs):
        gc.collect()
        start = time.perf_counter()
        result = action()
        best = min(best, time.perf_counter() - start)
    return best, result


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--goals", type=int, default=500)
    parser.add_argument("--charts", type=int, default=200)
    args = parser.parse_args()
    orders = mission(args.goals, args.charts)
    check_geo(orders)  # warm: projection and land-mask bands load once per process
    _, _, legs = mission_legs(orders)
    full, findings = best_of(3, lambda: check_geo(orders))
    cpu_start = time.process_time()
    check_geo(orders)
    cpu = time.process_time() - cpu_start
    indexed, crossings = best_of(3, lambda: indexed_crossings(orders))
    naive, naive_count = best_of(1, lambda: naive_crossings(orders))
    assert crossings == naive_count, (crossings, naive_count)
    print(f"bench_geo: {args.goals} goals, {len(legs)} legs, {args.charts} charts")
    print(f"  GEO check, STRtree (legs, sweeps, loiters, land): {full:.3f} s, "
          f"{len(findings)} findings (target < 1 s: {'met' if full < 1 else 'MISSED'}); "  # type: ignore[arg-type]
          f"{cpu:.3f} s of CPU")
    print(f"  leg crossings only, STRtree:   {indexed:.4f} s ({crossings} crossings)")
    print(f"  leg crossings only, all pairs: {naive:.4f} s ({naive_count} crossings), "
          f"{naive / indexed:.1f}x the indexed time")


if __name__ == "__main__":
    main()
