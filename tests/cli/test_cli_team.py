"""`countersign validate` of team orders: team findings and counts, exit codes; the other
commands refuse a team with exit 2 and say what to do instead."""

from __future__ import annotations

import json
from pathlib import Path

from .test_bad_input import run_cli, write

TEAM = "example:search-and-sample-team"


def test_validate_prints_team_findings_and_joint_counts() -> None:
    result = run_cli("validate", TEAM)
    assert result.returncode == 1, result.stderr
    out = result.stdout
    assert "TEAM" in out and "[R1, remus-100/G1 violate, vehicle-2/G1 violate -> " \
        "(remus-100/G4, vehicle-2/ABORT)]" in out
    assert "Team of 2: remus-100, vehicle-2" in out
    assert "remus-100 (search-and-sample-v1, sha256:" in out and "75 paths" in out
    assert "Meetings: R1 (remus-100, vehicle-2)" in out
    assert "Joint executions: 449 (14 deadlocked)" in out
    assert "8  remus-100 left waiting, vehicle-2 ABORT" in out
    assert "remus-100 waits at R1 for ever in 8" in out


def test_validate_json_of_a_clean_team_exits_0(tmp_path: Path) -> None:
    team = json.loads(run_cli("examples", "search-and-sample-team").stdout)
    team["team"][1]["orders"]["goals"][0]["next"]["violate"] = "G2"
    team["team"][0]["orders"]["goals"][1]["next"]["fail"] = "G4"
    result = run_cli("validate", write(tmp_path, "team.json", json.dumps(team).encode()),
                     "--format", "json")
    assert result.returncode == 0, result.stdout
    report = json.loads(result.stdout)
    assert report["ok"] and report["team"]["joint"]["deadlocked"] == 0
    assert report["paths"]["count"] == report["team"]["joint"]["count"]


def test_unreadable_team_is_exit_2_naming_where(tmp_path: Path) -> None:
    team = json.loads(run_cli("examples", "search-and-sample-team").stdout)
    team["team"][1]["vehicle"] = "remus-100"
    result = run_cli("validate", write(tmp_path, "team.json", json.dumps(team).encode()))
    assert result.returncode == 2
    assert "team[1].vehicle" in result.stderr and "Traceback" not in result.stderr


def test_single_vehicle_commands_refuse_a_team_with_exit_2() -> None:
    for args in (["paths", TEAM], ["export", TEAM, "--format", "dot"],
                 ["validate", TEAM, "--explain"]):
        result = run_cli(*args)
        assert result.returncode == 2, (args, result.stdout)
        assert "team" in result.stderr and "Traceback" not in result.stderr


def test_plain_export_puts_the_meeting_points_side_by_side() -> None:
    result = run_cli("export", TEAM, "--format", "plain")
    assert result.returncode == 0, result.stderr
    lines = result.stdout.splitlines()
    assert "Meeting | remus-100" in "\n".join(lines)
    row = next(line for line in lines if line.startswith("R1 "))
    assert "Goal 4 (Rendezvous with vehicle 2 in Area C)" in row
    assert "Goal 2 (Rendezvous with vehicle 1 in Area C)" in row
    assert "Vehicle 1 of 2: remus-100, orders sha256:" in result.stdout
    assert "Mission orders search-and-sample-v1" in result.stdout
