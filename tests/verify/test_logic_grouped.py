"""Goals screened and grouped give exactly the findings of one session check at a time per
goal: codes, wording, cores, witnesses and order."""

from __future__ import annotations

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from countersign.orders.examples import example_names, load_example
from countersign.orders.model import Orders
from countersign.verify.graph import build_graph
from countersign.verify.logic import LogicCache, check_logic
from countersign.verify.logic import run as logic_run
from countersign.verify.properties import check_properties
from tests.bench.bench_logic import logic_orders


def findings(orders: Orders, grouped: bool, patch: pytest.MonkeyPatch) -> tuple[
    list[dict[str, object]], int
]:
    """Every logic and property finding, and how many checks the screen spared (answers
    shared between goals or proven by bounds propagation)."""
    patch.setattr(logic_run, "GROUP_CHECKS", grouped)
    cache = LogicCache()
    found = check_logic(orders, cache) + check_properties(orders, build_graph(orders), cache)
    screen = cache.model(orders).screen
    spared = screen.shared + screen.decider.decided if screen is not None else 0
    return [f.to_json() for f in found], spared


@pytest.mark.parametrize("name", example_names())
def test_grouped_equals_one_check_per_goal_on_the_examples(
    name: str, monkeypatch: pytest.MonkeyPatch
) -> None:
    orders = load_example(name)
    assert findings(orders, True, monkeypatch)[0] == findings(orders, False, monkeypatch)[0]


def test_goals_spare_checks(monkeypatch: pytest.MonkeyPatch) -> None:
    orders = logic_orders(goals=120, constraints=30, norms=6, seed=3)
    grouped, shared = findings(orders, True, monkeypatch)
    assert grouped == findings(orders, False, monkeypatch)[0]
    assert shared > 0


@settings(max_examples=15, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(seed=st.integers(0, 10**6), goals=st.integers(3, 60), constraints=st.integers(2, 80),
       norms=st.integers(0, 8))
def test_grouped_equals_one_check_per_goal_on_random_orders(
    seed: int, goals: int, constraints: int, norms: int
) -> None:
    orders = logic_orders(goals=goals, constraints=constraints, norms=norms, seed=seed)
    with pytest.MonkeyPatch.context() as patch:
        grouped, _ = findings(orders, True, patch)
        single, _ = findings(orders, False, patch)
    assert grouped == single
