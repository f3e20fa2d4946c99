"""Time and energy of an execution against the vehicle's budget.

Each budget quantity is measured from the best evidence the log holds, in this order:
1. readings named after the quantity (`energy_wh`, `duration_s`): the mission's cumulative use
   so far, as a vehicle's energy counter or mission clock reports it (the highest one counts);
2. for time only, the log's timestamps: from the first step's `start` (or, without one, its
   `time`, so the span is then a lower bound) to the last timestamp;
3. otherwise the cost model verify's BUDGET check uses (verify/budget.py): each goal's given or
   estimated cost plus the leg of each outcome edge taken, summed over the steps run.
A run whose use exceeds the budget is a BUDGET deviation at the step where it went over."""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from datetime import datetime
from typing import Any, Protocol

from ..orders.model import BUDGET_QUANTITIES, Orders
from ..verify.budget import UNITS
from ..verify.costs import mission_costs


class StepLike(Protocol):
    @property
    def goal(self) -> str: ...

    @property
    def outcome(self) -> str: ...

    @property
    def time(self) -> str | None: ...

    @property
    def start(self) -> str | None: ...

    @property
    def readings(self) -> dict[str, float | bool | str]: ...


@dataclass(frozen=True)
class Usage:
    quantity: str
    used: float
    budget: float | None
    source: str  # readings, timestamps or model
    over_at: int | None  # 1-based step where the use first exceeded the budget
    lower_bound: bool = False  # timestamps without the first goal's start

    @property
    def over(self) -> bool:
        return self.over_at is not None

    def to_json(self) -> dict[str, Any]:
        return {"quantity": self.quantity, "used": round(self.used, 3), "budget": self.budget,
                "source": self.source, "over": self.over, "lower_bound": self.lower_bound}

    def message(self) -> str:
        unit, noun = UNITS[self.quantity]
        lower = "at least " if self.lower_bound else ""
        return (f"the run used {lower}{self.used:,.1f} {unit} of {noun} (from its "
                f"{self.source}), more than the budget of {self.budget:,.1f} {unit}")


def parse_time(text: str | None) -> float | None:
    """Seconds of an ISO 8601 timestamp (a zone is required) or of a plain number of seconds;
    None for anything else (such times are kept as labels, not measured)."""
    if text is None:
        return None
    try:
        return float(text)
    except ValueError:
        pass
    try:
        moment = datetime.fromisoformat(text.replace("Z", "+00:00"))
    except ValueError:
        return None
    return moment.timestamp() if moment.tzinfo is not None else None


def _first_over(running: Sequence[float], budget: float | None) -> int | None:
    if budget is None:
        return None
    return next((i + 1 for i, used in enumerate(running) if used > budget), None)


def _from_readings(steps: Sequence[StepLike], quantity: str) -> list[float] | None:
    running: list[float] = []
    high: float | None = None
    for step in steps:
        value = step.readings.get(quantity)
        if isinstance(value, int | float) and not isinstance(value, bool):
            high = float(value) if high is None else max(high, float(value))
        running.append(high if high is not None else 0.0)
    return running if high is not None else None


def _from_timestamps(steps: Sequence[StepLike]) -> tuple[list[float], bool] | None:
    """Elapsed seconds after each step, and whether the span starts at a known start."""
    times = [parse_time(s.time) for s in steps]
    begin = parse_time(steps[0].start) if steps else None
    if not steps or any(t is None for t in times) or (begin is None and len(steps) < 2):
        return None
    origin = begin if begin is not None else times[0]
    assert origin is not None
    return [max(0.0, t - origin) for t in times if t is not None], begin is not None


def _from_model(orders: Orders, steps: Sequence[StepLike], quantity: str) -> list[float]:
    goals = orders.goal_index()
    costs = mission_costs(orders)
    total, running = 0.0, []
    for step in steps:
        goal = goals.get(step.goal)
        if goal is not None:
            total += costs.step(goal, step.outcome, quantity)
        running.append(total)
    return running


def budget_usage(orders: Orders, steps: Sequence[StepLike]) -> list[Usage]:
    """The run's use of each budget quantity, measured as the module says."""
    vehicle = orders.target_vehicle()
    usages: list[Usage] = []
    for quantity in BUDGET_QUANTITIES:
        budget = getattr(vehicle.budget, quantity, None) if vehicle and vehicle.budget else None
        running = _from_readings(steps, quantity)
        source, lower_bound = "readings", False
        if running is None and quantity == "duration_s":
            spans = _from_timestamps(steps)
            if spans is not None:
                (running, exact), source = spans, "timestamps"
                lower_bound = not exact
        if running is None:
            running, source = _from_model(orders, steps, quantity), "model"
        if not running:
            continue
        usages.append(Usage(quantity, max(running), budget, source,
                            _first_over(running, budget), lower_bound))
    return usages
