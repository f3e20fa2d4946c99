"""Path properties (seed 001, section 6.2): conditions that must hold on every path of the
mission, checked symbolically, never by enumerating paths.

    {"id": "P1", "always": "not (behavior == 'surface' and context('shipping_lane'))"}
    {"id": "P2", "never": "depth_m < 2 and context('shipping_lane')"}
    {"id": "P3", "max": {"energy_wh": 800, "duration_s": 20000}}

`always` and `never` are state properties. A goal's states are those its orders allow: its
envelope and facts (behaviour, area and the area's tags), the vehicle envelope, the quantity
domains and the constraints in scope (a state outside them ends the goal with `violate`). A
state property fails on some path exactly when it fails at some goal reachable from the start,
so each goal is decided once (by the goal's facts alone where they decide it, by z3
otherwise) and the counterexample is the shortest path from the start through a failing goal to
a terminal (breadth-first distances both ways).

`max` bounds a resource over every path (seed 001, Lemma 2: the vehicle does not run out of
battery). A path costs its goals and the legs of the edges it takes, as BUDGET charges them
(verify/costs.py); the counterexample is
the shortest path whose total exceeds the bound, found by dynamic programming over the DAG by
path length.
"""

from __future__ import annotations

import functools
from collections import deque
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any, Literal

import numpy as np

from ..orders.expressions.reads import Reads
from ..orders.findings import Finding, error, warning
from ..orders.model import BUDGET_QUANTITIES, OUTCOMES, Goal, Orders, PathProperty
from .budget import UNITS, reportable_total
from .costs import graph_costs
from .expressions import Expr, fold, number_words, quantity_words, reads, with_unit
from .graph import MissionGraph, build_graph
from .logic import (
    DEFAULT_TIMEOUT_MS,
    DEFAULT_TOTAL_S,
    WALL_CAP_REACHED,
    Item,
    Limits,
    LogicCache,
    LogicModel,
    LogicRun,
    expr_formula,
    join_words,
)
from .logic import run as logic_run
from .logic.collector import collector_paused
from .paths import topological_order

# Above this many (goal x path length) steps, the shortest resource counterexample falls back
# to the costliest path (still a counterexample, not necessarily the shortest).
MAX_LAYER_WORK = 2_000_000


@dataclass(frozen=True)
class CounterPath:
    goals: tuple[str, ...]
    outcomes: tuple[str, ...]
    terminal: str

    def steps(self) -> str:
        return ", ".join(f"{g} {o}" for g, o in zip(self.goals, self.outcomes, strict=True))

    def to_json(self) -> dict[str, Any]:
        return {"goals": list(self.goals), "outcomes": list(self.outcomes),
                "terminal": self.terminal}


# ---------------------------------------------------------------------------------------------
# Shortest paths over the mission graph


def distances_from_start(graph: MissionGraph) -> list[int]:
    """Outcomes from the start to each goal (-1 when unreachable)."""
    n = graph.goal_count
    dist = [-1] * n
    if graph.start is None:
        return dist
    succ, extra = graph.succ, graph.extra_targets
    dist[graph.start] = 0
    queue = deque([graph.start])
    while queue:
        node = queue.popleft()
        step = dist[node] + 1
        for target in succ[node] if node not in extra else (*succ[node], *extra[node]):
            if 0 <= target < n and dist[target] < 0:
                dist[target] = step
                queue.append(target)
    return dist


def distances_to_terminal(graph: MissionGraph) -> list[int]:
    """Goals on the shortest way from each goal to a terminal, itself included (-1: none)."""
    n = graph.goal_count
    reverse: list[list[int]] = [[] for _ in range(n)]
    dist = [-1] * n
    queue: deque[int] = deque()
    for node, row in enumerate(graph.succ):
        for target in row:
            if target >= n:
                if dist[node] < 0:
                    dist[node] = 1
                    queue.append(node)
            elif target >= 0:
                reverse[target].append(node)
    while queue:
        node = queue.popleft()
        for parent in reverse[node]:
            if dist[parent] < 0:
                dist[parent] = dist[node] + 1
                queue.append(parent)
    return dist


