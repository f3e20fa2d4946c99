"""One reader core (orders/reader.py) for every JSON input read into a model: the orders and the
planning problem refuse the same bytes with the same problems (size, emptiness, the strict JSON
policy, files that cannot be read), validation problems are deduplicated and capped the same way,
and each reader only rewords its own errors."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from countersign.orders import reader as orders_reader
from countersign.orders.examples import example_bytes
from countersign.orders.reader import MAX_INPUT_BYTES, MAX_PROBLEMS_SHOWN, OrdersReadError
from countersign.plan import model as plan_model
from countersign.plan.model import PlanReadError

REFUSED = [b"", b" \n ", b"{", b'{"a": 1, "a": 2}', b'{"x": NaN}', b"[1e999]",
           b" " + b"{}" * (MAX_INPUT_BYTES // 2)]


def _problems(error: OrdersReadError) -> list[str]:
    return [str(problem) for problem in error.problems]


@pytest.mark.parametrize("data", REFUSED, ids=lambda d: repr(d[:20]))
def test_both_readers_refuse_bytes_alike(data: bytes) -> None:
    with pytest.raises(OrdersReadError) as orders:
        orders_reader.read_bytes(data, "in.json")
    with pytest.raises(PlanReadError) as plan:
        plan_model.read_bytes(data, "in.json")
    assert type(orders.value) is OrdersReadError
    assert _problems(orders.value) == _problems(plan.value)


@pytest.mark.parametrize("value, kind", [([], "an array"), (3, "a int"), ("x", "a str")])
def test_each_reader_names_what_must_be_an_object(value: object, kind: str) -> None:
    with pytest.raises(OrdersReadError) as orders:
        orders_reader.orders_from_data(value)
    with pytest.raises(PlanReadError) as plan:
        plan_model.problem_from_data(value)
    assert _problems(orders.value) == [f"$: orders must be a JSON object, not {kind}"]
    assert _problems(plan.value) == [f"$: a planning problem must be a JSON object, not {kind}"]


def test_files_that_cannot_be_read(tmp_path: Path) -> None:
    for path, why in ((tmp_path / "none.json", "does not exist"), (tmp_path, "is a directory")):
        with pytest.raises(OrdersReadError) as orders:
            orders_reader.read_file(path)
        with pytest.raises(PlanReadError) as plan:
            plan_model.read_file(path)
        assert _problems(orders.value) == _problems(plan.value) == [f"$: {path} {why}"]


def test_validation_problems_are_distinct_capped_and_reworded_per_reader() -> None:
    orders = json.loads(example_bytes("search-and-sample"))
    orders["format"] = "countersign.orders/0"
    orders["goals"] = [{"id": 1}] * 3 + [{"id": n} for n in range(30)]
    with pytest.raises(OrdersReadError) as caught:
        orders_reader.orders_from_data(orders)
    problems = _problems(caught.value)
    assert problems[0] == "$.format: format must be 'countersign.orders/1'"
    assert len(problems) == MAX_PROBLEMS_SHOWN == len(set(problems))
    assert caught.value.total > MAX_PROBLEMS_SHOWN
    assert f"... and {caught.value.total - MAX_PROBLEMS_SHOWN} more problems" in str(caught.value)

    with pytest.raises(PlanReadError) as plan:
        plan_model.problem_from_data({"format": "countersign.orders/1", "level": 3, "typo": 1})
    assert _problems(plan.value)[:2] == [
        "$.format: format must be 'countersign.plan/1'",
        "$.level: level must be 1 (order only) or 2 (order and passes)"]
    assert "$.typo: unknown field (check its spelling)" in _problems(plan.value)
