"""Progressive goal refinement (seed 000 III.D): a goal carried out by sub-orders.

Every check sees the refined mission through one flat form. A refined goal is replaced by the
goals of its refinement, named `G1/G1.1` (nested: `G1/G1.2/G1.2.1`); an outcome edge into it
goes to its start, and an edge into a terminal of the refinement goes where the parent goes on
the outcome that terminal `returns`. The parent's constraints in scope apply to every goal
inside (`applies_to` naming it is widened to them).

A refinement with `within` is unrolled (DESIGN.md: "counted as its bounded unrolling"). The
time-out is checked each time a goal inside is about to commence:
- `steps` N: a goal commences only while fewer than N goals of this refinement have commenced
  (a refined goal inside counts once); its copy is `G1/G1.2#k`, the k-th goal commenced inside.
- `duration_s` D: a goal commences only while the goals of this refinement that have ended
  took less than D seconds in all (their durations as BUDGET prices them, given or estimated;
  legs are not counted); its copy is `G1/G1.2@Ts`, T the seconds spent inside before it.
Otherwise the refinement ends at once with `on_timeout` (fail or violate) and the mission goes
where the parent goes on that outcome. The start always commences. Copies are made only for the
states a path reaches, so path counts, costs and probabilities come from the same dynamic
programming over the flat DAG as for any orders, never from enumeration: each refined goal's
sub-graph (per time-out state) is built and counted once, whatever precedes it.
"""

from __future__ import annotations

import dataclasses
import re
from collections import deque
from collections.abc import Iterator, Mapping
from dataclasses import dataclass, field
from fractions import Fraction

from ..orders.findings import Finding, error, warning
from ..orders.model import (
    OUTCOMES,
    Area,
    Constraint,
    Goal,
    Orders,
    Refinement,
    RefinementTerminal,
    Terminal,
    Vehicle,
)
from .costs import goal_cost
from .graph import MissionGraph, build_graph
from .nesting import Exit, Nesting
from .structure import check_structure

SEP = "/"
MAX_DEPTH = 8  # refinements inside refinements
MAX_FLAT_GOALS = 10_000  # goals of the unrolled mission: bounds memory and every later check
_MARK = re.compile(r"[#@][^/]*")

State = int | Fraction | None


def has_refinements(orders: Orders) -> bool:
    return any(goal.refines is not None for goal in orders.goals)


def base_id(flat_id: str) -> str:
    """A flat id without its unrolling marks: `G1/G1.2#3` -> `G1/G1.2`."""
    return _MARK.sub("", flat_id)


@dataclass(frozen=True)
class Flat:
    """The refined mission, flat: `orders` unrolled (what paths, costs and probabilities
    read), `representative` with one goal per goal of the orders (what the per-goal checks
    read, so an unrolled loop is not solved N times), the hierarchy and what flattening found."""

    orders: Orders
    representative: Orders
    nesting: Nesting
    findings: list[Finding] = field(default_factory=list)


@dataclass(eq=False)
class _Level:
    prefix: str  # flat id of the refined goal + "/", "" at the top
    goals: dict[str, Goal]
    terminals: Mapping[str, Terminal]
    refinement: Refinement | None  # None at the top
    parent: tuple[_Level, str, State] | None
    chain: tuple[tuple[str, str], ...]
    depth: int
    durations: dict[str, Fraction | None] = field(default_factory=dict)

    def initial(self) -> State:
        within = self.refinement.within if self.refinement else None
        if within is None:
            return None
        return 0 if within.steps is not None else Fraction(0)

    def may_commence(self, state: State) -> bool:
        within = self.refinement.within if self.refinement else None
        if within is None or state is None:
            return True
        if within.steps is not None:
            return state < within.steps
        assert within.duration_s is not None
        return state < Fraction(repr(within.duration_s))

    def after(self, local: str, state: State) -> State | bool:
        """The state once goal `local` has ended; False when its duration is unknown."""
        if state is None:
            return None
        if isinstance(state, int):
            return state + 1
        spent = self.durations.get(local)
        return False if spent is None else state + spent

    def flat_id(self, local: str, state: State) -> str:
        if state is None:
            return self.prefix + local
        if isinstance(state, int):
            return f"{self.prefix}{local}#{state + 1}"
        seconds = int(state) if state.denominator == 1 else float(state)
        return f"{self.prefix}{local}@{seconds}s"


