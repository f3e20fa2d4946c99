"""Vacuity settled in batches gives exactly the findings of one check per constraint."""

from __future__ import annotations

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from countersign.verify.logic import LogicCache, check_logic
from countersign.verify.logic import findings as logic
from tests.bench.bench_logic import logic_orders


def findings(orders: object, batched: bool, monkeypatch: pytest.MonkeyPatch) -> tuple[
    list[dict[str, object]], int
]:
    monkeypatch.setattr(logic, "BATCH_VACUITY", batched)
    cache = LogicCache()
    result = check_logic(orders, cache)  # type: ignore[arg-type]
    model = cache.model(orders)  # type: ignore[arg-type]
    assert model.session is not None
    return [f.to_json() for f in result], model.session.calls


@pytest.mark.parametrize("seed", [1, 2, 3, 4, 5, 6])
def test_batched_vacuity_equals_one_check_per_constraint(
    seed: int, monkeypatch: pytest.MonkeyPatch
) -> None:
    orders = logic_orders(goals=30, constraints=25, norms=5, seed=seed)
    batched, batched_calls = findings(orders, True, monkeypatch)
    single, single_calls = findings(orders, False, monkeypatch)
    assert batched == single
    assert any(f["code"] == "VACUOUS" for f in single) or seed != 1
    assert batched_calls < single_calls


def test_many_constraints_take_few_vacuity_checks(monkeypatch: pytest.MonkeyPatch) -> None:
    orders = logic_orders(goals=20, constraints=200, norms=0, seed=9)
    _, batched_calls = findings(orders, True, monkeypatch)
    _, single_calls = findings(orders, False, monkeypatch)
    # One check per non-vacuous constraint in the reference; a handful of models in a batch.
    assert single_calls - batched_calls > 100


@settings(max_examples=12, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(seed=st.integers(0, 10**6), goals=st.integers(3, 40), constraints=st.integers(2, 60),
       norms=st.integers(0, 8))
def test_batched_vacuity_equals_one_check_per_constraint_on_random_orders(
    seed: int, goals: int, constraints: int, norms: int
) -> None:
    orders = logic_orders(goals=goals, constraints=constraints, norms=norms, seed=seed)
    with pytest.MonkeyPatch.context() as patch:
        batched, _ = findings(orders, True, patch)
        single, _ = findings(orders, False, patch)
    assert batched == single
