"""The benchmarks' own inputs are valid, and the benchmark refuses an invalid one."""

from __future__ import annotations

import pytest

from countersign.orders.model import Orders
from countersign.verify import validate
from tests.bench.bench_meo import checked, meo_mission


def test_meo_benchmark_mission_is_valid() -> None:
    report = validate(meo_mission(60))
    assert [f.code for f in report.findings if f.severity == "error"] == []
    assert checked(meo_mission(60)).id == "meo-60"


def test_an_invalid_benchmark_input_is_refused_before_timing() -> None:
    data = meo_mission(20).model_dump(mode="json", exclude_unset=True)
    data.pop("quantities")
    with pytest.raises(SystemExit, match="EXPR"):
        checked(Orders.model_validate(data))
