"""Benchmarks of the constraint logic with z3.

Run: .venv/bin/python -m tests.bench.bench_logic

"All logic checks" are check_logic (EXPR, CONTRADICTION, NORM, VACUOUS) plus check_properties
(PROPERTY). Each figure is printed with a ratio against a naive baseline measured in this same
process: no cache, no folding of facts, one fresh z3 solver per check built through z3's Python
API, every norm and property checked separately for every goal, cores shrunk by deletion.
"""

from __future__ import annotations

import argparse
import random
import subprocess
import sys
import time
from collections.abc import Callable
from typing import Any

import z3

from countersign.orders.examples import load_example
from countersign.orders.model import OUTCOMES, Orders
from countersign.verify.expressions import Expr, Logic, Not, fold, to_z3
from countersign.verify.graph import build_graph
from countersign.verify.logic import DEFAULT_TOTAL_S, LogicCache, LogicModel, check_logic
from countersign.verify.properties import check_properties
from tests.bench.timing import best_of

TAGS = ["coastal", "shipping_lane", "marine_protected_area", "harbor_approach", "research_zone",
        "cable_area", "anchorage"]
BEHAVIORS = ["transit", "area_search", "sample", "hydro_survey", "reacquire", "loiter",
             "surface_report", "rendezvous"]


def logic_orders(goals: int = 200, constraints: int = 50, norms: int = 20,
                 seed: int = 11) -> Orders:
    """A ternary DAG of goals in tagged areas, with envelopes, scoped and mission-wide
    constraints (bounds, disjunctions, implications on behaviour and context), norms of every
    kind (prohibitions, obligations, permissions, expression contexts) and three properties."""
    rng = random.Random(seed)
    areas = [{"id": f"A{i}", "title": f"Area {i}", "contexts": rng.sample(TAGS, rng.randint(1, 2))}
             for i in range(12)]
    items = []
    for i in range(goals):
        nxt: dict[str, str] = {}
        for k, outcome in enumerate(OUTCOMES):
            if i + 1 >= goals:
                nxt[outcome] = "COMPLETE" if k == 0 else "ABORT"
            elif k == 0:
                nxt[outcome] = f"G{i + 1}"
            else:
                hop = rng.randint(1, 12)
                nxt[outcome] = f"G{i + hop}" if i + hop < goals else "ABORT"
        low = rng.choice([5, 10, 15, 20, 25, 30])
        envelope: dict[str, list[float]] = {
            "depth_m": [low, low + rng.choice([10, 20, 40])],
            "speed_mps": [0.5, rng.choice([1.5, 2.0, 2.5])],
        }
        if rng.random() < 0.5:
            envelope["altitude_m"] = [rng.choice([2, 3, 4]), rng.choice([8, 10, 15])]
        if rng.random() < 0.3:
            envelope["lane_distance_m"] = [rng.choice([0, 200, 800]), 5000]
        behavior = rng.choice(BEHAVIORS)
        items.append({
            "id": f"G{i}", "title": f"Goal {i} ({behavior})", "behavior": behavior,
            "area": f"A{rng.randrange(12)}", "envelope": envelope, "next": nxt,
            "cost": {"energy_wh": rng.randint(1, 50), "duration_s": rng.randint(60, 3600)},
        })
    forms: list[Callable[[], str]] = [
        lambda: f"depth_m >= {rng.choice([2, 4, 5])}",
        lambda: f"lane_distance_m >= {rng.choice([500, 1000])} or "
                f"depth_m >= {rng.choice([10, 12, 20])}",
        lambda: "altitude_m >= 2 and altitude_m <= 20",
        lambda: f"speed_mps <= {rng.choice([2.5, 3, 4])}",
        lambda: f"behavior == 'sample' implies depth_m >= {rng.choice([5, 8])}",
        lambda: f"context('shipping_lane') implies depth_m >= {rng.choice([5, 10])}",
        lambda: f"nav_error_m <= {rng.choice([5, 10, 20])}",
        lambda: f"contact_distance_m >= {rng.choice([300, 500, 1000])}",
        lambda: "battery_reserve_pct >= 20",
        lambda: "not (behavior == 'loiter' and context('shipping_lane'))",
        lambda: f"depth_m + altitude_m <= {rng.choice([120, 150])}",
    ]
    cons = []
    for j in range(constraints):
        expr = rng.choice(forms)()
        scope: str | list[str] = "mission" if rng.random() < 0.3 else sorted(
            {f"G{rng.randrange(goals)}" for _ in range(rng.randint(5, 40))})
        cons.append({"id": f"C{j}", "text": f"Constraint {j}", "applies_to": scope, "expr": expr})
    norm_forms: list[Callable[[], dict[str, str]]] = [
        lambda: {"context": rng.choice(TAGS),
                 "forbidden": f"behavior == '{rng.choice(BEHAVIORS)}'"},
        lambda: {"context": "shipping_lane", "obligated": f"depth_m >= {rng.choice([5, 8])}"},
        lambda: {"context": "research_zone", "permitted": "behavior == 'sample'"},
        lambda: {"context": "context('coastal') and depth_m < 6", "forbidden": "speed_mps > 2.5"},
        lambda: {"context": "marine_protected_area", "obligated": "speed_mps <= 3"},
    ]
    norm_items = [{"id": f"N{j}", "text": f"Norm {j}", **rng.choice(norm_forms)()}
                  for j in range(norms)]
    return Orders.model_validate({
        "id": f"logic-{goals}", "start": "G0", "vehicle": "v", "goals": items,
        "constraints": cons, "norms": norm_items, "areas": areas,
        "vehicles": [{"id": "v", "title": "Vehicle",
                      "envelope": {"depth_m": [0, 300], "speed_mps": [0, 3]},
                      "budget": {"energy_wh": 10**9, "duration_s": 10**12}}],
        "properties": [
            {"id": "P1", "never": "behavior == 'surface_report' and context('shipping_lane')"},
            {"id": "P2", "always": "depth_m <= 60"},
            {"id": "P3", "max": {"energy_wh": 400}},
        ],
    })


