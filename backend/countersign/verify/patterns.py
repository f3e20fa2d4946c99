"""Temporal properties as specification patterns (Dwyer, Avrunin and Corbett), over every path.

A path is a sequence of positions: each goal with the outcome it ended with, then the terminal.
A pattern (absence, existence, universality, precedence, response, bounded response by steps,
time or energy) holds in a scope (globally, before r, after q, between q and r). Each pattern is
a small monitor whose state is run over the DAG as a product (node, monitor state), breadth
first by path length, so the first violating path found is a shortest counterexample and no
path is enumerated. Cost-bounded responses keep the cost since the oldest unanswered `p` in the
state; of two states that differ only in that cost, the larger dominates (it violates no later)
and the smaller, reached later, is dropped.

An event happens when its goal ends (a terminal's when the mission ends), so a bound runs from
the `p` event to the `s` event: the leg out of the `p` goal, every goal after it up to and
including the `s` goal, and the legs between them. The `p` goal's own cost was spent before `p`
happened and does not count; a terminal costs nothing. Goals and legs cost what BUDGET charges
(budget.goal_cost, budget.leg_cost); in steps each goal counts 1 and a leg 0.

Semantics on finite paths (Dwyer's): `before r` and `between q and r` only count a segment that
`r` closes; `after q` runs from the first `q` to the end; a segment starts at `q` (inclusive)
and stops before `r`; in `between`, a position with both q and r opens nothing.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

from ..orders.findings import Finding, error, warning
from ..orders.model import OUTCOMES, Event, Orders, PathProperty
from ..orders.pattern_words import pattern_sentence
from .costs import goal_cost, leg_cost
from .graph import MissionGraph
from .legs import MissionLegs, leg_lengths, mission_legs
from .paths import topological_order

NEEDS = {"absence": ("p",), "existence": ("p",), "universality": ("p",),
         "precedence": ("p", "s"), "response": ("p", "s"), "bounded_response": ("p", "s")}
SCOPE_NEEDS = {"globally": (), "before": ("r",), "after": ("q",), "between": ("q", "r")}
MAX_STATES = 2_000_000  # product states per property; past it the verdict is a warning

# Monitor state: (phase, flags, elapsed). phase: 0 outside a scope segment, 1 inside, 2 no
# segment can open any more; flags: bit 0 "p seen", bit 1 "segment violated", bit 2 "s seen",
# bit 3 "response pending", bit 4 "a counted segment was violated" (absorbing).
State = tuple[int, int, float]
CONFIRMED = 16


@dataclass(frozen=True)
class Position:
    goal: str | None
    outcome: str | None
    behavior: str | None
    terminal: str | None
    kind: str | None


def matches(event: Event | None, at: Position) -> bool:
    if event is None:
        return False
    for name in ("goal", "outcome", "behavior", "terminal", "kind"):
        wanted = getattr(event, name)
        if wanted is None:
            continue
        have = getattr(at, name)
        if have is None or (have not in wanted if isinstance(wanted, list) else have != wanted):
            return False
    return True


@dataclass(frozen=True)
class Monitor:
    prop: PathProperty
    # The most a bounded response may cost from its `p` event to its `s` event.
    limit: float | None

    def initial(self) -> State:
        return (1 if self.prop.scope in ("globally", "before") else 0, 0, 0.0)

    def _close(self, flags: int) -> bool:
        """Whether the segment that just closed violates the pattern."""
        pattern = self.prop.pattern
        if pattern == "existence":
            return not flags & 1
        if pattern in ("response", "bounded_response"):
            return bool(flags & 2 or flags & 8)
        return bool(flags & 2)

    def step(self, state: State, at: Position, cost: float, leg: float) -> State:
        """The state after the position `at`: its goal ran for `cost`, then took the leg of
        its outcome for `leg` (both 0 at a terminal)."""
        phase, flags, elapsed = state
        prop = self.prop
        scope = prop.scope
        confirmed = flags & CONFIRMED
        if phase == 1 and scope in ("before", "between") and matches(prop.r, at):
            if self._close(flags):
                confirmed = CONFIRMED
            return (2 if scope == "before" else 0, confirmed, 0.0)
        if phase == 0 and matches(prop.q, at) and not (scope == "between" and matches(prop.r, at)):
            phase, flags, elapsed = 1, 0, 0.0
        if phase != 1:
            return (phase, confirmed, 0.0)
        flags = self._observe(flags | confirmed, at)
        if prop.pattern == "bounded_response":
            flags, elapsed = self._bounded(flags, elapsed, at, cost, leg)
        return (phase, flags | confirmed, elapsed)

    def _observe(self, flags: int, at: Position) -> int:
        pattern = self.prop.pattern
        p = matches(self.prop.p, at)
        if pattern == "absence" and p:
            flags |= 2
        elif pattern == "existence" and p:
            flags |= 1
        elif pattern == "universality" and not p:
            flags |= 2
        elif pattern == "precedence":
            s = matches(self.prop.s, at)
            if p and not flags & 4 and not s:
                flags |= 2  # p before any s (s at the same position counts as before)
            if s:
                flags |= 4
        elif pattern == "response":
            s = matches(self.prop.s, at)
            if s:
                flags &= ~8
            elif p:
                flags |= 8
        return flags

    def _bounded(self, flags: int, elapsed: float, at: Position, cost: float, leg: float
                 ) -> tuple[int, float]:
        assert self.limit is not None
        s = matches(self.prop.s, at)
        if flags & 8:
            elapsed += cost  # this goal ran after the pending `p` happened
            if s:
                answered = flags & ~8
                return (answered | 2 if elapsed > self.limit else answered), 0.0
        elif matches(self.prop.p, at) and not s:
            # `p` happens as this goal ends: only what comes after it counts.
            flags |= 8
            elapsed = 0.0
        if not flags & 8:
            return flags, 0.0
        elapsed += leg
        if elapsed > self.limit:
            return (flags | 2) & ~8, 0.0
        return flags, elapsed

    def finish(self, state: State) -> bool:
        """Whether a path that ends in this state violates the property."""
        phase, flags, _ = state
        if flags & CONFIRMED:
            return True
        if phase == 1 and self.prop.scope in ("globally", "after"):
            return self._close(flags)
        return False


def _limit(prop: PathProperty) -> tuple[float | None, str | None]:
    within = prop.within
    if within is None:
        return None, None
    for quantity in ("steps", "duration_s", "energy_wh"):
        value = getattr(within, quantity)
        if value is not None:
            return float(value), quantity
    return None, None


@dataclass(frozen=True)
class Counterexample:
    goals: tuple[str, ...]
    outcomes: tuple[str, ...]
    terminal: str


def check_pattern(orders: Orders, graph: MissionGraph, prop: PathProperty,
                  legs: MissionLegs | None = None) -> Counterexample | str | None:
    """A shortest violating path, None when every path satisfies the property, or a reason why
    it cannot be decided."""
    limit, quantity = _limit(prop)
    monitor = Monitor(prop, limit)
    costs, leg_costs = _position_costs(orders, graph, quantity, legs)
    start = graph.start
    assert start is not None
    goal_count = graph.goal_count
    positions = [[Position(g.id, o, g.behavior, None, None) for o in OUTCOMES]
                 for g in graph.goals]
    ends = [Position(None, None, None, t.id, t.kind) for t in graph.terminals]
    first: State = monitor.initial()
    parent: dict[tuple[int, State], tuple[tuple[int, State], int] | None] = {(start, first): None}
    # For cost-bounded responses: the largest pending cost seen per (node, phase, flags) in an
    # earlier layer; within one layer only the largest survives.
    bounded_by_cost = limit is not None and quantity != "steps"
    best: dict[tuple[int, int, int], float] = {}
    # Interval pruning: a pending cost that cannot pass the limit on any way to the end
    # behaves like any other such cost, so all of them are one state (cost 0).
    room = _room(graph, costs, leg_costs) if bounded_by_cost else []
    slack = 1e-9 * (abs(limit) + 1.0) if limit is not None else 0.0
    layer: list[tuple[int, State]] = [(start, first)]
    while layer:
        candidates: dict[object, tuple[tuple[int, State], tuple[tuple[int, State], int]]] = {}
        for key in layer:
            node, state = key
            for k, target in enumerate(graph.succ[node]):
                after = monitor.step(state, positions[node][k], costs[node], leg_costs[node][k])
                if target >= goal_count:
                    final = monitor.step(after, ends[target - goal_count], 0.0, 0.0)
                    if monitor.finish(final):
                        return _path(graph, parent, key, k, target)
                    continue
                if bounded_by_cost and after[1] & 8 and limit is not None and (
                        after[2] + room[target] < limit - slack * (1.0 + room[target])):
                    after = (after[0], after[1], 0.0)
                nxt = (target, after)
                if nxt in parent:
                    continue
                slot: object = nxt
                if bounded_by_cost:
                    slot = (target, after[0], after[1])
                    if best.get(slot, -1.0) >= after[2]:
                        continue
                    held = candidates.get(slot)
                    if held is not None and held[0][1][2] >= after[2]:
                        continue
                candidates[slot] = (nxt, (key, k))
        layer = []
        for slot, (nxt, link) in candidates.items():
            if bounded_by_cost:
                best[slot] = nxt[1][2]  # type: ignore[index]
            parent[nxt] = link
            layer.append(nxt)
        if len(parent) > MAX_STATES:
            return "the pattern's product with the mission has too many states"
    return None


def _room(graph: MissionGraph, costs: list[float], leg_costs: list[list[float]]
          ) -> list[float]:
    """Per goal, the most cost any way from it to a terminal adds (its own and its legs
    included)."""
    order = topological_order(graph)
    assert order is not None
    goal_count = graph.goal_count
    room = [0.0] * goal_count
    for node in order:  # successors first
        room[node] = costs[node] + max(
            leg_costs[node][k] + (room[t] if t < goal_count else 0.0)
            for k, t in enumerate(graph.succ[node]))
    return room


def _position_costs(orders: Orders, graph: MissionGraph, quantity: str | None,
                    legs: MissionLegs | None) -> tuple[list[float], list[list[float]]]:
    """Each goal's cost and the cost of the leg of each of its outcomes, as BUDGET charges
    them (in steps: 1 per goal, legs free)."""
    if quantity is None or quantity == "steps":
        return [1.0] * graph.goal_count, [[0.0] * len(OUTCOMES)] * graph.goal_count
    vehicle = orders.target_vehicle()
    areas = orders.area_index()
    lengths = leg_lengths(orders, legs) if vehicle is not None and vehicle.speed_mps else {}
    return ([goal_cost(goal, quantity, vehicle, areas)[0] or 0.0 for goal in graph.goals],
            [[leg_cost(lengths.get((goal.id, outcome)), quantity, vehicle)
              for outcome in OUTCOMES] for goal in graph.goals])


def _path(graph: MissionGraph, parent: dict[tuple[int, State], tuple[tuple[int, State], int]
                                             | None],
          key: tuple[int, State], k: int, terminal: int) -> Counterexample:
    nodes: list[int] = []
    outcomes: list[int] = [k]
    current: tuple[int, State] | None = key
    while current is not None:
        nodes.append(current[0])
        link = parent[current]
        if link is None:
            break
        current, outcome = link
        outcomes.append(outcome)
    nodes.reverse()
    outcomes.reverse()
    return Counterexample(tuple(graph.goal_ids[n] for n in nodes),
                          tuple(OUTCOMES[o] for o in outcomes), graph.node_id(terminal))


def _problems(prop: PathProperty) -> list[str]:
    assert prop.pattern is not None
    missing = [f for f in (*NEEDS[prop.pattern], *SCOPE_NEEDS[prop.scope])
               if getattr(prop, f) is None]
    problems = [f"{prop.id} ({prop.pattern.replace('_', ' ')}, {prop.scope}) needs "
                f"{', '.join(repr(m) for m in missing)}"] if missing else []
    if prop.pattern == "bounded_response" and _limit(prop)[0] is None:
        problems.append(f"{prop.id} (bounded response) needs 'within' with steps, "
                        "duration_s or energy_wh")
    return problems


def check_patterns(orders: Orders, graph: MissionGraph,
                   sentence: Callable[[PathProperty], str] | None = None,
                   legs: MissionLegs | None = None) -> list[Finding]:
    findings: list[Finding] = []
    patterned = [p for p in orders.properties if p.pattern is not None]
    if not patterned:
        return findings
    countable = graph.start is not None and topological_order(graph) is not None
    if legs is None and any(_limit(p)[1] in ("duration_s", "energy_wh") for p in patterned):
        legs = mission_legs(orders)  # once for every property that charges legs
    for prop in patterned:
        problems = _problems(prop)
        if problems:
            findings.append(error("EXPR", [prop.id], "; ".join(problems) + ".", field="pattern"))
            continue
        if not countable:
            continue
        verdict = check_pattern(orders, graph, prop, legs)
        words = (sentence or pattern_sentence)(prop)
        if isinstance(verdict, str):
            findings.append(warning("PROPERTY", [prop.id], f"{prop.id} could not be decided: "
                                    f"{verdict}."))
        elif verdict is not None:
            steps = ", ".join(f"{g} {o}" for g, o in zip(verdict.goals, verdict.outcomes,
                                                         strict=True))
            findings.append(error(
                "PROPERTY", [prop.id, *verdict.goals, verdict.terminal],
                f"{prop.id} fails: {words} Counterexample: {steps} -> {verdict.terminal}.",
                path={"goals": list(verdict.goals), "outcomes": list(verdict.outcomes),
                      "terminal": verdict.terminal}))
    return findings
