"""Logic at scale: the logic check of a generated mission, cold.

Run: nice .venv/bin/python -m tests.bench.bench_logic_scale --goals 10000 --constraints 1000

Times check_logic and check_properties cold (a fresh LogicCache and a fresh z3 context) twice in
one process: with the screen and grouped checks (run.GROUP_CHECKS, the default) and with the
baseline of one session check at a time per goal. Each is timed with a generous budget and with
validate's solver budget (report.SOLVER_BUDGET_S: CPU time of the checking thread, shared by
both checks, under a wall-clock cap), where the figure is how many goals are left undecided.
Goals: < 5 s CPU cold, fewer than 1% of goals undecided. The findings of the two paths are
compared too (they must be the same).
"""

from __future__ import annotations

import argparse
import gc
import os
import time
from collections.abc import Callable
from typing import Any

from countersign.orders.findings import Finding
from countersign.orders.model import Orders
from countersign.verify.graph import build_graph
from countersign.verify.logic import WALL_CAP_FACTOR, Limits, LogicCache, check_logic
from countersign.verify.logic import run as logic_run
from countersign.verify.properties import check_properties
from countersign.verify.report import SOLVER_BUDGET_S, SOLVER_CALL_MS
from tests.bench.bench_logic import logic_orders

GOAL_CPU_S = 5.0
GOAL_UNDECIDED = 0.01


def undecided_goals(findings: list[Finding], goal_ids: set[str]) -> set[str]:
    """Goals named by a warning that says the solver did not decide."""
    out: set[str] = set()
    for f in findings:
        if f.severity == "warning" and ("undecided" in f.details
                                        or "could not be decided" in f.message):
            out.update(s for s in f.subjects if s in goal_ids)
    return out


def timed(action: Callable[[], list[Finding]]) -> tuple[float, float, list[Finding]]:
    gc.collect()
    cpu, wall = time.process_time(), time.perf_counter()
    found = action()
    return time.process_time() - cpu, time.perf_counter() - wall, found


def run(orders: Orders, grouped: bool, budget_s: float) -> dict[str, Any]:
    logic_run.GROUP_CHECKS = grouped
    try:
        cache = LogicCache()
        graph = build_graph(orders)
        # One budget for both, as validate shares it: CPU time, under its wall-clock cap.
        limits = Limits.start(SOLVER_CALL_MS, budget_s)
        cpu, wall, logic = timed(lambda: check_logic(orders, cache, limits=limits))
        pcpu, pwall, props = timed(lambda: check_properties(orders, graph, cache, limits=limits))
    finally:
        logic_run.GROUP_CHECKS = True
    model = cache.model(orders)
    return {
        "cpu": cpu, "wall": wall, "pcpu": pcpu, "pwall": pwall,
        "findings": [f.to_json() for f in logic + props],
        "undecided": len(undecided_goals(logic + props, set(model.goals))),
        "undecided_logic": len(undecided_goals(logic, set(model.goals))),
        "session": model.session.calls if model.session else 0,
        "screen": model.screen.calls if model.screen else 0,
        "shared": model.screen.shared if model.screen else 0,
    }


def line(label: str, ours: dict[str, Any], base: dict[str, Any], goals: int) -> None:
    verdict = "ok" if ours["cpu"] < GOAL_CPU_S else "OVER"
    share = ours["undecided"] / goals
    print(f"{label:<26} check_logic CPU {ours['cpu']:7.2f} s (goal < {GOAL_CPU_S:g} s "
          f"{verdict}; baseline {base['cpu']:7.2f} s, {base['cpu'] / ours['cpu']:4.1f}x), wall "
          f"{ours['wall']:7.2f} s (baseline {base['wall']:7.2f} s)")
    print(f"{'':<26} + check_properties CPU {ours['pcpu']:6.2f} s (baseline "
          f"{base['pcpu']:6.2f} s); undecided goals {ours['undecided']:,} = {share:.2%} "
          f"(goal < {GOAL_UNDECIDED:.0%} {'ok' if share < GOAL_UNDECIDED else 'OVER'}; "
          f"baseline {base['undecided']:,}); by check_logic alone {ours['undecided_logic']:,} "
          f"(baseline {base['undecided_logic']:,})")
    print(f"{'':<26} solver checks: session {ours['session']:,} + screen {ours['screen']:,} "
          f"({ours['shared']:,} answers shared) vs baseline session {base['session']:,}")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--goals", type=int, default=10_000)
    parser.add_argument("--constraints", type=int, default=1_000)
    parser.add_argument("--norms", type=int, default=20)
    parser.add_argument("--generous", type=float, default=900.0,
                        help="the budget of the untruncated runs, seconds")
    parser.add_argument("--budget-only", action="store_true",
                        help="only the runs under validate's budget")
    args = parser.parse_args()
    orders = logic_orders(args.goals, args.constraints, args.norms)
    print(f"## {args.goals:,} goals, {args.constraints:,} constraints, {args.norms} norms, "
          "cold (fresh cache and z3 context per run); load average "
          + ", ".join(f"{x:.2f}" for x in os.getloadavg()))
    failed = False
    runs = [(f"budget {args.generous:g} s", args.generous),
            (f"validate's {SOLVER_BUDGET_S:g} s CPU budget", SOLVER_BUDGET_S)]
    print(f"(a budget is CPU time of the checking thread, ended by a wall-clock cap of "
          f"{WALL_CAP_FACTOR:g}x it: verify/logic/limits.py)")
    for label, budget in runs[1:] if args.budget_only else runs:
        base = run(orders, False, budget)
        ours = run(orders, True, budget)
        line(label, ours, base, args.goals)
        if budget == args.generous and ours["findings"] != base["findings"]:
            failed = True
            print("FINDINGS DIFFER between the grouped path and the baseline")
    raise SystemExit(1 if failed else 0)


if __name__ == "__main__":
    main()