def _prefix(graph: MissionGraph, node: int) -> tuple[list[str], list[str]]:
    outcomes = graph.outcomes_to(node) or []
    goals: list[str] = []
    current = graph.start
    assert current is not None
    for outcome in outcomes:
        goals.append(graph.goal_ids[current])
        current = graph.succ[current][OUTCOMES.index(outcome)]
    return goals, outcomes


def path_through(graph: MissionGraph, node: int, to_terminal: list[int]) -> CounterPath:
    """The shortest path from the start through a goal to a terminal."""
    goals, outcomes = _prefix(graph, node)
    current = node
    while True:
        goals.append(graph.goal_ids[current])
        best_k, best = -1, None
        for k, target in enumerate(graph.succ[current]):
            if target < 0:
                continue
            length = 0 if target >= graph.goal_count else to_terminal[target]
            if length < 0:
                continue
            if best is None or length < best:
                best_k, best = k, length
        if best_k < 0:  # no way on: the path ends at this goal
            return CounterPath(tuple(goals), tuple(outcomes), "")
        outcomes.append(OUTCOMES[best_k])
        target = graph.succ[current][best_k]
        if target >= graph.goal_count:
            return CounterPath(tuple(goals), tuple(outcomes), graph.node_id(target))
        current = target


def shortest_through_any(graph: MissionGraph, nodes: Sequence[int]) -> tuple[int, CounterPath]:
    """Of several goals, the one on the shortest complete path from the start, and that path."""
    from_start = distances_from_start(graph)
    to_terminal = distances_to_terminal(graph)

    def length(node: int) -> tuple[int, int]:
        tail = to_terminal[node] if to_terminal[node] >= 0 else graph.goal_count + 1
        return from_start[node] + tail, node

    best = min((n for n in nodes if from_start[n] >= 0), key=length)
    return best, path_through(graph, best, to_terminal)


Legs = Sequence[tuple[float, float, float]]


def shortest_exceeding_path(
    graph: MissionGraph, costs: Sequence[float], bound: float, legs: Legs | None = None
) -> tuple[CounterPath, float, bool] | None:
    """The shortest complete path whose total cost exceeds a bound: (path, its total, whether it
    is proven shortest), or None when no path exceeds the bound or paths cannot be counted.
    Costs are per goal node, `legs` per outcome edge (the leg each outcome takes), all
    non-negative."""
    order = topological_order(graph)
    if order is None or graph.start is None:
        return None
    n = graph.goal_count
    succ = graph.succ
    edge = legs if legs is not None else [(0.0, 0.0, 0.0)] * n
    worst, longest = _worst_and_longest(order, succ, costs, edge, n)
    if worst[graph.start] <= bound:
        return None
    if len(order) * longest[graph.start] <= MAX_LAYER_WORK:
        found = _shortest_by_length(graph, order, costs, edge, bound, longest[graph.start])
        if found is not None:
            return found[0], reportable_total(found[1]), True
    return _costliest(graph, worst, edge), reportable_total(worst[graph.start]), False


def _worst_and_longest(order: list[int], succ: Sequence[tuple[int, int, int]],
                       costs: Sequence[float], legs: Legs, n: int
                       ) -> tuple[list[float], list[int]]:
    """Per goal of `order` (successors first), the costliest path from it to a terminal and
    the most goals on such a path. The float sums and maxima of the loop they replace (the
    same additions, the first of equal maxima), in one pass with the outcomes in line."""
    worst = [0.0] * n
    longest = [0] * n
    for node in order:
        first, second, third = succ[node]
        to_first, to_second, to_third = legs[node]
        to_first += 0.0 if first >= n else worst[first]
        to_second += 0.0 if second >= n else worst[second]
        to_third += 0.0 if third >= n else worst[third]
        most = to_first
        if to_second > most:
            most = to_second
        if to_third > most:
            most = to_third
        worst[node] = costs[node] + most
        deepest = 0 if first >= n else longest[first]
        if second < n and longest[second] > deepest:
            deepest = longest[second]
        if third < n and longest[third] > deepest:
            deepest = longest[third]
        longest[node] = 1 + deepest
    return worst, longest


