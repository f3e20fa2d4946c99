"""Exact survey planning: dynamic programming over subsets of areas and the last pass.

best[S][v] is the least energy that starts at `start`, surveys exactly the areas of S and ends
with pass v (an area of S, one of its passes). It is computed from smaller subsets:

    best[S][v] = min over u in S - area(v) of best[S - area(v)][u] + leg(exit u, entry v) + survey v

so every subset, order and pass choice is covered without enumerating permutations. The plan
for S costs min over v of best[S][v] + leg(exit v, recovery). The best plan maximises the total
reward over feasible subsets (energy within the limit, every mandatory area included), then
minimises energy (with a conversion function for energy, it maximises reward less the
converted energy: for a fixed subset that is still the least-energy route, so the same tables
serve). Time is O(2^n * n^2 * p^2) and memory O(2^n * n * p) for n areas with p
passes each, so the number of states is bounded (`MAX_STATES`) and a deadline is checked.

When no plan is feasible, the answer is a minimal set of mandatory areas that no feasible plan
can serve together (seed 001, Algorithm 1: drop members while the rest still cannot be served).
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from operator import add
from typing import Any, Final

from .model import PlanProblem

MAX_STATES: Final = 4_500_000  # subsets x passes; ~16 areas with 3 passes, 17 with 1
INF: Final = math.inf


class PlanTooLarge(ValueError):
    """The exact solver would need more states than it allows."""


class PlanTimeout(TimeoutError):
    """The exact solver did not finish before its deadline."""


@dataclass(frozen=True)
class Step:
    area: str
    pass_index: int
    leg_wh: float  # transit into the area
    survey_wh: float

    @property
    def energy_wh(self) -> float:
        return self.leg_wh + self.survey_wh


@dataclass(frozen=True)
class Plan:
    """A feasible plan, or (feasible False) the reason there is none."""

    feasible: bool
    reward: float = 0.0
    energy_wh: float = 0.0
    limit_wh: float = 0.0
    steps: tuple[Step, ...] = ()
    return_wh: float = 0.0  # the last leg, to recovery
    conflict: tuple[str, ...] = ()  # infeasible: a minimal set of mandatory areas
    message: str = ""
    value: float = 0.0  # the objective: reward, less converted energy when a conversion is given
    stats: dict[str, Any] = field(default_factory=dict, compare=False)

    @property
    def order(self) -> list[str]:
        return [step.area for step in self.steps]

    @property
    def passes(self) -> dict[str, int]:
        return {step.area: step.pass_index for step in self.steps}

    def to_json(self) -> dict[str, Any]:
        if not self.feasible:
            return {
                "feasible": False,
                "conflict": list(self.conflict),
                "message": self.message,
                "limit_wh": self.limit_wh,
            }
        return {
            "feasible": True,
            "reward": self.reward,
            "energy_wh": round(self.energy_wh, 6),
            "value": round(self.value, 6),
            "limit_wh": self.limit_wh,
            "order": self.order,
            "passes": self.passes,
            "legs_wh": [round(step.leg_wh, 6) for step in self.steps]
            + [round(self.return_wh, 6)],
        }


@dataclass(frozen=True)
class _Node:
    area: int
    pass_index: int
    entry: tuple[float, float]
    exit: tuple[float, float]
    survey_wh: float


def _leg(rate: float, a: tuple[float, float], b: tuple[float, float]) -> float:
    return rate * math.dist(a, b)


def state_count(problem: PlanProblem) -> int:
    nodes = sum(len(problem.passes_of(area)) for area in problem.areas)
    return (1 << len(problem.areas)) * max(nodes, 1)


def check_size(problem: PlanProblem) -> None:
    states = state_count(problem)
    if states > MAX_STATES:
        raise PlanTooLarge(
            f"{len(problem.areas)} areas with "
            f"{sum(len(problem.passes_of(a)) for a in problem.areas)} passes in all need "
            f"{states:,} states, more than the exact planner's limit of {MAX_STATES:,} "
            "(about 16 areas with 3 passes each, or 17 at level 1): split the survey into "
            "smaller problems or use fewer passes"
        )


def _pass_nodes(problem: PlanProblem) -> tuple[list[_Node], list[list[int]]]:
    """A node per pass of every area, and each area's node indices."""
    nodes: list[_Node] = []
    nodes_of: list[list[int]] = []
    for a, area in enumerate(problem.areas):
        indices = []
        for p, pass_ in enumerate(problem.passes_of(area)):
            indices.append(len(nodes))
            nodes.append(_Node(a, p, pass_.entry, pass_.exit, pass_.survey_wh))
        nodes_of.append(indices)
    return nodes, nodes_of