class _Flattener:
    def __init__(self, orders: Orders) -> None:
        self.orders = orders
        self.vehicle = orders.target_vehicle()
        self.areas = orders.area_index()
        self.goals: dict[str, Goal] = {}
        self.nesting = Nesting()
        self.levels: dict[tuple[int, str, State], _Level] = {}
        self.queue: deque[tuple[_Level, str, State]] = deque()
        self.placed: dict[int, set[str]] = {}  # per level: local goals with a flat copy
        self.all_levels: list[_Level] = []
        self.too_large = False
        self.top = self._level("", orders.goal_index(), orders.terminal_index(), None, None,
                               (), 0)

    def _level(self, prefix: str, goals: dict[str, Goal], terminals: Mapping[str, Terminal],
               refinement: Refinement | None, parent: tuple[_Level, str, State] | None,
               chain: tuple[tuple[str, str], ...], depth: int) -> _Level:
        level = _Level(prefix, goals, terminals, refinement, parent, chain, depth)
        if refinement is not None and refinement.within is not None \
                and refinement.within.duration_s is not None:
            for local, goal in goals.items():
                seconds, _ = goal_cost(goal, "duration_s", self.vehicle, self.areas)
                ok = seconds is not None and seconds > 0 and goal.refines is None
                level.durations[local] = Fraction(repr(seconds)) if ok else None
        self.all_levels.append(level)
        self.placed[id(level)] = set()
        return level

    def child(self, level: _Level, local: str, state: State) -> _Level | None:
        key = (id(level), local, state)
        if key in self.levels:
            return self.levels[key]
        goal = level.goals[local]
        refinement = goal.refines
        if refinement is None or level.depth >= MAX_DEPTH:
            return None
        flat = level.flat_id(local, state)
        goals: dict[str, Goal] = {}
        for inner in refinement.goals:
            goals.setdefault(inner.id, inner)
        terminals: dict[str, Terminal] = {}
        for terminal in refinement.terminals:
            if terminal.id not in goals:
                terminals.setdefault(terminal.id, terminal)
        made = self._level(flat + SEP, goals, terminals, refinement, (level, local, state),
                           (*level.chain, (flat, goal.label)), level.depth + 1)
        self.levels[key] = made
        return made

    def entry(self, level: _Level, local: str, state: State) -> str | None:
        """The flat goal where goal `local` (at `state`) begins: itself, or the start of its
        refinement (and of the refinements nested at that start)."""
        goal = level.goals[local]
        if goal.refines is None:
            flat = level.flat_id(local, state)
            if flat not in self.goals and not self.too_large:
                self.goals[flat] = goal  # a placeholder until the queue builds its copy
                self.queue.append((level, local, state))
                if len(self.goals) > MAX_FLAT_GOALS:
                    self.too_large = True
            return flat
        inner = self.child(level, local, state)
        if inner is None:
            return None
        start = inner.refinement.start if inner.refinement else None
        if not isinstance(start, str) or start not in inner.goals:
            return None
        self.placed[id(inner)].add(start)
        return self.entry(inner, start, inner.initial())

    def resolve(self, level: _Level, local: str, state: State, outcome: str
                ) -> tuple[str | None, tuple[Exit, ...]]:
        """Where goal `local` (at `state`) goes on `outcome`, and the refinements it leaves."""
        targets = level.goals[local].successors(outcome)
        if not targets:
            return None, ()
        target = targets[0]
        if target in level.goals:
            after = level.after(local, state)
            if after is False or after is True:
                return None, ()  # no duration to bound it by: REFINE says so
            if level.may_commence(after):
                self.placed[id(level)].add(target)
                return self.entry(level, target, after), ()
            timeout = level.refinement.on_timeout if level.refinement else None
            return self.leave(level, timeout, True)
        if level.parent is None:
            return target, ()  # a mission terminal, or an unknown id (G3 says so)
        terminal = level.terminals.get(target)
        if not isinstance(terminal, RefinementTerminal):
            return None, ()
        return self.leave(level, terminal.returns, False)

    def leave(self, level: _Level, returns: str | None, timed_out: bool
              ) -> tuple[str | None, tuple[Exit, ...]]:
        if level.parent is None or returns not in OUTCOMES:
            return None, ()
        parent, local, state = level.parent
        target, exits = self.resolve(parent, local, state, returns)
        if target is None:
            return None, ()
        return target, (Exit(level.prefix[:-1], returns, timed_out), *exits)

    def build(self, level: _Level, local: str, state: State) -> None:
        goal = level.goals[local]
        flat = level.flat_id(local, state)
        next_: dict[str, str | None] = {}
        for outcome in OUTCOMES:
            target, exits = self.resolve(level, local, state, outcome)
            next_[outcome] = target
            if exits:
                self.nesting.exits[(flat, outcome)] = exits
        if level.chain:
            self.nesting.parents[flat] = level.chain
        self.goals[flat] = goal.model_copy(update={"id": flat, "next": next_})

    def run(self) -> None:
        for local in self.top.goals:
            self.entry(self.top, local, None)
        while not self.too_large:
            while self.queue and not self.too_large:
                self.build(*self.queue.popleft())
            # Goals inside that no path reaches still get one copy, so the per-goal checks
            # (capability, constraints, norms, charts) see every goal the orders contain.
            missing = [(level, local) for level in self.all_levels
                       for local in level.goals if local not in self.placed[id(level)]]
            if not missing:
                break
            for level, local in missing:
                self.placed[id(level)].add(local)
                self.entry(level, local, level.initial())


