"""Answers shared between goals, and what makes a large check cheap, stay proofs.

Goals that state the same things (the same envelope, facts and constraints, whatever their
ids) take one bounds.py decision between them; goals whose statements differ, if only in one
bound, each take their own. A goal unit's cache key stands for the mission-wide constraints by
one digest of theirs, and stays one of the item set. The cyclic garbage collector pauses for a
logic check and comes back after it, also when checks overlap in threads.
"""

from __future__ import annotations

import gc
import threading
from collections.abc import Sequence
from typing import Any

import pytest

from countersign.orders.model import Orders
from countersign.verify.logic import (
    LogicCache,
    LogicModel,
    LogicRun,
    check_logic,
    collector,
    unit_key,
)
from countersign.verify.logic.bounds import Decider
from countersign.verify.logic.cache import unit_key_apart
from countersign.verify.logic.limits import Limits
from tests.verify.test_logic_bounds import z3_status

NEXT = {"succeed": "COMPLETE", "fail": "ABORT", "violate": "ABORT"}


def _orders(bounds: dict[str, int], mission: Sequence[str] = ()) -> Orders:
    """One goal per entry (id -> the depth its own constraint asks for), all with the same
    envelope, behaviour and area."""
    return Orders.model_validate({
        "id": "s", "start": "G0",
        "goals": [{"id": gid, "behavior": "a", "area": "A0", "envelope": {"x": [0, 20]},
                   "next": NEXT} for gid in bounds],
        "constraints": [
            *({"id": f"C{gid}", "applies_to": [gid], "expr": f"x >= {low}"}
              for gid, low in bounds.items()),
            *({"id": f"M{j}", "applies_to": "mission", "expr": e}
              for j, e in enumerate(mission)),
        ],
        "areas": [{"id": "A0", "contexts": ["t1"]}],
        "quantities": {"x": {"min": -50, "max": 50}},
    })


def _asked(orders: Orders) -> tuple[LogicModel, LogicRun, frozenset[Any],
                                    dict[str, list[Any]]]:
    model = LogicModel(orders)
    run = LogicRun(model, None, Limits.start(2000, 60))
    base = run.block(frozenset())
    items = {gid: run.goal_items(goal, frozenset())[0] for gid, goal in model.goals.items()}
    return model, run, base, items


def test_goals_that_state_the_same_take_one_decision() -> None:
    model, _, base, items = _asked(_orders({"G0": 10, "G1": 10}, ["x <= 30"]))
    decider = Decider(model.quantities)
    for gid in ("G0", "G1"):
        assert decider.status([i for i in items[gid] if i not in base], base) == "sat"
    # Two goals and two constraints, but one question (the ids are not part of it).
    assert decider.decided == 2 and len(decider._verdicts) == 1


def test_goals_whose_constraints_differ_in_a_bound_are_decided_apart() -> None:
    """G1's own constraint asks for more depth than its envelope allows, G0's does not: a
    decision shared between them (keyed by less than what they state) is wrong for one."""
    model, _, base, items = _asked(_orders({"G0": 10, "G1": 30}, ["x <= 30"]))
    decider = Decider(model.quantities)
    answers = {gid: decider.status([i for i in items[gid] if i not in base], base)
               for gid in ("G0", "G1")}
    assert answers == {"G0": "sat", "G1": "unsat"}
    assert answers == {gid: z3_status(model, items[gid]) for gid in items}
    # The findings say so too: G1 only.
    found = check_logic(_orders({"G0": 10, "G1": 30}, ["x <= 30"]))
    assert [f.subjects for f in found if f.code == "CONTRADICTION"] == [("G1", "CG1")]


def test_a_goal_key_stands_for_its_base_and_stays_one_of_its_items() -> None:
    orders = _orders({"G0": 10, "G1": 10}, ["x <= 30", "x >= -5"])
    _, _, base, items = _asked(orders)
    own = items["G0"]
    assert base and base <= set(own)
    with_base = unit_key("goal", own, base)
    # A caller that holds the items but the base apart gets the same key.
    assert unit_key_apart("goal", [i for i in own if i not in base], base) == with_base
    # Another model of the same orders (a new set of item objects, as after an edit): the
    # same key, with or without its own base.
    _, _, other_base, other = _asked(orders)
    assert unit_key("goal", other["G0"], other_base) == with_base
    assert unit_key("goal", other["G0"], base) == with_base
    # A unit that lacks one of the base's items is another set: another key, the one made
    # without a base.
    dropped = [i for i in own if i is not next(iter(base))]
    assert unit_key("goal", dropped, base) == unit_key("goal", dropped)
    assert unit_key("goal", dropped, base) != with_base
    # A base whose constraint reads another bound: another key.
    _, _, moved_base, moved = _asked(_orders({"G0": 10, "G1": 10}, ["x <= 31", "x >= -5"]))
    assert unit_key("goal", moved["G0"], moved_base) != with_base
    # Goals of other ids with the same statements still have keys of their own (their items'
    # sources name them): the cache keeps per-goal results apart.
    assert unit_key("goal", items["G1"], base) != with_base


def test_a_one_goal_edit_reuses_the_other_goals_results() -> None:
    cache = LogicCache()
    check_logic(_orders({"G0": 10, "G1": 30}, ["x <= 30"]), cache)
    solved = cache.misses
    check_logic(_orders({"G0": 10, "G1": 25}, ["x <= 30"]), cache)
    # G1's unit, and its constraint's vacuity (which bounds settle in the batch, so it is not
    # asked alone): G0's unit, the mission and the other constraints come from the cache.
    assert cache.misses == solved + 2


def test_the_collector_pauses_for_a_check_and_comes_back(collector_enabled: None) -> None:
    seen: list[bool] = []
    original = collector.gc.isenabled

    class Spy(Decider):
        def status(self, rest: Any, base: frozenset[Any]) -> str | None:
            seen.append(original())
            return super().status(rest, base)

    with pytest.MonkeyPatch.context() as patch:
        patch.setattr("countersign.verify.logic.screen.Decider", Spy)
        check_logic(_orders({"G0": 10, "G1": 30}, ["x <= 30"]))
    assert seen and not any(seen)
    assert gc.isenabled()


def test_overlapping_checks_enable_the_collector_when_the_last_ends(
        collector_enabled: None) -> None:
    first, second = collector.collector_paused(), collector.collector_paused()
    first.__enter__()
    second.__enter__()
    first.__exit__(None, None, None)
    assert not gc.isenabled()  # the second check still runs
    second.__exit__(None, None, None)
    assert gc.isenabled()
    # Off before: off after.
    gc.disable()
    with collector.collector_paused():
        pass
    assert not gc.isenabled()


def test_threads_checking_at_once_leave_the_collector_as_it_was(
        collector_enabled: None) -> None:
    orders = [_orders({"G0": 10, "G1": low}, ["x <= 30"]) for low in (30, 25, 12)]
    results: list[int] = []

    def check(o: Orders) -> None:
        results.append(len(check_logic(o)))

    threads = [threading.Thread(target=check, args=(o,)) for o in orders]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert sorted(results) == [0, 1, 1] and gc.isenabled()
