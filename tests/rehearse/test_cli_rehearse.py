"""`countersign rehearse` without the web app."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from countersign.cli import main


def test_headless_rehearsal_writes_the_record(tmp_path: Path, capsys: pytest.CaptureFixture[str]
                                              ) -> None:
    out = tmp_path / "rec.json"
    code = main(["rehearse", "example:transect-survey", "--headless", "--fault", "nav_drift@G4",
                 "--record-out", str(out), "--format", "json"])
    assert code == 0
    printed = json.loads(capsys.readouterr().out)
    saved = json.loads(out.read_text())
    assert printed["digest"] == saved["digest"]
    assert saved["format"] == "countersign.rehearsal/1"
    assert saved["goals"] == ["G1", "G2", "G3", "G4", "G5"]
    assert saved["outcomes"][3] != "succeed" and saved["terminal"] == "COMPLETE"
    assert saved["inputs"]["faults"][0].startswith("nav_drift@")


def test_text_summary_and_html_replay(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    html = tmp_path / "replay.html"
    code = main(["rehearse", "example:search-and-sample", "--source", "replay", "--path", "5",
                 "--headless", "--html-out", str(html)])
    assert code == 0
    text = capsys.readouterr().out
    assert "Path #5:" in text and "G4: fail." in text and "Mission Abort!" in text
    assert "viser" not in text  # viser's banner goes to standard error
    assert html.read_bytes().startswith(b"<!doctype html>")


@pytest.mark.parametrize(("argv", "code"), [
    (["--source", "manual", "--headless"], 2),
    (["--fault", "meteor", "--headless"], 2),
    (["--path", "3", "--headless"], 2),
    (["--source", "replay", "--path", "999", "--headless"], 1),
])
def test_bad_usage(argv: list[str], code: int) -> None:
    assert main(["rehearse", "example:search-and-sample", *argv]) == code


def test_unreadable_file(tmp_path: Path) -> None:
    bad = tmp_path / "bad.json"
    bad.write_text("{")
    assert main(["rehearse", str(bad), "--headless"]) == 2
    assert main(["rehearse", str(tmp_path / "missing.json"), "--headless"]) == 2