def flatten(orders: Orders) -> Flat:
    """The refined mission as flat orders (see the module's docstring)."""
    work = _Flattener(orders)
    work.run()
    findings: list[Finding] = []
    if work.too_large:
        findings.append(error(
            "REFINE", [g.id for g in orders.goals if g.refines is not None],
            f"The bounded unrolling of the refinements has more than {MAX_FLAT_GOALS:,} goals: "
            "lower a time-out (within) or refine less deeply."))
    start = orders.start
    if isinstance(start, str) and start in work.top.goals:
        start = work.entry(work.top, start, None)
    goals = [] if work.too_large else list(work.goals.values())
    constraints = [_widen(c, work.goals) for c in orders.constraints]
    unrolled = orders.model_copy(update={"goals": goals, "start": start,
                                         "constraints": constraints})
    return Flat(unrolled, _representative(unrolled), work.nesting, findings)


def _widen(constraint: Constraint, goals: Mapping[str, Goal]) -> Constraint:
    """A constraint on a refined goal applies to every goal inside it instead."""
    if not isinstance(constraint.applies_to, list):
        return constraint
    scope: list[str] = []
    for named in constraint.applies_to:
        inside = [flat for flat in goals if flat.startswith(named + SEP)]
        scope.extend(inside if inside else [named])
    return constraint.model_copy(update={"applies_to": list(dict.fromkeys(scope))})


def _representative(unrolled: Orders) -> Orders:
    """One goal per goal of the orders (the first copy), named without unrolling marks."""
    goals: dict[str, Goal] = {}
    for goal in unrolled.goals:
        name = base_id(goal.id)
        if name not in goals:
            next_ = {o: None if t is None else base_id(t) for o, t in goal.next.items()
                     if isinstance(t, str) or t is None}
            goals[name] = goal.model_copy(update={"id": name, "next": next_})
    constraints = [
        c if not isinstance(c.applies_to, list) else c.model_copy(
            update={"applies_to": list(dict.fromkeys(base_id(g) for g in c.applies_to))})
        for c in unrolled.constraints
    ]
    start = base_id(unrolled.start) if isinstance(unrolled.start, str) else unrolled.start
    return unrolled.model_copy(update={"goals": list(goals.values()), "start": start,
                                       "constraints": constraints})


