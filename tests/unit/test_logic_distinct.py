"""Status checks assume one indicator per distinct formula (issue 22): a mission-wide constraint
repeated in every goal's scope costs one assumption, and the findings are those of assuming
every item.

Which of several constraints with the same formula a core names is z3's choice, and it changes
with the checks asked before (so does a witness); the comparison therefore names a constraint
by the first constraint with its formula and leaves witness values out. Everything else (codes,
goals, norms, the formulas in each core, minimality) must be equal."""

from __future__ import annotations

import json
import re
from collections.abc import Sequence
from typing import Any, ClassVar

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from countersign.orders.model import Orders
from countersign.verify.graph import build_graph
from countersign.verify.logic import CheckResult, Item, LogicCache, Session, check_logic
from countersign.verify.logic import run as logic_run
from countersign.verify.logic import session as logic_session
from countersign.verify.properties import check_properties
from tests.bench.bench_logic import logic_orders

CONSTRAINT_ID = re.compile(r"\bC\d+\b")


def findings(orders: Orders, distinct: bool) -> list[dict[str, Any]]:
    with pytest.MonkeyPatch.context() as patch:
        patch.setattr(logic_session, "DISTINCT_FORMULAS", distinct)
        cache = LogicCache()
        # A generous budget: a run cut short by it reports different undecided warnings.
        found = check_logic(orders, cache, total_timeout_s=600)
        found += check_properties(orders, build_graph(orders), cache, total_timeout_s=600)
    return [f.to_json() for f in found]


def comparable(orders: Orders, found: list[dict[str, Any]]) -> list[str]:
    """The findings as sorted text, each constraint named by the first with its formula."""
    first: dict[str, str] = {}
    named = {c.id: first.setdefault(c.expr or "", c.id) for c in orders.constraints}
    out = []
    for finding in found:
        finding = json.loads(json.dumps(finding))
        if "witness" in finding["details"]:
            finding["details"].pop("witness")
            finding.pop("message")  # it states the witness
        text = json.dumps(finding, sort_keys=True)
        out.append(CONSTRAINT_ID.sub(lambda m: named.get(m.group(0), m.group(0)), text))
    return sorted(out)


def assert_same(orders: Orders) -> list[dict[str, Any]]:
    fast = findings(orders, distinct=True)
    reference = findings(orders, distinct=False)
    assert comparable(orders, fast) == comparable(orders, reference)
    return fast


@pytest.mark.parametrize("seed", [1, 2, 3])
def test_distinct_formulas_give_the_findings_of_every_item(seed: int) -> None:
    orders = logic_orders(goals=80, constraints=60, norms=8, seed=seed)
    codes = {f["code"] for f in assert_same(orders)}
    assert {"NORM", "PROPERTY", "VACUOUS"} <= codes or seed != 1


@settings(max_examples=8, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(seed=st.integers(0, 10**6), goals=st.integers(3, 60), constraints=st.integers(2, 60),
       norms=st.integers(0, 8))
def test_distinct_formulas_give_the_findings_of_every_item_on_random_orders(
    seed: int, goals: int, constraints: int, norms: int
) -> None:
    assert_same(logic_orders(goals=goals, constraints=constraints, norms=norms, seed=seed))


class AssumptionCounter(Session):
    """The session as it is, recording how many assumptions each check makes."""

    sizes: ClassVar[list[int]] = []

    def check(self, items: Sequence[Item]) -> CheckResult:
        type(self).sizes.append(len(items))
        return super().check(items)


def test_a_repeated_mission_constraint_costs_one_assumption() -> None:
    orders = logic_orders(goals=4, constraints=0, norms=0, seed=5).model_copy(deep=True)
    data = orders.model_dump(mode="json", exclude_none=True)
    data["constraints"] = [
        {"id": f"C{i}", "text": "Stay deep", "applies_to": "mission", "expr": "depth_m >= 2"}
        for i in range(40)
    ]
    repeated = Orders.model_validate(data)
    with pytest.MonkeyPatch.context() as patch:
        patch.setattr(logic_run, "Session", AssumptionCounter)
        patch.setattr(AssumptionCounter, "sizes", [])
        assert [f for f in check_logic(repeated, LogicCache()) if f.severity == "error"] == []
        sizes = AssumptionCounter.sizes
    # Every goal's checks see the 40 copies once: no check assumes more than a handful.
    assert sizes and max(sizes) < 40, sizes
    assert_same(repeated)


def test_only_mission_wide_constraints_stay_asserted_between_goals() -> None:
    orders = logic_orders(goals=60, constraints=40, norms=6, seed=2)
    cache = LogicCache()
    check_logic(orders, cache)
    check_properties(orders, build_graph(orders), cache)
    session = cache.model(orders).session
    assert session is not None
    kept = {key for key in session._based if key.startswith(("con:", "neg:"))}
    mission = {f"con:{c.id}" for c in orders.constraints if c.applies_to == "mission"}
    assert kept and kept <= mission, sorted(kept - mission)