def all_checks(orders: Orders, cache: LogicCache | None) -> int:
    findings = check_logic(orders, cache)
    findings += check_properties(orders, build_graph(orders), cache)
    return len(findings)


# ---------------------------------------------------------------------------------------------
# The naive baseline


class Naive:
    """The same decisions, computed the simple way."""

    def __init__(self, orders: Orders) -> None:
        self.model = LogicModel(orders)
        self.checks = 0

    def _solver(self, formulas: list[Any]) -> z3.Solver:
        solver = z3.Solver()
        solver.set("timeout", 2000)
        for formula in formulas:
            solver.add(formula)
        return solver

    def _check(self, formulas: list[Any]) -> Any:
        self.checks += 1
        return self._solver(formulas).check()

    def _bounds(self, name: str, low: float | None, high: float | None) -> list[Any]:
        spec = self.model.quantities.get(name)
        kind = spec.type if spec else "real"
        if kind == "boolean":
            return []
        var = z3.Int(f"q:{name}") if kind == "integer" else z3.Real(f"q:{name}")
        out = []
        if low is not None:
            out.append(var >= z3.RealVal(str(low)) if kind != "integer" else var >= int(low))
        if high is not None:
            out.append(var <= z3.RealVal(str(high)) if kind != "integer" else var <= int(high))
        return out

    def _expr(self, expr: Expr) -> Any:
        return to_z3(expr, self.model.quantities)

    def goal_formulas(self, goal_id: str) -> list[Any]:
        model = self.model
        goal = model.goals[goal_id]
        formulas: list[Any] = []
        for name, (low, high) in goal.envelope.items():
            formulas += self._bounds(name, low, high)
        if model.vehicle:
            for name, (low, high) in model.vehicle.envelope.items():
                formulas += self._bounds(name, low, high)
        for name, spec in model.quantities.items():
            formulas += self._bounds(name, spec.min, spec.max)
        codes: dict[str, int] = {}
        behavior = z3.Int("behavior")
        formulas.append(behavior == codes.setdefault(goal.behavior or "", len(codes)))
        area = model.areas.get(goal.area or "")
        for tag in TAGS:
            holds = area is not None and tag in area.contexts
            formulas.append(z3.Bool(f"ctx:{tag}") == holds)
        for c in model.in_scope(goal_id):
            formulas.append(self._expr(c.expr))
        return formulas

    def minimal_core(self, formulas: list[Any]) -> list[Any]:
        core = list(formulas)
        index = 0
        while index < len(core):
            trial = core[:index] + core[index + 1:]
            if self._check(trial) == z3.unsat:
                core = trial
            else:
                index += 1
        return core

    def run(self, graph_properties: bool = True) -> int:
        model = self.model
        problems = 0
        for c in model.constraints:  # VACUOUS, one solver each
            background: list[Any] = []
            if model.vehicle:
                for name, (low, high) in model.vehicle.envelope.items():
                    background += self._bounds(name, low, high)
            if self._check([*background, z3.Not(self._expr(c.expr))]) == z3.unsat:
                problems += 1
        for goal_id in model.goals:
            formulas = self.goal_formulas(goal_id)
            if self._check(formulas) == z3.unsat:
                problems += 1
                self.minimal_core(formulas)
                continue
            for n in model.norms:
                if n.modality == "permitted":
                    continue
                breach = model.breach_expr(n)
                refused = self._check([*formulas, self._expr(Not(breach, 1))]) == z3.unsat
                at_risk = not refused and self._check([*formulas, self._expr(breach)]) == z3.sat
                problems += refused or at_risk
            if graph_properties:
                for prop in model.orders.properties:
                    for mode in ("always", "never"):
                        text = getattr(prop, mode)
                        if text is None:
                            continue
                        expr = model.parse_condition(text, prop.id, prop.id, mode, [])
                        assert expr is not None
                        check = Not(expr, 1) if mode == "always" else expr
                        if self._check([*formulas, self._expr(check)]) == z3.sat:
                            problems += 1
        return problems