def dedupe_copies(findings: list[Finding]) -> list[Finding]:
    """Per-goal and per-edge findings of the unrolled mission, once per goal of the orders:
    a copy's finding is its original's, named without the marks."""
    seen: set[tuple[str, tuple[str, ...], str]] = set()
    result: list[Finding] = []
    for finding in findings:
        subjects = tuple(base_id(s) for s in finding.subjects)
        message = _MARK.sub("", finding.message) if "#" in finding.message \
            or "@" in finding.message else finding.message
        key = (finding.code, subjects, message)
        if key in seen:
            continue
        seen.add(key)
        result.append(Finding(finding.code, finding.severity, subjects, message,
                              finding.details))
    return result


# --- REFINE and the sub-orders' own structure ------------------------------------------------

def refine_findings(orders: Orders) -> list[Finding]:
    """Each refinement checked as orders (structure), plus REFINE: a terminal that returns no
    outcome or one the parent has no successor for, a loop without a time-out, a time-out
    that cannot bound its loop, nesting deeper than MAX_DEPTH, a property naming a refined
    goal (its outcome is its refinement's: name the goals inside)."""
    findings: list[Finding] = []
    vehicle = orders.target_vehicle()
    areas = orders.area_index()
    refined: set[str] = set()
    for path, goal, depth in _refined_goals(orders.goals, "", 1):
        refined.add(path)
        if depth > MAX_DEPTH:
            findings.append(error("REFINE", [path], f"{path} refines goals {depth} levels "
                                  f"deep; refinements nest at most {MAX_DEPTH} deep."))
            continue
        assert goal.refines is not None
        findings.extend(_check_refinement(path, goal, goal.refines, vehicle, areas))
    for prop in orders.properties:
        named = {g for e in (prop.p, prop.s, prop.q, prop.r) if e is not None
                 for g in ([e.goal] if isinstance(e.goal, str) else e.goal or [])}
        for goal_id in sorted(named & refined):
            findings.append(error(
                "REFINE", [prop.id, goal_id],
                f"{prop.id} names {goal_id}, which is carried out by its refinement: name "
                "the goals inside it or the goals after it instead."))
    return findings


def _refined_goals(goals: list[Goal], prefix: str, depth: int
                   ) -> Iterator[tuple[str, Goal, int]]:
    for goal in goals:
        if goal.refines is None:
            continue
        path = prefix + goal.id
        yield path, goal, depth
        if depth <= MAX_DEPTH:
            yield from _refined_goals(goal.refines.goals, path + SEP, depth + 1)


def _check_refinement(path: str, parent: Goal, refinement: Refinement,
                      vehicle: Vehicle | None, areas: dict[str, Area]) -> list[Finding]:
    used = {o for o in OUTCOMES if parent.successors(o)}
    return [*_structure_findings(path, refinement), *_return_findings(path, refinement, used),
            *_timeout_findings(path, refinement, used, vehicle, areas)]


def _structure_findings(path: str, refinement: Refinement) -> list[Finding]:
    """The refinement's own structure checked as orders, named inside `path` (a loop is
    allowed under a time-out)."""
    findings: list[Finding] = []
    sub = Orders.model_construct(
        id=path, start=refinement.start, goals=refinement.goals,
        terminals=[Terminal(id=t.id, kind=t.kind, title=t.title) for t in refinement.terminals])
    bounded = refinement.within is not None
    for finding in check_structure(sub):
        local = tuple(path + SEP + s if s != path else s for s in finding.subjects)
        if finding.code == "G7":
            if bounded:
                continue  # a loop with a time-out is what refinement allows
            findings.append(error(
                "REFINE", local, f"In the refinement of {path}: {finding.message} A loop "
                "inside a refinement needs a time-out: \"within\" {\"steps\": N} or "
                "{\"duration_s\": S} with \"on_timeout\" fail or violate."))
            continue
        findings.append(Finding(finding.code, finding.severity, local,
                                f"In the refinement of {path}: {finding.message}",
                                finding.details))
    return findings


