"""A validation's solver time is bounded: what the solver cannot decide within the
request's budget is a warning with the DESIGN.md codes, never an error nor a hang."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from countersign.cli import main
from countersign.orders.reader import orders_from_data
from countersign.verify.logic import LogicCache
from countersign.verify.report import validate

from ..heavy_orders import heavy_orders

SOLVER_CODES = {"CONTRADICTION", "PROPERTY", "VACUOUS", "NORM"}


def _orders(constraints: int, properties: int):  # type: ignore[no-untyped-def]
    data = heavy_orders(constraints, properties)
    # Decidable at once, and false at every goal (their depths are 20-60 m): an error when the
    # solver has time, undecided when the budget is spent.
    data["properties"].append({"id": "SHALLOW", "always": "depth_m <= 10"})
    return orders_from_data(data)


def test_an_easy_property_fails_when_the_solver_has_time() -> None:
    report = validate(_orders(0, 0), logic_cache=LogicCache())
    shallow = [f for f in report.findings if f.details.get("property") == "SHALLOW"]
    assert [f.severity for f in shallow] == ["error"], shallow


def test_what_the_budget_leaves_undecided_is_a_warning() -> None:
    report = validate(_orders(4, 2), logic_cache=LogicCache(), solver_budget_s=0.0)
    solver = [f for f in report.findings if f.code in SOLVER_CODES]
    assert solver and all(f.severity == "warning" for f in solver), solver
    shallow = [f for f in report.findings if f.details.get("property") == "SHALLOW"]
    assert len(shallow) == 1 and shallow[0].severity == "warning"
    assert "could not be decided" in shallow[0].message
    # Every path property is reported undecided, under its own code.
    undecided = {f.details.get("property") for f in solver if f.code == "PROPERTY"}
    assert undecided == {"P0", "P1", "SHALLOW"}


def test_the_command_line_takes_a_solver_budget(tmp_path: Path,
                                                capsys: pytest.CaptureFixture[str]) -> None:
    data = heavy_orders(2, 1)
    data["properties"].append({"id": "SHALLOW", "always": "depth_m <= 10"})
    target = tmp_path / "heavy.json"
    target.write_text(json.dumps(data))
    main(["validate", str(target), "--format", "json", "--solver-budget", "0"])
    report = json.loads(capsys.readouterr().out)
    shallow = [f for f in report["findings"] if f["code"] == "PROPERTY"
               and "SHALLOW" in f["message"]]
    assert [f["severity"] for f in shallow] == ["warning"]
    for bad in ("inf", "nan", "-1", "soon"):
        with pytest.raises(SystemExit) as exit_code:
            main(["validate", str(target), "--solver-budget", bad])
        assert exit_code.value.code == 2
        assert "--solver-budget" in capsys.readouterr().err
