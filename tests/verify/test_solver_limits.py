"""The solver's limits: a budget of the work's CPU time, so a loaded machine decides what a
quiet one does, under a wall-clock cap that still ends the work and says so.

Load is played with clocks passed to `validate`, never by sleeping: a loaded machine is one
where wall time passes faster than the validating thread's CPU time."""

from __future__ import annotations

import itertools
import re
import time
from collections.abc import Callable
from typing import Any

from countersign.orders.findings import Finding
from countersign.orders.model import Orders
from countersign.verify.logic import (
    BUDGET_SPENT,
    WALL_CAP_FACTOR,
    WALL_CAP_REACHED,
    Clocks,
    Limits,
    LogicCache,
)
from countersign.verify.parts import PartsCache
from countersign.verify.report import Report, validate
from tests.bench.bench_logic import logic_orders


class Dial:
    """A clock that reads what the test sets."""

    def __init__(self) -> None:
        self.now = 0.0

    def __call__(self) -> float:
        return self.now


def test_the_budget_counts_cpu_time_and_the_cap_wall_time() -> None:
    cpu, wall = Dial(), Dial()
    limits = Limits.start(1_000, 8.0, clocks=Clocks(cpu=cpu, wall=wall))
    assert limits.wall_cap_s == WALL_CAP_FACTOR * 8.0
    wall.now, cpu.now = 20.0, 2.0  # a busy machine: 20 s have passed, 2 s of them ours
    assert limits.spent() is None
    assert limits.call_timeout_ms() == 1_000
    cpu.now = 7.75  # a call may not run past the budget
    assert limits.call_timeout_ms() == 250
    assert limits.timed_out() == BUDGET_SPENT
    cpu.now = 8.0
    assert (limits.spent(), limits.call_timeout_ms()) == (BUDGET_SPENT, 0)
    cpu.now, wall.now = 5.0, 31.5  # nor past the wall cap
    assert limits.call_timeout_ms() == 500
    assert limits.timed_out() == WALL_CAP_REACHED
    wall.now = 32.0
    assert (limits.spent(), limits.call_timeout_ms()) == (WALL_CAP_REACHED, 0)


def test_a_call_that_times_out_on_its_own_says_so() -> None:
    limits = Limits.start(200, 60.0, clocks=Clocks(cpu=Dial(), wall=Dial()))
    assert limits.call_timeout_ms() == 200
    assert limits.timed_out() == "timeout after 200 ms"


def _mission() -> Orders:
    """200 goals with contradictions, refusals, vacuous constraints and path properties, and
    a nonlinear constraint on every other goal: bounds propagation decides the rest without
    z3, these only z3 decides (each quickly), so the goals need solver time."""
    data = logic_orders(goals=200, constraints=40, norms=8, seed=3).model_dump(
        mode="json", by_alias=True, exclude_none=True)
    data["constraints"] += [
        {"id": f"NL{i}", "applies_to": [f"G{i}"],
         "expr": f"depth_m * speed_mps >= {(i * 7) % 120 + 1}"}
        for i in range(0, 200, 2)]
    return Orders.model_validate(data)


def _validate(orders: Orders, **limits: Any) -> Report:
    return validate(orders, logic_cache=LogicCache(), parts=PartsCache(), **limits)


def _json(findings: list[Finding]) -> list[dict[str, Any]]:
    return [f.to_json() for f in findings]


def test_a_loaded_machine_decides_every_goal_within_the_cpu_budget() -> None:
    orders = _mission()
    quiet = _validate(orders)
    assert not [f for f in quiet.findings if "undecided" in f.details]
    # This thread gets a twentieth of a core: wall time passes 20 times as fast as its CPU
    # time. The solver part needs a fraction of a second of CPU (about 0.3 s), a budget of
    # 2 s of wall time would end it after 0.1 s of CPU; 2 s of CPU decide it all.
    share = 20.0
    started = time.thread_time()
    loaded = _validate(orders, solver_budget_s=2.0, solver_wall_cap_s=60.0,
                       solver_clocks=Clocks(wall=lambda: share * time.thread_time()))
    assert time.thread_time() - started < 2.0 + 1.0  # the budget, and the checks around it
    assert _json(loaded.findings) == _json(quiet.findings)