class _Tables:
    """best[S] for every subset S, filled in increasing order of S."""

    def __init__(
        self,
        problem: PlanProblem,
        deadline: float | None,
        progress: Callable[[int, int], None] | None,
    ) -> None:
        check_size(problem)
        rate = problem.vehicle.transit_wh_per_m
        self.problem = problem
        self.n = len(problem.areas)
        self.nodes, self.nodes_of = _pass_nodes(problem)
        nodes = self.nodes
        self.first = [_leg(rate, problem.start, v.entry) + v.survey_wh for v in nodes]
        # into[v][u]: the leg from the exit of u to the entry of v, plus the survey of v
        self.into = [[_leg(rate, u.exit, v.entry) + v.survey_wh for u in nodes] for v in nodes]
        self.home = [_leg(rate, v.exit, problem.recovery) for v in nodes]
        self.direct = _leg(rate, problem.start, problem.recovery)
        size = 1 << self.n
        self.best: list[list[float]] = [[]] * size
        self.energy: list[float] = [INF] * size
        self.energy[0] = self.direct
        started = time.perf_counter()
        self._fill(deadline, progress, started)
        rewards = [0.0] * size
        values = [area.reward for area in problem.areas]
        for mask in range(1, size):
            low = mask & -mask
            rewards[mask] = rewards[mask ^ low] + values[low.bit_length() - 1]
        self.rewards = rewards
        self.elapsed_s = time.perf_counter() - started

    def _fill(self, deadline: float | None, progress: Callable[[int, int], None] | None,
              started: float) -> None:
        """best[S] and energy[S] for every non-empty subset S, in increasing order of S (each
        from the subsets one area smaller)."""
        size = 1 << self.n
        blank = [INF] * len(self.nodes)
        for mask in range(1, size):
            if not mask & 0xFF:
                if deadline is not None and time.perf_counter() > deadline:
                    raise PlanTimeout(
                        f"the exact planner stopped after {time.perf_counter() - started:.1f} s "
                        f"({mask:,} of {size:,} subsets): raise the timeout or plan fewer areas"
                    )
                if progress is not None:
                    progress(mask, size)
            row = blank.copy()
            bits = mask
            while bits:
                low = bits & -bits
                a = low.bit_length() - 1
                bits ^= low
                prev = mask ^ low
                if prev == 0:
                    for v in self.nodes_of[a]:
                        row[v] = self.first[v]
                else:
                    before = self.best[prev]
                    into = self.into
                    for v in self.nodes_of[a]:
                        row[v] = min(map(add, before, into[v]))
            self.best[mask] = row
            self.energy[mask] = min(map(add, row, self.home))
        if progress is not None:
            progress(size, size)

    def route(self, mask: int) -> tuple[list[int], float]:
        """The nodes of the cheapest plan for exactly `mask`, in order, and its last leg."""
        row = self.best[mask]
        totals = list(map(add, row, self.home))
        last = min(range(len(totals)), key=totals.__getitem__)
        route = [last]
        while True:
            v = route[-1]
            prev = mask & ~(1 << self.nodes[v].area)
            if prev == 0:
                break
            before = self.best[prev]
            into = self.into[v]
            u = min(range(len(before)), key=lambda i: before[i] + into[i])
            route.append(u)
            mask = prev
        route.reverse()
        return route, self.home[last]


def _mandatory_mask(problem: PlanProblem) -> int:
    return sum(1 << a for a, area in enumerate(problem.areas) if area.mandatory)


def _cover(energy: Sequence[float], n: int) -> list[float]:
    """cover[S] = least energy of a plan that surveys at least the areas of S."""
    cover = list(energy)
    for bit in range(n):
        step = 1 << bit
        for mask in range(len(cover)):
            if not mask & step and cover[mask | step] < cover[mask]:
                cover[mask] = cover[mask | step]
    return cover


