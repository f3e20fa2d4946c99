"""Benchmark of the rehearsal simulation (Speed): simulated seconds per wall second
for the exemplar, target at least 50x real time.

Run: .venv/bin/python -m tests.bench.bench_rehearsal_sim

Baseline, in this same process: the same simulation with the two economies switched off, i.e.
every constraint monitor, every quantity and the default theory's extension recomputed every
simulated second (no check period, no quantity selection, no verdict cache).
"""

from __future__ import annotations

import contextlib
import gc
import sys
import time
from collections.abc import Callable, Iterator
from typing import Any

from countersign.orders.examples import load_example
from countersign.orders.model import Orders
from countersign.rehearse import sim_judge, sim_model
from countersign.rehearse.manager import Rehearsal, RehearsalOptions
from countersign.rehearse.sim import Simulation
from countersign.rehearse.sources import make_source

TARGET = 50.0


class _NoCache(dict):  # type: ignore[type-arg]
    def __setitem__(self, key: Any, value: Any) -> None:
        pass

    def get(self, key: Any, default: Any = None) -> Any:
        return default


@contextlib.contextmanager
def naive() -> Iterator[None]:
    saved = sim_judge.CHECK_PERIOD_S
    sim_judge.CHECK_PERIOD_S = 0.0
    try:
        yield
    finally:
        sim_judge.CHECK_PERIOD_S = saved


def run(orders: Orders, seed: int, faults: tuple[str, ...] = (), *, baseline: bool = False
        ) -> tuple[float, float]:
    """(simulated seconds, wall seconds) of one headless simulate-source rehearsal."""
    sim = Simulation(orders, seed=seed, source=make_source("simulate", orders), faults=faults)
    if baseline:
        sim.needed = sim_model.ALL_QUANTITIES | frozenset(sim.values())
        sim.contingency._cache = _NoCache()
    gc.collect()
    start = time.perf_counter()
    if baseline:
        with naive():
            sim.advance(10_000_000)
    else:
        sim.advance(10_000_000)
    wall = time.perf_counter() - start
    assert sim.state == "finished"
    return sim.time_s, wall


def best(runs: int, action: Callable[[], tuple[float, float]]) -> tuple[float, float]:
    results = [action() for _ in range(runs)]
    return min(results, key=lambda r: r[1])


def with_scene(orders: Orders, seed: int) -> tuple[float, float]:
    """A live rehearsal with its viser server and scene, at the highest speed setting."""
    with contextlib.redirect_stdout(sys.stderr):
        rehearsal = Rehearsal(orders, owner="bench", options=RehearsalOptions(
            source="simulate", seed=seed, speed=1_000_000))
    start = time.perf_counter()
    rehearsal.start()
    while rehearsal.status()["state"] == "running":
        time.sleep(0.02)
    wall = time.perf_counter() - start
    simulated = rehearsal.status()["sim_time_s"]
    with contextlib.redirect_stdout(sys.stderr):
        rehearsal.stop()
    return simulated, wall


def bench_simulation() -> None:
    print("\n## Rehearsal simulation: simulated seconds per wall second (target >= 50x)")
    print(f"{'scenario':<46} {'sim h':>6} {'ours x':>10} {'naive x':>10} {'ratio':>6}")
    cases = [
        ("exemplar (search-and-sample), seed 0", "search-and-sample", 0, ()),
        ("exemplar, seed 1 (strong current)", "search-and-sample", 1, ()),
        ("exemplar, contact closing at G3", "search-and-sample", 0, ("contact_close@G3",)),
        ("exemplar with rules (search-and-sample-rules)", "search-and-sample-rules", 0, ()),
        ("seed 004 transects, nav drift at G4 (44 rules)", "transect-survey", 0,
         ("nav_drift@G4",)),
    ]
    for label, name, seed, faults in cases:
        orders = load_example(name)
        sim_s, wall = best(3, lambda o=orders, s=seed, f=faults: run(o, s, f))  # type: ignore[misc]
        base_s, base_wall = best(1, lambda o=orders, s=seed, f=faults: run(  # type: ignore[misc]
            o, s, f, baseline=True))
        ours = sim_s / wall
        theirs = base_s / base_wall
        flag = "" if ours >= TARGET else "  BELOW TARGET"
        print(f"{label:<46} {sim_s / 3600:>6.2f} {ours:>9,.0f}x {theirs:>9,.0f}x "
              f"{ours / theirs:>5.1f}x{flag}")
    orders = load_example("search-and-sample")
    sim_s, wall = with_scene(orders, 0)
    print(f"{'exemplar live, viser scene + recording':<46} {sim_s / 3600:>6.2f} "
          f"{sim_s / wall:>9,.0f}x {'':>10} {'':>6}")


if __name__ == "__main__":
    bench_simulation()
