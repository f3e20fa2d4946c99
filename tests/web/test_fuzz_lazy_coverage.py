"""The fuzz module's coverage cases are made when its tests run (tests/web/lazy_coverage.py):
the same cases, in the same order, as schemathesis attaches while collecting."""

from __future__ import annotations

import json
from collections.abc import Callable
from pathlib import Path
from typing import Any

import pytest
import schemathesis
from schemathesis.generation.feedback import NO_FEEDBACK
from schemathesis.generation.hypothesis import builder
from schemathesis.pytest._test_builder import build_operation_test

from .lazy_coverage import EAGER_ADD_COVERAGE, LazyExamples, lazy_add_coverage

OPENAPI = Path(__file__).resolve().parents[2] / "frontend" / "openapi.json"
# A body, path parameters, a query: each kind of coverage case; two operations of one path
# (/api/tokens), whose undeclared methods (TRACE...) go to the first of them to make its cases.
# (planView's thousands of cases take seconds to make; they come from the same code.)
OPERATIONS = ("login", "getVersion", "listTokens", "createToken", "listMissions")


def _case(case: Any) -> None:
    del case


def _described(example: Any) -> tuple[str, str, str]:
    case = example.kwargs["case"]
    data = case.meta.phase.data
    return repr(case), repr(case.meta.components), f"{data.scenario} {data.description}"


def _tests(add_coverage: Callable[..., Any], monkeypatch: pytest.MonkeyPatch) -> list[Any]:
    """OPERATIONS' tests as schemathesis' pytest plugin builds them, in that order, from a schema
    of their own (a schema remembers which undeclared methods of a path it has sent)."""
    schema = schemathesis.openapi.from_dict(json.loads(OPENAPI.read_text()))
    found = {result.ok().definition.raw.get("operationId"): result.ok()
             for result in schema.get_all_operations()}
    monkeypatch.setattr(builder, "add_coverage", add_coverage)
    try:
        return [build_operation_test(config=schema.config, operation=found[name], test_func=_case,
                                     given_kwargs={}, feedback=NO_FEEDBACK)
                for name in OPERATIONS]
    finally:
        monkeypatch.undo()


def test_lazy_cases_are_the_collected_ones(monkeypatch: pytest.MonkeyPatch) -> None:
    eager = _tests(EAGER_ADD_COVERAGE, monkeypatch)
    lazy = _tests(lazy_add_coverage, monkeypatch)
    assert all(isinstance(test.hypothesis_explicit_examples, LazyExamples)
               and not test.hypothesis_explicit_examples.made for test in lazy)
    # Made in the order the module's tests run, which is the order they were collected in.
    for name, made, collected in zip(OPERATIONS, lazy, eager, strict=True):
        cases = [_described(e) for e in reversed(made.hypothesis_explicit_examples)]
        assert cases == [_described(e) for e in reversed(collected.hypothesis_explicit_examples)]
        assert len(cases) > 5, name
        assert builder.UnserializablePayloadMark.get(made) == \
            builder.UnserializablePayloadMark.get(collected)
    assert any("Unspecified HTTP method" in case[2] for case in map(
        _described, lazy[OPERATIONS.index("listTokens")].hypothesis_explicit_examples))


def test_the_fuzz_module_makes_its_cases_lazily() -> None:
    from . import test_fuzz  # noqa: F401  (installs the lazy builder on import)

    assert builder.add_coverage is lazy_add_coverage