def _shortest_by_length(
    graph: MissionGraph, order: list[int], costs: Sequence[float], legs: Legs, bound: float,
    limit: int
) -> tuple[CounterPath, float] | None:
    n = graph.goal_count
    succ = graph.succ
    minus = float("-inf")
    # Each layer reads only the one before it, so a layer is one array operation over every
    # goal (an edit revalidates in milliseconds, not the seconds of a loop over goals per
    # layer). float64 sums and maxima are the IEEE operations the loop made: equal results.
    # Targets: a goal, `n` for a terminal, `n + 1` for no successor.
    targets = np.array([[t if 0 <= t < n else (n if t >= n else n + 1) for t in row]
                        for row in succ], dtype=np.intp).reshape(n, 3)
    leg = np.array(legs, dtype=np.float64).reshape(n, 3)
    cost = np.array(costs[:n], dtype=np.float64)
    ordered = np.zeros(n, dtype=bool)
    ordered[order] = True

    def layer_after(previous: np.ndarray | None) -> np.ndarray:
        """layer[node]: the largest cost of a path of one goal more than `previous`'s from
        node to a terminal (of one goal, into a terminal, when there is no previous)."""
        tail = np.full(n + 2, minus)
        if previous is None:
            tail[n] = 0.0
        else:
            tail[:n] = previous
        reached = tail[targets]
        best = np.where(reached > minus, leg + reached, minus).max(axis=1)
        return np.where(ordered & (best > minus), cost + best, minus)

    def onward(node: int, previous: np.ndarray | None) -> list[float]:
        """Per outcome, the leg and the most the rest of the path adds (-inf: none)."""
        return [legs[node][k] + (0.0 if t >= n else minus) if previous is None else
                (legs[node][k] + float(previous[t]) if 0 <= t < n and previous[t] > minus
                 else minus)
                for k, t in enumerate(succ[node])]

    # layers[k][node]: the largest cost of a path of exactly k+1 goals from node to a terminal.
    layers = [layer_after(None)]
    start = graph.start
    assert start is not None
    while layers[-1][start] <= bound and len(layers) < limit:
        layers.append(layer_after(layers[-1]))
    if layers[-1][start] <= bound:
        return None
    total = float(layers[-1][start])
    goals: list[str] = []
    outcomes: list[str] = []
    node = start
    for k in range(len(layers) - 1, -1, -1):
        goals.append(graph.goal_ids[node])
        # The outcome the layer's best came through: the same sums, so equal exactly.
        options = onward(node, layers[k - 1] if k else None)
        j = options.index(max(options))
        outcomes.append(OUTCOMES[j])
        if k == 0:
            return CounterPath(tuple(goals), tuple(outcomes), graph.node_id(succ[node][j])), total
        node = succ[node][j]
    raise AssertionError("unreachable")  # pragma: no cover


def _costliest(graph: MissionGraph, worst: list[float], legs: Legs) -> CounterPath:
    n = graph.goal_count
    node = graph.start
    assert node is not None
    goals: list[str] = []
    outcomes: list[str] = []
    while node < n:
        options = [legs[node][k] + (0.0 if t >= n else worst[t])
                   for k, t in enumerate(graph.succ[node])]
        k = max(range(3), key=lambda i: (options[i], -i))
        goals.append(graph.goal_ids[node])
        outcomes.append(OUTCOMES[k])
        node = graph.succ[node][k]
    return CounterPath(tuple(goals), tuple(outcomes), graph.node_id(node))


# ---------------------------------------------------------------------------------------------
# Property checks


@dataclass(frozen=True)
class _StateProperty:
    prop: PathProperty
    mode: Literal["always", "never"]
    expr: Expr
    text: str


@dataclass(frozen=True)
class GoalVerdict:
    fails: bool
    # Values that let the property fail; None: not yet asked (only the goal a finding
    # reports needs them, and a model costs a z3 context of its own).
    witness: tuple[tuple[str, str], ...] | None
    undecided: str | None


def _label(prop: PathProperty) -> str:
    return f"{prop.id} ({prop.text})" if prop.text else prop.id