def _return_findings(path: str, refinement: Refinement, used: set[str]) -> list[Finding]:
    """Each terminal returns an outcome the refined goal has a successor for; an outcome with
    a successor that nothing returns is worth a warning."""
    findings: list[Finding] = []
    for terminal in refinement.terminals:
        where = path + SEP + terminal.id
        if terminal.returns is None:
            findings.append(error("REFINE", [where], f"Terminal {where} returns no outcome: "
                                  "say which outcome of " + path + " it ends with (\"returns\": "
                                  "succeed, fail or violate)."))
        elif terminal.returns not in OUTCOMES:
            findings.append(error("REFINE", [where], f"Terminal {where} returns "
                                  f"{terminal.returns[:40]!r}, which is not an outcome "
                                  "(succeed, fail or violate)."))
        elif terminal.returns not in used:
            findings.append(error("REFINE", [where, path], f"Terminal {where} returns "
                                  f"{terminal.returns}, but {path} names no successor for "
                                  f"{terminal.returns}."))
    returned = {t.returns for t in refinement.terminals} | {refinement.on_timeout}
    for outcome in OUTCOMES:
        if outcome in used and outcome not in returned:
            # Not an error: a search may never fail. But the successor is then reached
            # from elsewhere or not at all, which the author should know.
            findings.append(warning("REFINE", [path], f"{path} names a successor for "
                                    f"{outcome}, but its refinement never returns {outcome}."))
    return findings


def _timeout_findings(path: str, refinement: Refinement, used: set[str],
                      vehicle: Vehicle | None, areas: dict[str, Area]) -> list[Finding]:
    """A time-out and its outcome come together, the outcome has a successor, and a time-out
    in seconds can bound every goal inside (each has a duration and none is refined)."""
    findings: list[Finding] = []
    bounded = refinement.within is not None
    if bounded and refinement.on_timeout is None:
        findings.append(error("REFINE", [path], f"The time-out of {path}'s refinement says "
                              "no outcome: add \"on_timeout\": fail or violate."))
    elif not bounded and refinement.on_timeout is not None:
        findings.append(error("REFINE", [path], f"{path}'s refinement gives on_timeout but no "
                              "time-out (\"within\")."))
    elif refinement.on_timeout is not None and refinement.on_timeout not in used:
        findings.append(error("REFINE", [path], f"The time-out of {path}'s refinement returns "
                              f"{refinement.on_timeout}, but {path} names no successor for it."))
    within = refinement.within
    if within is not None and within.duration_s is not None:
        for goal in refinement.goals:
            where = path + SEP + goal.id
            if goal.refines is not None:
                findings.append(error("REFINE", [where, path], f"{where} is refined, so its "
                                      f"duration depends on its path: bound {path}'s "
                                      "refinement by steps instead of duration_s."))
                continue
            seconds, _ = goal_cost(goal, "duration_s", vehicle, areas)
            if seconds is None or seconds <= 0:
                findings.append(error("REFINE", [where, path], f"{where} has no duration "
                                      "(give cost.duration_s, or an area and the vehicle's "
                                      f"speed), so the time-out of {path} cannot bound it."))
    return findings


def checked_form(orders: Orders) -> tuple[Orders, MissionGraph]:
    """What every path-reading check reads: the orders and their graph, or, for refined
    orders, the flat unrolled orders and their graph with the hierarchy (for traces)."""
    if not has_refinements(orders):
        return orders, build_graph(orders)
    flat = flatten(orders)
    return flat.orders, flat_graph(flat)


def flat_graph(flat: Flat) -> MissionGraph:
    return dataclasses.replace(build_graph(flat.orders), nesting=flat.nesting)
