"""The whole logic check at scale, and how much the default time budget leaves out.

Run: nice .venv/bin/python -m tests.bench.bench_logic_whole --goals 10000 --constraints 1000

Times check_logic + check_properties cold with the default total budget and with a generous one,
and prints the findings of each by code: a run that the budget cut short reports fewer
refusals and contradictions, and no VACUOUS findings when it ends before vacuity. `--history`
also solves half the goals first in a shuffled order and says whether the findings changed
(z3's models depend on what it was asked before, so witnesses and cores can)."""

from __future__ import annotations

import argparse
import random
import time
from collections import Counter
from typing import Any

from countersign.orders.model import Orders
from countersign.verify.graph import build_graph
from countersign.verify.logic import DEFAULT_TOTAL_S, Limits, LogicCache, LogicRun, check_logic
from countersign.verify.properties import check_properties
from tests.bench.bench_logic import logic_orders


def whole(orders: Orders, budget: float, cache: LogicCache | None = None) -> tuple[
    float, list[dict[str, Any]], int
]:
    cache = cache or LogicCache()
    start = time.perf_counter()
    found = check_logic(orders, cache, total_timeout_s=budget)
    found += check_properties(orders, build_graph(orders), cache, total_timeout_s=budget)
    seconds = time.perf_counter() - start
    session = cache.model(orders).session
    return seconds, [f.to_json() for f in found], session.calls if session else 0


def counts(findings: list[dict[str, Any]]) -> str:
    by_code = Counter(f"{f['code']}/{f['severity']}" for f in findings)
    return ", ".join(f"{k} {v:,}" for k, v in sorted(by_code.items()))


def shuffled_first(orders: Orders, seed: int) -> list[dict[str, Any]]:
    cache = LogicCache()
    model = cache.model(orders)
    run = LogicRun(model, cache, Limits.start(2_000, 900))
    mission = run.mission()
    goals = list(model.goals.values())
    random.Random(seed).shuffle(goals)
    for goal in goals[::2]:
        run.goal(goal, mission.quarantined)
    return whole(orders, 900, cache)[1]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--goals", type=int, default=2_000)
    parser.add_argument("--constraints", type=int, default=200)
    parser.add_argument("--norms", type=int, default=20)
    parser.add_argument("--budget", type=float, default=900.0)
    parser.add_argument("--history", type=int, default=0, metavar="SEEDS")
    args = parser.parse_args()
    orders = logic_orders(args.goals, args.constraints, args.norms)
    for budget in (DEFAULT_TOTAL_S, args.budget):
        seconds, findings, calls = whole(orders, budget)
        print(f"budget {budget:5.0f} s: {seconds:8.1f} s, {calls:,} solver calls; "
              f"{counts(findings)}", flush=True)
    for seed in range(args.history):
        small = logic_orders(goals=60, constraints=30, norms=8, seed=seed)
        same = whole(small, 900)[1] == shuffled_first(small, seed)
        print(f"history seed {seed}: findings {'the same' if same else 'CHANGED'} when half "
              "the goals are solved first in another order")


if __name__ == "__main__":
    main()