def check_properties(
    orders: Orders,
    graph: MissionGraph | None = None,
    cache: LogicCache | None = None,
    *,
    timeout_ms: int = DEFAULT_TIMEOUT_MS,
    total_timeout_s: float = DEFAULT_TOTAL_S,
    limits: Limits | None = None,
) -> list[Finding]:
    """EXPR findings for property expressions and PROPERTY findings with the shortest
    counterexample path from the start. The solver's limits as check_logic's."""
    # As for check_logic: the goals' units, verdicts and items it builds are long-lived, and
    # collections during the check only walk them again.
    with collector_paused():
        return _check_properties(orders, graph, cache, timeout_ms, total_timeout_s, limits)


def _check_properties(orders: Orders, graph: MissionGraph | None, cache: LogicCache | None,
                      timeout_ms: int, total_timeout_s: float, limits: Limits | None
                      ) -> list[Finding]:
    graph = graph or build_graph(orders)
    model = cache.model(orders) if cache is not None else LogicModel(orders)
    findings: list[Finding] = []
    states: list[_StateProperty] = []
    bounds: list[tuple[PathProperty, str, float]] = []
    # check_logic reports the EXPR findings of constraints and norms; here only properties'.
    expr_findings: list[Finding] = []
    for prop in orders.properties:
        modes: tuple[Literal["always", "never"], ...] = ("always", "never")
        for mode in modes:
            text = getattr(prop, mode)
            if text is None:
                continue
            expr = model.parse_condition(text, f"{prop.id} {mode}", prop.id, mode,
                                         expr_findings)
            if expr is not None:
                states.append(_StateProperty(prop, mode, expr, text))
        bounds.extend(_bounds(prop, findings))
        if (prop.always is None and prop.never is None and prop.pattern is None
                and not (prop.model_extra or {}).get("max")):
            findings.append(error("EXPR", [prop.id], f"{prop.id} states nothing: give 'always', "
                                  "'never' or 'max'.", field="always"))
    findings[:0] = expr_findings
    if graph.start is None:
        return findings
    if states:
        from_start = distances_from_start(graph)
        with model.lock:
            run = LogicRun(model, cache,
                           limits or Limits.start(timeout_ms, total_timeout_s))
            for state in states:
                findings.extend(_check_state(model, run, graph, state, from_start))
    for prop, quantity, bound in bounds:
        findings.extend(_check_bound(orders, graph, prop, quantity, bound))
    return findings


def _bounds(prop: PathProperty, findings: list[Finding]) -> list[tuple[PathProperty, str, float]]:
    raw = (prop.model_extra or {}).get("max")
    if raw is None:
        return []
    if not isinstance(raw, dict):
        findings.append(error("EXPR", [prop.id], f"{prop.id} max: give resource bounds as an "
                              'object, e.g. {"energy_wh": 800}.', field="max"))
        return []
    result = []
    for quantity, value in raw.items():
        if quantity not in BUDGET_QUANTITIES:
            findings.append(error(
                "EXPR", [prop.id],
                f"{prop.id} max: unknown resource {quantity!r}; use "
                f"{' or '.join(BUDGET_QUANTITIES)}.", field="max"))
        elif isinstance(value, bool) or not isinstance(value, int | float) or value < 0:
            findings.append(error(
                "EXPR", [prop.id],
                f"{prop.id} max: the bound for {quantity} must be a number of at least 0.",
                field="max"))
        else:
            result.append((prop, quantity, float(value)))
    return result