class CountingWall:
    """Wall time that passes one second at every reading: the same run reads it the same
    number of times whatever the machine's speed, so where the cap falls is fixed."""

    def __init__(self) -> None:
        self.readings = itertools.count()

    def __call__(self) -> float:
        return float(next(self.readings))


def _goals_of(finding: dict[str, Any]) -> set[str]:
    details = finding["details"]
    return {details["goal"]} if "goal" in details else set(details.get("goals", ()))


def _by_goal(findings: list[dict[str, Any]], goal: str) -> list[dict[str, Any]]:
    return [f for f in findings if goal in _goals_of(f)]


def _logic(findings: list[dict[str, Any]]) -> list[dict[str, Any]]:
    return [f for f in findings if f["code"] in {"CONTRADICTION", "NORM"}]


def _readings(action: Callable[[Clocks], object]) -> int:
    wall = CountingWall()
    action(Clocks(wall=wall))
    return next(wall.readings)


def test_the_wall_cap_ends_the_work_with_an_honest_undecided_count() -> None:
    orders = _mission()
    full = _json(_validate(orders).findings)
    # A validation that reads the wall clock R times, capped at a quarter of them.
    readings = _readings(lambda clocks: _validate(orders, solver_wall_cap_s=1e9,
                                                  solver_clocks=clocks))
    cap = float(readings // 4)
    parts = PartsCache()
    capped = _json(validate(orders, logic_cache=LogicCache(), parts=parts,
                            solver_wall_cap_s=cap,
                            solver_clocks=Clocks(wall=CountingWall())).findings)
    out_of_time = [f for f in capped if f["details"].get("undecided") == WALL_CAP_REACHED
                   and f["code"] == "CONTRADICTION"]
    assert len(out_of_time) == 1, capped
    left = out_of_time[0]
    counted = re.search(r"before deciding (\d+) goal\(s\)", left["message"])
    assert counted is not None and f"wall-clock cap of {cap:g} s" in left["message"]
    assert int(counted.group(1)) == len(left["subjects"]) == len(set(left["subjects"]))
    undecided = set(left["subjects"])
    goals = {g.id for g in orders.goals}
    assert 0 < len(undecided) < len(goals) and undecided <= goals
    # A goal not counted undecided was decided as the full run decides it: nothing is
    # dropped silently.
    for goal in sorted(goals - undecided):
        assert _by_goal(_logic(capped), goal) == _by_goal(_logic(full), goal), goal
    # A property's counterexample is one the full run finds too (it may name another goal
    # when a nearer one was left undecided).
    failing = {f["details"]["property"]: set(f["details"]["failing_goals"]) for f in full
               if f["code"] == "PROPERTY" and "failing_goals" in f["details"]}
    for f in capped:
        if f["code"] == "PROPERTY" and "failing_goals" in f["details"]:
            found = failing[f["details"]["property"]]
            assert f["details"]["goal"] in found and set(f["details"]["failing_goals"]) <= found
    # The vacuity checks and properties the cap cut short are said, with why.
    cut = [f for f in capped if f["severity"] == "warning" and f["code"] in {"PROPERTY", "VACUOUS"}
           and "could not" in f["message"]]
    assert {f["code"] for f in cut} == {"PROPERTY", "VACUOUS"}
    assert all(f"wall-clock cap of {cap:g} s" in f["message"] for f in cut), cut
    # What the cap left undecided is not kept: validating again decides it.
    again = validate(orders, logic_cache=LogicCache(), parts=parts)
    assert _json(again.findings) == full
