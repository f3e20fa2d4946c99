"""Execution logs checked against the orders: which path the vehicle followed (numbered as
`countersign paths` numbers them) and every deviation, named.

A log is NDJSON, one line per goal run: {"goal", "outcome", "time"?, "start"?, "readings"?,
"samples"?},
outcome succeed, fail or violate, time when the outcome came (start when the goal began),
readings the measured values of constrained quantities (readings named energy_wh or
duration_s are the mission's cumulative use). Time and energy are checked against the
vehicle's budget (execution_budget.py). A rehearsal's record is an execution in simulation and
goes through the same check.

"No deviation" is only said of a run that evidences it (execution_evidence.py): every goal run
with start and end times, and readings for every constraint in scope of it; a run that follows
the orders without them is "unverified", naming what is missing. Times that cannot be real
(unparseable, running backwards, after the present, before the approval) make the log
unreadable rather than a run."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

from .. import strict_json
from ..orders.model import OUTCOMES, Orders
from ..verify.graph import MissionGraph
from ..verify.paths import paths_of
from ..verify.refine import checked_form
from .execution_budget import Usage, budget_usage
from .execution_evidence import Evidence, TimeWindow, check_times
from .execution_evidence import ExecutionLogError as ExecutionLogError
from .monitor import GoalFacts, Monitor, facts_of, monitors_of

MAX_STEPS = 100_000
MAX_LINE = 64 * 1024
MAX_SAMPLES = 256


@dataclass(frozen=True)
class Step:
    goal: str
    outcome: str
    time: str | None = None
    readings: dict[str, float | bool | str] = field(default_factory=dict)
    start: str | None = None
    # Further readings taken during the goal (a converted vehicle log keeps each quantity's
    # extremes): each is checked like `readings`.
    samples: tuple[dict[str, float | bool | str], ...] = ()


@dataclass(frozen=True)
class Deviation:
    code: str  # SKIPPED-GOAL, WRONG-TRANSITION, UNKNOWN-GOAL, CONSTRAINT, BUDGET, INCOMPLETE,
    # AFTER-END
    step: int  # 1-based line of the log
    message: str

    def to_json(self) -> dict[str, Any]:
        return {"code": self.code, "step": self.step, "message": self.message}


@dataclass(frozen=True)
class ExecutionVerdict:
    path: int | None  # the path number when the run followed the orders
    terminal: str | None
    deviations: tuple[Deviation, ...]
    usage: tuple[Usage, ...] = ()
    evidence: Evidence = field(default_factory=Evidence)

    @property
    def ok(self) -> bool:
        """No deviation, and the evidence to say so."""
        return not self.deviations and self.evidence.complete

    @property
    def status(self) -> str:
        if self.deviations:
            return "deviation"
        return "no-deviation" if self.evidence.complete else "unverified"

    def summary(self) -> str:
        if self.ok:
            return f"executed as path {self.path} to {self.terminal}, no deviation"
        if not self.deviations:
            followed = (f"executed as path {self.path} to {self.terminal}"
                        if self.path is not None else "executed")
            return f"{followed}, unverified: {'; '.join(self.evidence.gaps())}"
        first = self.deviations[0]
        more = f" (and {len(self.deviations) - 1} more)" if len(self.deviations) > 1 else ""
        return f"deviation at step {first.step}: {first.message}{more}"

    def to_json(self) -> dict[str, Any]:
        return {"ok": self.ok, "status": self.status, "path": self.path,
                "terminal": self.terminal, "summary": self.summary(),
                "deviations": [d.to_json() for d in self.deviations],
                "usage": [u.to_json() for u in self.usage], "evidence": self.evidence.to_json()}


def _values(data: Any, what: str) -> dict[str, float | bool | str]:
    if not isinstance(data, dict) or not all(
            isinstance(v, int | float | bool | str) for v in data.values()):
        raise TypeError(f"{what} must map quantities to values")
    return data


def read_log(text: str) -> list[Step]:
    steps: list[Step] = []
    for number, line in enumerate(text.splitlines(), 1):
        if not line.strip():
            continue
        if len(line) > MAX_LINE or len(steps) >= MAX_STEPS:
            raise ExecutionLogError(f"line {number}: the log is too large")
        try:
            # The one JSON policy (depth bound, no duplicate keys or NaN) names the path.
            data = strict_json.loads(line)
            goal, outcome = str(data["goal"]), str(data["outcome"])
            readings = _values(data.get("readings") or {}, "readings")
            samples = data.get("samples") or []
            if not isinstance(samples, list) or len(samples) > MAX_SAMPLES:
                raise TypeError(f"samples must be a list of at most {MAX_SAMPLES} readings")
            sampled = tuple(_values(sample, "each sample") for sample in samples)
        except (ValueError, KeyError, TypeError, AttributeError) as exc:
            raise ExecutionLogError(f"line {number}: not a step {{goal, outcome, time?, "
                                    f"readings?}} ({exc})") from None
        if outcome == "constraint":
            outcome = "violate"
        if outcome not in OUTCOMES:
            raise ExecutionLogError(f"line {number}: outcome {outcome[:40]!r} is not succeed, "
                                    "fail or violate")
        time, start = data.get("time"), data.get("start")
        for name, value in (("time", time), ("start", start)):
            if value is not None and (isinstance(value, bool)
                                      or not isinstance(value, str | int | float)):
                raise ExecutionLogError(f"line {number}: {name} must be an ISO 8601 time or "
                                        "a number of seconds")
        steps.append(Step(goal, outcome, None if time is None else str(time), readings,
                          None if start is None else str(start), sampled))
    return steps


def check_execution(orders: Orders, steps: list[Step],
                    window: TimeWindow | None = None) -> ExecutionVerdict:
    """The run's path, deviations and evidence. `window` bounds its absolute times (without
    one, as for a rehearsal's simulated seconds, times are only checked to run forwards)."""
    untimed = check_times(steps, window)
    # A refined mission runs as its flat automaton: logs name its goals (G1/G1.1#1).
    orders = checked_form(orders)[0]
    graph, counts = paths_of(orders)
    if counts is None or graph.start is None:
        raise ExecutionLogError("the orders have no countable paths (fix their structure)")
    index = {goal_id: i for i, goal_id in enumerate(graph.goal_ids)}
    goals = orders.goal_index()
    monitors, _ = monitors_of(orders)
    deviations: list[Deviation] = []
    unread: list[tuple[str, int]] = []
    in_scope: set[str] = set()
    node: int | None = graph.start
    rank = 0
    for number, step in enumerate(steps, 1):
        if node is None or graph.is_terminal(node):
            deviations.append(Deviation("AFTER-END", number, f"{step.goal} ran after the "
                                        "mission ended"))
            break
        if step.goal != graph.goal_ids[node]:
            deviations.append(_transition_deviation(graph, index, node, step, number))
            if step.goal not in index:
                break
            node = index[step.goal]  # follow what the vehicle did, to name later deviations
            rank = -1
        facts = facts_of(goals[step.goal], orders)
        for monitor in monitors:
            if not monitor.applies(step.goal):
                continue
            in_scope.add(monitor.constraint_id)
            if all(monitor.holds(r, facts) is None for r in (step.readings, *step.samples)):
                unread.append((monitor.constraint_id, number))
            broken = _broken_constraint(monitor, step, number, facts)
            if broken is not None:
                deviations.append(broken)
        k = OUTCOMES.index(step.outcome)
        if rank >= 0:
            rank += sum(counts.per_node[graph.succ[node][j]] for j in range(k))
        node = graph.succ[node][k]
    if node is not None and not graph.is_terminal(node):
        deviations.append(Deviation("INCOMPLETE", len(steps), f"the log ends before "
                                    f"{graph.goal_ids[node]} ran"))
    usage = tuple(budget_usage(orders, steps))
    for used in usage:
        if used.over_at is not None:
            deviations.append(Deviation("BUDGET", used.over_at, used.message()))
    deviations.sort(key=lambda d: d.step)
    terminal = graph.node_id(node) if node is not None and graph.is_terminal(node) else None
    ok = not deviations and rank >= 0
    read = sorted(in_scope - {constraint for constraint, _ in unread})
    evidence = Evidence(untimed, tuple(unread), tuple(read))
    return ExecutionVerdict(rank + 1 if ok else None, terminal, tuple(deviations), usage,
                            evidence)