def _check_state(model: LogicModel, run: LogicRun, graph: MissionGraph,
                 state: _StateProperty, from_start: list[int]) -> list[Finding]:
    expr_reads = reads(state.expr)
    key = f"prop:{state.prop.id}:{state.mode}"
    # The item states that the property fails in a state: `always` fails where the condition
    # can be false, `never` where it can be true.
    negate = state.mode == "always"
    failing = Item(
        key, "property", state.prop.id, f"{state.prop.id} {state.mode}: {state.text}",
        f"{key}|{state.text}|{model.specs(expr_reads.quantities)}",
        expr_formula(state.expr, negate=negate),
        quantities=tuple(sorted(expr_reads.quantities)),
        # Bounds propagation (logic/bounds.py) decides most goals' states without z3.
        meaning=("expr", ("prop", key, state.text, negate), (state.expr, negate)),
    )
    bad, undecided = _failing_goals(model, run, graph, state, failing, expr_reads, from_start)
    findings: list[Finding] = []
    if bad:
        node, path = shortest_through_any(graph, list(bad))
        verdict = bad[node]
        if verdict.witness is None:  # the solver's: only the reported goal's values are asked
            verdict = _witnessed(run, graph.goals[node], failing, expr_reads)
        findings.append(_counterexample(model, graph, state, bad, (node, path), verdict))
    if undecided:
        # The wall-clock cap ends the work on a busy machine, however easy what is left.
        capped = WALL_CAP_REACHED in undecided.values()
        why = (f"the machine was too busy to finish within the wall-clock cap of "
               f"{run.limits.wall_cap_s:g} s" if capped else "solver timeout")
        goals = list(undecided)
        findings.append(warning(
            "PROPERTY", goals,
            f"{_label(state.prop)} could not be decided at {', '.join(goals[:20])} ({why}).",
            property=state.prop.id,
            # Marked so that the report part is not kept: another run may decide it.
            undecided=WALL_CAP_REACHED if capped else next(iter(undecided.values())),
        ))
    return findings


def _failing_goals(model: LogicModel, run: LogicRun, graph: MissionGraph,
                   state: _StateProperty, failing: Item, expr_reads: Reads,
                   from_start: list[int]) -> tuple[dict[int, GoalVerdict], dict[str, str]]:
    """The reachable goals where the property can fail (by graph node, with their verdict),
    and those undecided (with why). `from_start`: distances_from_start(graph)."""
    mission = run.mission()
    bad: dict[int, GoalVerdict] = {}
    undecided: dict[str, str] = {}
    for node, goal in enumerate(graph.goals):
        if from_start[node] < 0:
            continue
        verdict = _goal_verdict(model, run, goal, state, failing, expr_reads, mission.quarantined)
        if verdict is None:
            continue
        if verdict.undecided:
            undecided[goal.id] = verdict.undecided
        elif verdict.fails:
            bad[node] = verdict
    return bad, undecided


def _goal_verdict(model: LogicModel, run: LogicRun, goal: Goal, state: _StateProperty,
                  failing: Item, expr_reads: Reads, quarantined: frozenset[str]
                  ) -> GoalVerdict | None:
    """Whether the property can fail while the goal runs (None: its facts alone say it cannot).
    Carried from the model before an edit that left the goal and the rest of the orders as
    they were (LogicModel.carry_goal_items): a verdict of the facts alone, or a solver's that
    the cache still holds under its key."""
    memo = (goal.id, quarantined, failing.key, failing.source)
    carried = model.property_verdicts.get(memo)
    if carried is not None:
        key, known = carried
        if key is None or run.cache.holds(key, known):
            return known if isinstance(known, GoalVerdict) else None
    decided = fold(state.expr, model.facts(goal))
    if decided is not None:
        by_facts = GoalVerdict(True, (), None) if decided is (state.mode == "never") else None
        model.property_verdicts[memo] = (None, by_facts)
        return by_facts
    items, _ = run.goal_items(goal, quarantined, [expr_reads])
    key, solved = run.keyed(
        "property", [*items, failing],
        functools.partial(_solve_state, run, items, failing, run.block(quarantined)))
    verdict: GoalVerdict = solved
    model.property_verdicts[memo] = (key, verdict)
    return verdict


