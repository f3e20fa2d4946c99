"""An edit revalidated from the state the last validation left (report parts, solver results,
goal items carried from the last logic model, canonical goals) gives the bytes a cold full
validation gives.

Random missions with constraints, norms and path properties (an energy bound among them: the
shortest costly path), each edited at random several times: a goal's envelope (a new quantity
too, which changes the quantity table every goal's items read), cost, title, area or
behaviour, a constraint, a norm, a quantity's declaration, the energy bound. After each edit
the report from the caches kept across the sequence and the report from fresh caches are
compared as canonical JSON (RFC 8785), byte for byte; so are the orders' canonical bytes
assembled from kept goals and the bytes of the whole written at once.
"""

from __future__ import annotations

import copy
import gc
import weakref
from typing import Any

import rfc8785
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from countersign.orders.canonical import canonical_bytes, orders_to_json
from countersign.orders.model import Orders
from countersign.verify.logic import LogicCache
from countersign.verify.parts import PartsCache
from countersign.verify.report import validate

from ..bench.bench_logic import logic_orders

EDITS = ("envelope", "new_quantity", "cost", "title", "area", "behavior", "constraint",
         "norm", "declaration", "bound")


def canonical_report(orders: Orders, logic: LogicCache, parts: PartsCache) -> bytes:
    return bytes(rfc8785.dumps(validate(orders, logic_cache=logic, parts=parts).to_json()))


def edit(draw: st.DrawFn, data: dict[str, Any]) -> None:
    goals = data["goals"]
    goal = goals[draw(st.integers(0, len(goals) - 1))]
    what = draw(st.sampled_from(EDITS))
    if what == "envelope":
        goal["envelope"]["depth_m"] = draw(st.sampled_from([[5, 15], [30, 90], [0, 400]]))
    elif what == "new_quantity":
        goal["envelope"][draw(st.sampled_from(["probe_m", "altitude_m"]))] = [1, 4]
    elif what == "cost":
        goal["cost"] = {"energy_wh": draw(st.integers(0, 500)), "duration_s": 60}
    elif what == "title":
        goal["title"] = draw(st.sampled_from(["Goal", "Survey the bay", ""]))
    elif what == "area":
        goal["area"] = f"A{draw(st.integers(0, 11))}"
    elif what == "behavior":
        goal["behavior"] = draw(st.sampled_from(["sample", "loiter", "transit"]))
    elif what == "constraint":
        data["constraints"][draw(st.integers(0, len(data["constraints"]) - 1))]["expr"] = draw(
            st.sampled_from(["depth_m >= 20", "depth_m <= 10", "speed_mps <= 2",
                             "probe_m <= 3"]))
    elif what == "norm":
        data["norms"][0] = {"id": "N0", "context": "shipping_lane",
                            "forbidden": draw(st.sampled_from(["depth_m < 20", "speed_mps > 1"]))}
    elif what == "declaration":
        data.setdefault("quantities", {})["depth_m"] = {
            "unit": "m", "min": 0, "max": draw(st.sampled_from([50, 500]))}
    else:
        data["properties"][2]["max"] = {"energy_wh": draw(st.sampled_from([100, 400, 5000]))}


@st.composite
def edit_sequences(draw: st.DrawFn) -> list[Orders]:
    goals = draw(st.integers(4, 24))
    data = logic_orders(goals, draw(st.integers(2, 8)), draw(st.integers(1, 4)),
                        seed=draw(st.integers(0, 50))).model_dump(mode="json",
                                                                  exclude_unset=True)
    versions = [Orders.model_validate(data)]
    for _ in range(draw(st.integers(1, 5))):
        data = copy.deepcopy(data)
        edit(draw, data)
        versions.append(Orders.model_validate(data))
    return versions


@settings(max_examples=25, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(edit_sequences())
def test_an_edit_revalidated_from_kept_state_is_byte_for_byte_a_cold_validation(
        versions: list[Orders]) -> None:
    parts, logic = PartsCache(), LogicCache()
    for orders in versions:
        kept = canonical_report(orders, logic, parts)
        assert kept == canonical_report(orders, LogicCache(), PartsCache())
        assert canonical_bytes(orders) == bytes(rfc8785.dumps(orders_to_json(orders)))


def test_a_quantity_one_goal_adds_reaches_the_other_goals_checks() -> None:
    """An envelope that names a quantity nobody declared adds it to the quantity table: a
    constraint that read it unknown now holds in every goal's scope, so no goal's items may
    be carried from before (every goal but the edited one is unchanged)."""
    data = logic_orders(6, 2, 1, seed=4).model_dump(mode="json", exclude_unset=True)
    data["constraints"][0].update({"applies_to": "mission",
                                   "expr": "probe_m <= 3 and depth_m <= 10"})
    parts, logic = PartsCache(), LogicCache()
    canonical_report(Orders.model_validate(data), logic, parts)
    data["goals"][0]["envelope"]["probe_m"] = [5, 9]
    orders = Orders.model_validate(data)
    kept = canonical_report(orders, logic, parts)
    assert kept == canonical_report(orders, LogicCache(), PartsCache())
    assert kept.count(b"CONTRADICTION") > 2


def test_a_model_does_not_keep_the_model_before_it_alive() -> None:
    """Carried goal items must not hold the model that built them (their phrases' closures
    did): a long editing session would otherwise keep every version's model, z3 session
    and orders."""
    data = logic_orders(8, 3, 2, seed=2).model_dump(mode="json", exclude_unset=True)
    logic = LogicCache()
    first = Orders.model_validate(data)
    validate(first, logic_cache=logic, parts=PartsCache())
    before = weakref.ref(logic.model(first))  # the model validate made for these orders
    data["goals"][0]["title"] = "Edited"
    second = Orders.model_validate(data)
    validate(second, logic_cache=logic, parts=PartsCache())
    after = logic.model(second)
    assert len(after.goal_items_memo) > 1  # the other goals' items were carried
    gc.collect()
    assert before() is None
