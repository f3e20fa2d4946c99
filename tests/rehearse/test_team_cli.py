"""`countersign rehearse` of team orders: headless, the joint events one a line,
each naming its vehicle; bad team options exit 2 naming what is wrong."""

from __future__ import annotations

import json
import re
import subprocess
import sys

TEAM = "example:search-and-sample-team"


def _cli(*args: str) -> subprocess.CompletedProcess[str]:
    # A generous timeout only so that a hang fails instead of blocking: never a speed check.
    return subprocess.run([sys.executable, "-m", "countersign.cli", "rehearse", *args],
                          capture_output=True, text=True, timeout=600, check=False)


def test_headless_team_prints_joint_events_naming_each_vehicle() -> None:
    result = _cli(TEAM, "--headless", "--source", "replay")
    assert result.returncode == 0, result.stderr
    lines = result.stdout.splitlines()
    assert lines[0] == "Team of 2: remus-100, vehicle-2"
    events = [line.strip() for line in lines if line.startswith("  [")]
    assert events
    for line in events:
        assert re.match(r"\[\d+h\d\dm\] (remus-100|vehicle-2)[ :]", line), line
    assert any(line.endswith("remus-100 G4: Meets vehicle-2 at meeting R1: shared outcome "
                             "succeed (replayed from remus-100's path).") for line in events)
    assert any("vehicle-2 G2: Meets remus-100 at meeting R1" in line for line in events)
    assert "Joint end: remus-100:COMPLETE + vehicle-2:COMPLETE" in lines


def test_vehicle_2_aborting_shows_the_deadlock_in_words() -> None:
    result = _cli(TEAM, "--headless", "--member-path", "vehicle-2=19", "--format", "json")
    assert result.returncode == 0, result.stderr
    record = json.loads(result.stdout)["record"]
    assert record["team"]["joint_end"] == "remus-100:waiting + vehicle-2:ABORT"
    deadlocks = [e for e in record["events"] if e["kind"] == "deadlock"]
    assert [e["vehicle"] for e in deadlocks] == ["remus-100"]
    assert "vehicle-2 has ended at ABORT (Mission abort), so it can no longer come" \
        in deadlocks[0]["text"]
    assert all(e["vehicle"] in ("remus-100", "vehicle-2") for e in record["events"])


def test_bad_team_options_exit_2_naming_what() -> None:
    for args, words in (
        (("--member-path", "vehicle-9=1"), "vehicle-9"),
        (("--member-path", "vehicle-2"), "VEHICLE=N"),
        (("--member-path", "vehicle-2=99"), "between 1 and 19"),
        (("--source", "tour"), "simulate or replay"),
        (("--fault", "vehicle-9:leak"), "vehicle-9"),
        (("--fault", "remus-100:melt"), "unknown fault"),
    ):
        result = _cli(TEAM, "--headless", *args)
        assert result.returncode == 2, (args, result.stdout, result.stderr)
        assert words in result.stderr, (args, result.stderr)
        assert "Traceback" not in result.stderr