def _counterexample(model: LogicModel, graph: MissionGraph, state: _StateProperty,
                    bad: dict[int, GoalVerdict], nearest: tuple[int, CounterPath],
                    verdict: GoalVerdict) -> Finding:
    """The PROPERTY error at the failing goal nearest the start (`nearest`: its node and
    shortest path), with the values (or facts) that let the property fail there."""
    node, path = nearest
    goal = graph.goals[node]
    if verdict.witness:
        values = join_words([
            f"{quantity_words(q, model.quantities)} {with_unit(v, model.unit(q))}"
            if v not in {"true", "false"} else f"{quantity_words(q, model.quantities)} {v}"
            for q, v in verdict.witness
        ])
        why = f"the orders of {model.goal_label(goal)} allow {values}"
    else:
        needs = reads(state.expr)
        facts_words = [i.phrase for i in model.fact_items(goal, needs)]
        why = join_words(facts_words) if facts_words else f"at {model.goal_label(goal)}"
    words = model.words(state.expr)
    rule = f"rules out {words}" if state.mode == "never" else f"requires {words} always"
    ending = f" -> {path.terminal}" if path.terminal else " (no terminal follows)"
    return error(
        "PROPERTY",
        [*path.goals, *([path.terminal] if path.terminal else [])],
        f"{_label(state.prop)} fails at {goal.id}: {why}, but {state.prop.id} {rule}. "
        f"Shortest counterexample: {path.steps()}{ending}.",
        property=state.prop.id,
        goal=goal.id,
        path=path.to_json(),
        witness=dict(verdict.witness or ()),
        failing_goals=[graph.goal_ids[n] for n in sorted(bad)],
    )


def _solve_state(run: LogicRun, items: list[Item], failing: Item,
                 base: frozenset[Item]) -> GoalVerdict:
    """Whether the state can fail. The screen's status is the answer when it decides (goals
    with the same formulas share it, bounds.py proves most without z3); the session decides
    the others. The values come later, for the reported goal alone (`_witnessed`)."""
    if logic_run.GROUP_CHECKS:
        status = run.screen.status([*items, failing], base)
        if status != "unknown":
            return GoalVerdict(status == "sat", None, None)
    session = run.session
    with session.scope([*items, failing]):
        result = session.check([*items, failing])
    if result.status == "unknown":
        return GoalVerdict(False, (), result.reason)
    return GoalVerdict(result.status == "sat", None, None)


def _witnessed(run: LogicRun, goal: Goal, failing: Item, expr_reads: Reads) -> GoalVerdict:
    """The reported goal's verdict with the values that let the property fail there: solved
    in the unit's own context, so they are the same whatever was checked before."""
    mission = run.mission()
    items, _ = run.goal_items(goal, mission.quarantined, [expr_reads])

    def solve() -> GoalVerdict:
        session = run.session
        with session.scope([*items, failing]):
            result = session.check([*items, failing])
            if result.status != "sat":  # out of time: the finding names no values
                return GoalVerdict(True, (), result.reason or None)
            witness = session.witness(failing.quantities, items=[*items, failing])
        return GoalVerdict(True, tuple(sorted(witness.items())), None)

    # The live block named: with every verdict carried, no unit of this run has named it.
    verdict: GoalVerdict = run.cached("property-witness", [*items, failing], solve,
                                      base=run.block(mission.quarantined))
    return verdict


def _check_bound(orders: Orders, graph: MissionGraph, prop: PathProperty, quantity: str,
                 bound: float) -> list[Finding]:
    # A path costs what BUDGET charges it: its goals and the legs of the edges it takes.
    priced = graph_costs(orders, graph, quantity)
    unknown = [graph.goal_ids[n] for n in priced.unknown]
    found = shortest_exceeding_path(graph, priced.goal, bound, priced.leg)
    unit, noun = UNITS[quantity]
    findings: list[Finding] = []
    if found is not None:
        path, total, shortest = found
        which = "the shortest path" if shortest else "the costliest path"
        findings.append(error(
            "PROPERTY",
            [*path.goals, path.terminal],
            f"{_label(prop)} fails: the path {path.steps()} -> {path.terminal} needs "
            f"{number_words(round(total, 1))} {unit} of {noun}, more than the bound of "
            f"{number_words(bound)} {unit} ({which} that exceeds it).",
            property=prop.id,
            quantity=quantity,
            total=round(total, 6),
            bound=bound,
            shortest=shortest,
            path=path.to_json(),
        ))
    elif unknown:
        findings.append(warning(
            "PROPERTY", unknown,
            f"{_label(prop)} cannot be proven for every path: goals {', '.join(unknown[:20])} "
            f"have no {noun} cost and none can be estimated.",
            property=prop.id,
            quantity=quantity,
        ))
    return findings

