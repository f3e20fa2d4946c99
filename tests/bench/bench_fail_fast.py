"""How fast hostile input is refused: the wall-clock figures that used to be
assertions in tests/orders and tests/verify (test_avcl < 0.5 s, test_expressions < 1 s,
test_logic < 5 s and < 10 s), printed here instead, because a bound on a shared, busy machine
is a flaky test.

Run: .venv/bin/python -m tests.bench.bench_fail_fast
"""

from __future__ import annotations

import time
from collections.abc import Callable

import pytest

from tests.orders import test_avcl
from tests.verify import test_expressions, test_logic


def _time(action: Callable[[], object]) -> float:
    start = time.perf_counter()
    action()
    return time.perf_counter() - start


def _row(label: str, seconds: float, former_limit: float) -> None:
    print(f"{label:<60} {seconds * 1000:9.1f} ms  (former test limit {former_limit:g} s)")


def main() -> None:
    _row("AVCL billion laughs refused", _time(test_avcl.test_billion_laughs_is_rejected), 0.5)
    _row("AVCL external entity refused", _time(test_avcl.test_external_entity_is_rejected), 0.5)
    _row("AVCL external DTD refused", _time(test_avcl.test_external_dtd_is_rejected), 0.5)
    marks = test_expressions.test_pathological_expressions_are_refused.pytestmark  # type: ignore[attr-defined]
    cases = next(m.args[1] for m in marks if m.name == "parametrize")
    for source, fragment in cases:
        seconds = _time(lambda s=source: test_expressions.error_of(s))
        _row(f"expression refused: {fragment[:40]}", seconds, 1.0)
    _row("logic: extreme numbers and 900-term sums",
         _time(test_logic.test_extreme_numbers_and_long_expressions_never_crash), 10)
    _row("logic: a hard constraint times out as a finding",
         _time(test_logic.test_a_hard_constraint_times_out_as_a_finding), 5)


if __name__ == "__main__":
    del pytest  # imported so that the test modules' decorators resolve as under pytest
    main()
