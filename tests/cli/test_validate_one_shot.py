"""`countersign validate` validates once and ends: it keeps no report parts, so it computes
none of their keys (the checker fingerprint and a serialisation of the orders per part)."""

from __future__ import annotations

import contextlib
import io

import pytest

from countersign.cli import main
from countersign.verify import report as report_module


def test_validate_computes_no_part_keys(monkeypatch: pytest.MonkeyPatch) -> None:
    def no_keys(*_: object) -> object:
        raise AssertionError("part keys computed by a one-shot validation")

    monkeypatch.setattr(report_module, "part_keys", no_keys)
    out = io.StringIO()
    with contextlib.redirect_stdout(out):
        assert main(["validate", "example:search-and-sample", "--format", "json"]) == 0
    assert '"ok": true' in out.getvalue()
