"""A team's rehearsal record holds each member's own run fields (goals, outcomes, terminal,
...) under `team.members`, and the readers of records read it per member: the execution
check (`countersign execution check --member VEHICLE`, the approval's rehearsal verdicts)."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

import pytest

from countersign.cli import main
from countersign.export.rehearsal_log import RehearsalRecordError, rehearsal_runs
from countersign.orders.examples import load_example
from countersign.orders.team import member_digests

TEAM = "example:search-and-sample-team"


@pytest.fixture(scope="module")
def record_file(tmp_path_factory: pytest.TempPathFactory) -> Path:
    target = tmp_path_factory.mktemp("team") / "record.json"
    assert main(["rehearse", TEAM, "--headless", "--record-out", str(target)]) == 0
    return target


def _record(path: Path) -> dict[str, Any]:
    data: dict[str, Any] = json.loads(path.read_text())
    return data


def test_each_member_holds_its_own_run_fields(record_file: Path) -> None:
    record = _record(record_file)
    digests = member_digests(load_example(TEAM.removeprefix("example:")))
    members = record["team"]["members"]
    assert [m["vehicle"] for m in members] == list(digests)
    for member in members:
        last = member["runs"][-1]
        assert member["goals"] == last["goals"] and member["goals"]
        assert member["outcomes"] == last["outcomes"]
        assert member["terminal"] == last["terminal"] == "COMPLETE"
        assert member["terminal_kind"] == last["terminal_kind"]
        assert member["orders"]["digest"] == digests[member["vehicle"]]
        assert member["steps"] > 0 and member["legs_flown"]
    # The team has no single run of its own: the joint end is in `team`.
    assert record["goals"] == [] and record["terminal"] is None


def test_the_execution_reader_reads_a_member_and_refuses_otherwise(record_file: Path) -> None:
    record = _record(record_file)
    for member in record["team"]["members"]:
        runs = rehearsal_runs(record, member["vehicle"])
        assert len(runs) == 1 and runs[0].terminal == "COMPLETE"
        steps = [json.loads(line) for line in runs[0].ndjson.splitlines()]
        assert [s["goal"] for s in steps] == member["goals"]
        # From the member's own events: times and readings, not only goals and outcomes.
        assert all("start" in s and "time" in s for s in steps)
    with pytest.raises(RehearsalRecordError, match=r"a team's \(remus-100, vehicle-2\): name"):
        rehearsal_runs(record)
    with pytest.raises(RehearsalRecordError, match="no member 'auv-9'"):
        rehearsal_runs(record, "auv-9")
    single = {**record, "team": None}
    with pytest.raises(RehearsalRecordError, match="one vehicle's"):
        rehearsal_runs(single, "vehicle-2")


def test_execution_check_reads_a_team_record_per_member(
        record_file: Path, capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["execution", "check", TEAM, str(record_file), "--member", "vehicle-2",
                 "--format", "json"]) in (0, 3)
    verdict = json.loads(capsys.readouterr().out)
    assert verdict["terminal"] == "COMPLETE" and verdict["deviations"] == []
    for argv, named in ((["--member", "auv-9"], "the team's members are remus-100, "
                         "vehicle-2"),
                        ([], "execution check of a team's orders needs --member VEHICLE")):
        assert main(["execution", "check", TEAM, str(record_file), *argv]) == 2
        assert named in capsys.readouterr().err
    assert main(["execution", "check", "example:search-and-sample", str(record_file)]) == 2
    assert "the record is a team's (remus-100, vehicle-2): name the member" in \
        capsys.readouterr().err
    assert main(["execution", "check", "example:search-and-sample", str(record_file),
                 "--member", "vehicle-2"]) == 2
    assert "these orders are one vehicle's, not a team's" in capsys.readouterr().err
