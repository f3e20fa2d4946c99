"""`countersign export --format imc|moos|avcl`: files out, notes on stderr, refusals exit 1."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from countersign.cli import main
from countersign.orders.examples import example_bytes

from .readers import read_bhv, read_imc


def test_imc_to_stdout_parses_and_notes_go_to_stderr(
        capsysbinary: pytest.CaptureFixture[bytes]) -> None:
    code = main(["export", "example:search-and-sample", "--format", "imc",
                 "--plan-version", "7"])
    out, err = capsysbinary.readouterr()
    assert code == 0
    plan, _ = read_imc(out)
    assert plan.plan_id == "search-and-sample@v7"
    assert b"note NORM /norms/0:" in err and b"note MONITOR /constraints/6:" in err


def test_moos_writes_both_files(tmp_path: Path, capsysbinary: pytest.CaptureFixture[bytes]
                                ) -> None:
    assert main(["export", "example:transect-survey", "--format", "moos",
                 "--output", str(tmp_path)]) == 0
    assert sorted(p.name for p in tmp_path.iterdir()) == [
        "transect-survey.bhv", "transect-survey.moos"]
    graph = read_bhv((tmp_path / "transect-survey.bhv").read_text())
    assert graph.start == "G1"


def test_orders_that_cannot_be_a_plan_exit_1(tmp_path: Path,
                                             capsysbinary: pytest.CaptureFixture[bytes]) -> None:
    data = json.loads(example_bytes("search-and-sample"))
    del data["goals"][0]["next"]["violate"]
    source = tmp_path / "orders.json"
    source.write_text(json.dumps(data))
    assert main(["export", str(source), "--format", "moos"]) == 1
    _, err = capsysbinary.readouterr()
    assert b"cannot export" in err and b"SINK G1" in err


def test_avcl_to_stdout_with_notes_on_stderr(capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["export", "example:search-and-sample", "--format", "avcl"]) == 0
    out, err = capsys.readouterr()
    assert out.startswith('<?xml version="1.0" encoding="UTF-8"?>\n<AVCL version="3.1">')
    assert "note CONSTRAINT /constraints/0:" in err and "note NORM /norms/0:" in err
    assert "note" not in out
