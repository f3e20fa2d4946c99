"""A validation that keeps no parts (NoParts, the command line's) computes no part keys and
reports what a validation from scratch reports."""

from __future__ import annotations

import pytest

from countersign.orders.examples import example_bytes
from countersign.orders.reader import read_bytes
from countersign.verify import report as report_module
from countersign.verify.parts import NoParts, PartsCache
from countersign.verify.report import validate


@pytest.mark.parametrize("name", ["search-and-sample", "search-and-sample-refined",
                                  "harbor-approach-survey"])
def test_no_parts_computes_no_keys_and_reports_the_same(
        name: str, monkeypatch: pytest.MonkeyPatch) -> None:
    orders = read_bytes(example_bytes(name), name).orders
    from_scratch = validate(orders, parts=PartsCache()).to_json()

    def no_keys(*_: object) -> object:
        raise AssertionError("part keys computed for a store that keeps nothing")

    monkeypatch.setattr(report_module, "part_keys", no_keys)
    assert validate(orders, parts=NoParts()).to_json() == from_scratch


def test_no_parts_keeps_nothing() -> None:
    parts = NoParts()
    parts.put("core", "core:key", object())
    assert parts.get("core", "core:key") is None