def minimal_conflict(cover: Sequence[float], required: int, limit: float, n: int) -> int:
    """Seed 001 Algorithm 1 (deletion form): shrink `required` while it still cannot be served.

    Serving is monotone (a plan that serves S serves every subset of S), so the result is
    minimal: removing any one of its areas leaves a set some feasible plan serves."""
    core = required
    for bit in range(n):
        if core & (1 << bit) and cover[core & ~(1 << bit)] > limit:
            core &= ~(1 << bit)
    return core


def solve(
    problem: PlanProblem,
    timeout_s: float | None = 60.0,
    progress: Callable[[int, int], None] | None = None,
) -> Plan:
    """The best feasible plan (reward first, then energy), or why there is none.

    Raises PlanTooLarge before starting when the problem exceeds the state bound, and
    PlanTimeout when `timeout_s` passes."""
    deadline = None if timeout_s is None else time.perf_counter() + timeout_s
    tables = _Tables(problem, deadline, progress)
    limit = problem.vehicle.limit_wh
    required = _mandatory_mask(problem)
    size = 1 << tables.n
    stats = {"areas": tables.n, "passes": len(tables.nodes), "states": size * len(tables.nodes),
             "seconds": tables.elapsed_s}
    best_mask = -1
    best_key = (-INF, -INF)
    objective = problem.objective
    for mask in range(size):
        if mask & required != required or tables.energy[mask] > limit:
            continue
        key = (objective(tables.rewards[mask], tables.energy[mask]), -tables.energy[mask])
        if best_mask < 0 or key > best_key:
            best_mask, best_key = mask, key
    if best_mask < 0:
        return _infeasible(problem, tables, required, stats)
    if best_mask == 0:
        return Plan(True, 0.0, tables.direct, limit, (), tables.direct,
                    value=objective(0.0, tables.direct), stats=stats)
    route, home = tables.route(best_mask)
    return Plan(
        True,
        tables.rewards[best_mask],
        tables.energy[best_mask],
        limit,
        _steps(problem, tables, route),
        home,
        value=objective(tables.rewards[best_mask], tables.energy[best_mask]),
        stats=stats,
    )


def _infeasible(problem: PlanProblem, tables: _Tables, required: int,
                stats: dict[str, Any]) -> Plan:
    """No plan: the smallest set of mandatory areas that cannot be served together (none when
    even the direct way to recovery is too long), said in words."""
    limit = problem.vehicle.limit_wh
    cover = _cover(tables.energy, tables.n)
    core = minimal_conflict(cover, required, limit, tables.n)
    ids = tuple(area.id for a, area in enumerate(problem.areas) if core & (1 << a))
    if not ids:
        message = (
            f"even going straight from the start to recovery needs {tables.direct:,.1f} Wh, "
            f"more than the {limit:,.1f} Wh the vehicle may use (battery less reserve)"
        )
    else:
        need = cover[core]
        amount = "no route at all" if need == INF else f"at least {need:,.1f} Wh"
        message = (
            f"the mandatory areas {', '.join(ids)} cannot be surveyed together: that needs "
            f"{amount}, more than the {limit:,.1f} Wh the vehicle may use (battery less "
            "reserve); without any one of them the rest can be served"
        )
    return Plan(False, limit_wh=limit, conflict=ids, message=message, stats=stats)


def _steps(problem: PlanProblem, tables: _Tables, route: Sequence[int]) -> tuple[Step, ...]:
    """The route's passes as plan steps, each with the leg to it and its survey energy."""
    steps = []
    previous: int | None = None
    rate = problem.vehicle.transit_wh_per_m
    for v in route:
        node = tables.nodes[v]
        origin = problem.start if previous is None else tables.nodes[previous].exit
        steps.append(
            Step(problem.areas[node.area].id, node.pass_index, _leg(rate, origin, node.entry),
                 node.survey_wh)
        )
        previous = v
    return tuple(steps)


def plan_energy(problem: PlanProblem, order: Sequence[str], passes: dict[str, int]) -> float:
    """Energy of a given plan by the problem's definition (no checks)."""
    rate = problem.vehicle.transit_wh_per_m
    areas = {area.id: area for area in problem.areas}
    position = problem.start
    total = 0.0
    for area_id in order:
        pass_ = areas[area_id].passes[passes.get(area_id, 0)]
        total += _leg(rate, position, pass_.entry) + pass_.survey_wh
        position = pass_.exit
    return total + _leg(rate, position, problem.recovery)