def _transition_deviation(graph: MissionGraph, index: dict[str, int], node: int, step: Step,
                          number: int) -> Deviation:
    """How a step that is not the goal the orders name next deviates from them."""
    expected = graph.goal_ids[node]
    if step.goal not in index:
        code, text = "UNKNOWN-GOAL", f"{step.goal} is not a goal of the orders"
    elif index[step.goal] in graph.succ[node]:
        code, text = "SKIPPED-GOAL", f"{expected} was skipped: {step.goal} ran instead"
    else:
        code, text = "WRONG-TRANSITION", (
            f"the orders name {expected} next, but {step.goal} ran")
    return Deviation(code, number, text)


def _broken_constraint(monitor: Monitor, step: Step, number: int,
                       facts: GoalFacts) -> Deviation | None:
    """The CONSTRAINT deviation of the step's first readings that break the monitor's
    constraint (None when none does)."""
    broken = next((r for r in (step.readings, *step.samples)
                   if r and monitor.holds(r, facts) is False), None)
    if broken is None:
        return None
    shown = ", ".join(f"{k}={v}" for k, v in sorted(broken.items()))
    return Deviation(
        "CONSTRAINT", number, f"readings {shown} break {monitor.constraint_id} "
        f"({monitor.expr}) during {step.goal}"
        + (f" at {step.time}" if step.time else ""))
