"""An execution is only "no deviation" with the evidence for it: times for every goal run and
readings for every constraint in scope; otherwise "unverified", naming what is missing. Times
that cannot be real, and JSON nested too deep, make the log unreadable (exit 2), never a crash."""

from __future__ import annotations

import json
from datetime import UTC, datetime, timedelta
from pathlib import Path

import pytest

from countersign.cli import main
from countersign.orders.examples import example_bytes
from countersign.orders.reader import read_bytes
from countersign.rehearse.execution import ExecutionLogError, check_execution, read_log
from countersign.rehearse.execution_evidence import TimeWindow

from ..export.execution_logs import evidenced_log

ORDERS = read_bytes(example_bytes("search-and-sample"), "exemplar").orders
RUN = (("G1", "violate"), ("G4", "succeed"), ("G5", "succeed"))
NOW = datetime(2026, 12, 4, 6, 0, tzinfo=UTC)
APPROVED = NOW - timedelta(days=1)
WINDOW = TimeWindow.of(now=NOW, skew_s=300, not_before=APPROVED)


def _iso(moment: datetime) -> str:
    return moment.isoformat().replace("+00:00", "Z")


def _with_times(times: list[tuple[str | None, str | None]]) -> str:
    """The evidenced run with each step's (start, time) replaced; None drops it."""
    lines = []
    for line, (start, time) in zip(evidenced_log(RUN).splitlines(), times, strict=True):
        step = json.loads(line)
        for key, value in (("start", start), ("time", time)):
            if value is None:
                step.pop(key)
            else:
                step[key] = value
        lines.append(json.dumps(step) + "\n")
    return "".join(lines)


def test_a_run_with_times_and_every_reading_is_no_deviation() -> None:
    verdict = check_execution(ORDERS, read_log(evidenced_log(RUN)), WINDOW)
    assert verdict.ok and verdict.status == "no-deviation", verdict.evidence
    assert verdict.summary().endswith("no deviation")
    assert verdict.evidence.read == ("C1", "C2", "C3", "C4", "C5", "C6", "C7")


def test_no_readings_and_no_times_is_unverified_naming_what_is_missing() -> None:
    bare = "".join(json.dumps({"goal": g, "outcome": o}) + "\n" for g, o in RUN)
    verdict = check_execution(ORDERS, read_log(bare), WINDOW)
    assert not verdict.ok and verdict.status == "unverified" and not verdict.deviations
    assert verdict.path is not None  # the path followed is still named
    assert "unverified: no start and end times for steps 1, 2, 3; no readings for C1, C2, " \
        "C3, C4, C5, C6, C7" in verdict.summary()
    assert verdict.to_json()["evidence"]["complete"] is False


def test_readings_missing_for_some_constraints_name_exactly_those() -> None:
    log = evidenced_log(RUN, drop=("nav_error_m", "contact_distance_m"))
    verdict = check_execution(ORDERS, read_log(log), WINDOW)
    assert verdict.status == "unverified"
    assert verdict.evidence.gaps() == ["no readings for C1, C6"]
    assert "C1" not in verdict.evidence.read and "C7" in verdict.evidence.read


def test_a_step_without_its_start_is_unverified() -> None:
    log = _with_times([("0", "10"), (None, "20"), ("20", "30")])
    verdict = check_execution(ORDERS, read_log(log), WINDOW)
    assert verdict.evidence.gaps() == ["no start and end times for step 2"]


@pytest.mark.parametrize(("times", "message"), [
    ([("0", "10"), ("10", "not-a-time"), ("20", "30")], "'not-a-time' is not an ISO 8601"),
    ([("0", "10"), ("10", "5"), ("20", "30")], "times must not run backwards"),
    ([("0", "10"), ("30", "40"), ("20", "50")], "times must not run backwards"),
    ([("0", "10"), ("10", "20"), ("20", "1e999")], "not a finite number"),
    ([("0", "10"), ("10", "20"), ("20", "9e9")], "longer than the time since its approval"),
    ([(_iso(NOW), _iso(NOW)), (_iso(NOW), "9999-12-31T23:59:59Z"), (None, None)],
     "9999-12-31T23:59:59Z is in the future"),
    ([(_iso(APPROVED - timedelta(hours=1)), _iso(NOW)), (None, None), (None, None)],
     "before the orders were approved"),
    ([("2026-12-04T05:00:00", _iso(NOW)), (None, None), (None, None)], "no time zone"),
    ([(_iso(NOW), "10"), (None, None), (None, None)], "mixes ISO 8601 times and numbers"),
])
def test_absurd_times_are_errors_naming_the_step(
        times: list[tuple[str | None, str | None]], message: str) -> None:
    with pytest.raises(ExecutionLogError, match=r"step [0-9]") as raised:
        check_execution(ORDERS, read_log(_with_times(times)), WINDOW)
    assert message in str(raised.value)


def test_times_a_little_ahead_within_the_clock_skew_are_accepted() -> None:
    ahead = _iso(NOW + timedelta(minutes=4))
    log = _with_times([(_iso(NOW - timedelta(hours=1)), _iso(NOW)), (_iso(NOW), ahead),
                       (ahead, ahead)])
    assert check_execution(ORDERS, read_log(log), WINDOW).ok


def test_a_line_nested_a_thousand_deep_is_unreadable_naming_the_line() -> None:
    deep = '{"goal": "G1", "outcome": "succeed", "readings": ' + "[" * 1000 + "]" * 1000 + "}"
    with pytest.raises(ExecutionLogError, match=r"line 2: .*nested") as raised:
        read_log(evidenced_log(RUN[:1]) + deep + "\n")
    assert "RecursionError" not in str(raised.value)


def test_the_command_line_exit_codes_say_no_deviation_unverified_or_unreadable(
        tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    log = tmp_path / "run.ndjson"
    check = ["execution", "check", "example:search-and-sample", str(log)]
    log.write_text(evidenced_log(RUN))
    assert main(check) == 0
    assert "no deviation" in capsys.readouterr().out
    log.write_text(evidenced_log(RUN, drop=("depth_m",)))
    assert main([*check, "--format", "json"]) == 3
    out = json.loads(capsys.readouterr().out)
    assert (out["status"], out["ok"], out["evidence"]["constraints_unread"]) == (
        "unverified", False, ["C7"])
    log.write_text(_with_times([("0", "10"), ("10", "20"), ("20", "9999-01-01T00:00:00Z")]))
    assert main(check) == 2
    assert "step 3 (G5) time" in capsys.readouterr().err
    log.write_text('{"goal": "G1", "outcome": "succeed", "readings": ' + "[" * 1000
                   + "]" * 1000 + "}\n")
    assert main(check) == 2
    assert "line 1" in capsys.readouterr().err