def naive_all(orders: Orders) -> int:
    return Naive(orders).run()


# ---------------------------------------------------------------------------------------------



def verdict(seconds: float, limit: float) -> str:
    return "ok" if seconds < limit else "OVER"


def edited(orders: Orders, goal_index: int, bump: float) -> Orders:
    data = orders.model_dump(mode="json", exclude_none=True)
    data["goals"][goal_index]["envelope"]["depth_m"][1] += bump
    return Orders.model_validate(data)


def import_time() -> float:
    code = ("import time; t = time.perf_counter(); import z3; "
            "print(time.perf_counter() - t)")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         check=True)
    return float(out.stdout)


def row(label: str, ours: float, limit: float | None, naive: float | None) -> None:
    target = f"< {limit * 1000:.0f} ms {verdict(ours, limit)}" if limit else ""
    ratio = f"{naive / ours:8.1f}x" if naive else ""
    base = f"{naive * 1000:10.1f}" if naive else ""
    print(f"{label:<44} {ours * 1000:9.1f} {target:<16} {base:>10} {ratio:>9}")


def bench_exemplar() -> None:
    print("\n## Exemplar (search-and-sample): all logic checks")
    print(f"{'':<44} {'ours ms':>9} {'target':<16} {'naive ms':>10} {'ratio':>9}")
    orders = load_example("search-and-sample")
    cold = best_of(5, lambda: all_checks(orders, LogicCache()))
    naive = best_of(3, lambda: naive_all(orders))
    row("cold (empty cache)", cold, 0.200, naive)
    cache = LogicCache()
    all_checks(orders, cache)
    warm = best_of(10, lambda: all_checks(load_example("search-and-sample"), cache))
    row("nothing changed (new orders object, warm)", warm, 0.020, naive)
    print(f"(importing z3 in a fresh process: {import_time() * 1000:.0f} ms, once per process; "
          "logic.py imports it only when a check misses the cache)")


def bench_large(goals: int, constraints: int, norms: int) -> None:
    orders = logic_orders(goals, constraints, norms)
    print(f"\n## {goals} goals, {constraints} constraints, {norms} norms, 3 properties")
    print(f"{'':<44} {'ours ms':>9} {'target':<16} {'naive ms':>10} {'ratio':>9}")
    counts: dict[str, int] = {}
    cut_short = 0
    for finding in check_logic(orders) + check_properties(orders):
        counts[finding.code] = counts.get(finding.code, 0) + 1
        if finding.details.get("undecided") == "time budget exhausted":
            cut_short += len(finding.subjects)
    if cut_short:
        # The figures below then time a run that stopped early, not the whole check.
        print(f"WARNING: the default time budget ({DEFAULT_TOTAL_S:.0f} s) ran out: "
              f"{cut_short:,} goals undecided; the figures below are of a truncated run")
    cold = best_of(3, lambda: all_checks(orders, LogicCache()))
    start = time.perf_counter()
    naive_checker = Naive(orders)
    naive_checker.run()
    naive = time.perf_counter() - start
    row("cold (empty cache)", cold, 2.0, naive)
    cache = LogicCache()
    all_checks(orders, cache)
    versions = [edited(orders, 57 + i, 1 + i) for i in range(5)]
    times = []
    for version in versions:
        start = time.perf_counter()
        all_checks(version, cache)
        times.append(time.perf_counter() - start)
    row("after a one-goal edit (best of 5 edits)", min(times), 0.150, naive)
    print(f"{'   (median of the 5 edits)':<44} {sorted(times)[2] * 1000:9.1f}")
    warm = best_of(5, lambda: all_checks(versions[-1], cache))
    row("nothing changed (warm)", warm, None, naive)
    print(f"findings: {dict(sorted(counts.items()))}; naive baseline made "
          f"{naive_checker.checks:,} solver checks")
    facts = LogicModel(orders)
    decided = sum(fold(Logic("and", (n.context, n.body), 1), facts.facts(g)) is not None
                  for g in orders.goals for n in facts.norms)
    print(f"norm checks decided by the goals' facts alone (no solver): {decided:,} of "
          f"{len(orders.goals) * len(facts.norms):,}")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--goals", type=int, default=200)
    parser.add_argument("--constraints", type=int, default=50)
    parser.add_argument("--norms", type=int, default=20)
    args = parser.parse_args()
    bench_exemplar()
    bench_large(args.goals, args.constraints, args.norms)


if __name__ == "__main__":
    main()
