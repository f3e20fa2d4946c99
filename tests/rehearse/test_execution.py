"""Execution logs against the orders: all 75 paths of the exemplar are recognised with their
`countersign paths` numbers; planted deviations are named."""

from __future__ import annotations

import json

import pytest

from countersign.orders.examples import example_bytes
from countersign.orders.model import Orders
from countersign.orders.reader import orders_from_data, read_bytes
from countersign.rehearse.execution import (
    ExecutionLogError,
    check_execution,
    read_log,
)
from countersign.verify.budget import WorstPath, worst_paths
from countersign.verify.paths import iter_paths, paths_of

ORDERS = read_bytes(example_bytes("search-and-sample"), "exemplar").orders


def _log(*steps: tuple[str, str] | tuple[str, str, dict[str, float]]) -> str:
    """A log without times (paths and deviations, not evidence, are under test)."""
    return "".join(json.dumps({"goal": s[0], "outcome": s[1],
                               "readings": s[2] if len(s) > 2 else {}}) + "\n"
                   for s in steps)


def test_every_path_of_the_exemplar_is_recognised_with_its_number() -> None:
    graph, counts = paths_of(ORDERS)
    assert counts is not None
    seen = 0
    for path in iter_paths(graph, counts):
        log = _log(*zip(path.goals, path.outcomes, strict=True))
        verdict = check_execution(ORDERS, read_log(log))
        assert not verdict.deviations and verdict.status == "unverified"
        assert (verdict.path, verdict.terminal) == (path.index, path.terminal)
        seen += 1
    assert seen == 75


def test_a_skipped_goal_is_named() -> None:
    verdict = check_execution(ORDERS, read_log(_log(("G1", "succeed"), ("G3", "succeed"),
                                                    ("G4", "succeed"), ("G5", "succeed"))))
    assert [d.code for d in verdict.deviations] == ["SKIPPED-GOAL"]
    assert "G2 was skipped" in verdict.summary() and verdict.path is None


def test_a_wrong_transition_is_named() -> None:
    verdict = check_execution(ORDERS, read_log(_log(("G1", "fail"), ("G2", "succeed"),
                                                    ("G3", "succeed"), ("G4", "succeed"),
                                                    ("G5", "succeed"))))
    assert verdict.deviations[0].code == "WRONG-TRANSITION"
    assert verdict.deviations[0].step == 2 and "G3 next, but G2 ran" in \
        verdict.deviations[0].message


def test_a_depth_reading_below_a_constraint_is_named() -> None:
    verdict = check_execution(ORDERS, read_log(_log(
        ("G1", "violate", {"depth_m": 30}), ("G4", "succeed"),
        ("G5", "succeed", {"depth_m": 15.5}))))
    assert [(d.code, d.step) for d in verdict.deviations] == [("CONSTRAINT", 3)]
    assert "depth_m=15.5 break C7 (depth_m >= 20) during G5" in \
        verdict.deviations[0].message


def test_an_unfinished_log_and_steps_after_the_end_are_named() -> None:
    short = check_execution(ORDERS, read_log(_log(("G1", "violate"), ("G4", "succeed"))))
    assert [d.code for d in short.deviations] == ["INCOMPLETE"]
    extra = check_execution(ORDERS, read_log(_log(("G1", "violate"), ("G4", "succeed"),
                                                  ("G5", "fail"), ("G5", "succeed"))))
    assert [d.code for d in extra.deviations] == ["AFTER-END"]


@pytest.mark.parametrize("text", ['{"goal": "G1"}', "not json", '{"goal": "G1", "outcome": "x"}'])
def test_unreadable_logs_name_the_line(text: str) -> None:
    with pytest.raises(ExecutionLogError, match="line 1"):
        read_log(text)


def test_the_command_line_names_the_path_or_the_deviation(
        tmp_path: pytest.TempPathFactory, capsys: pytest.CaptureFixture[str]) -> None:
    from pathlib import Path

    from countersign.cli import main

    log = Path(str(tmp_path)) / "run.ndjson"
    log.write_text(_log(("G1", "violate"), ("G4", "succeed"), ("G5", "succeed")))
    assert main(["execution", "check", "example:search-and-sample", str(log)]) == 3
    graph, counts = paths_of(ORDERS)
    assert counts is not None
    number = next(p.index for p in iter_paths(graph, counts)
                  if p.outcomes == ("violate", "succeed", "succeed"))
    assert capsys.readouterr().out.startswith(f"executed as path {number} to COMPLETE")
    log.write_text(_log(("G1", "fail"), ("G2", "succeed")))
    assert main(["execution", "check", "example:search-and-sample", str(log),
                 "--format", "json"]) == 1
    assert json.loads(capsys.readouterr().out)["deviations"][0]["code"] == "WRONG-TRANSITION"
    log.write_text("nonsense\n")
    assert main(["execution", "check", "example:search-and-sample", str(log)]) == 2


def _with_budget(**budget: float) -> Orders:
    data = json.loads(example_bytes("search-and-sample"))
    data["vehicles"][0]["budget"] = budget
    return orders_from_data(data)


def _timed(*steps: tuple[str, str, str], readings: dict[int, dict[str, float]] | None = None,
           start: str | None = None) -> str:
    lines = []
    for i, (goal, outcome, time) in enumerate(steps):
        line: dict[str, object] = {"goal": goal, "outcome": outcome, "time": time,
                                   "readings": (readings or {}).get(i, {})}
        if i == 0 and start:
            line["start"] = start
        lines.append(json.dumps(line) + "\n")
    return "".join(lines)


RUN = (("G1", "violate"), ("G4", "succeed"), ("G5", "succeed"))


def test_time_over_the_budget_from_the_logs_timestamps_is_named() -> None:
    orders = _with_budget(duration_s=3600, energy_wh=1500)
    times = ("2026-12-02T01:00:00Z", "2026-12-02T01:30:00Z", "2026-12-02T01:50:00Z")
    steps = [(g, o, t) for (g, o), t in zip(RUN, times, strict=True)]
    within = check_execution(orders, read_log(_timed(*steps)))
    assert not within.deviations  # 50 min from the first report: a lower bound
    over = check_execution(orders, read_log(_timed(*steps, start="2026-12-02T00:30:00Z")))
    assert [(d.code, d.step) for d in over.deviations] == [("BUDGET", 3)]
    assert "4,800.0 s of time (from its timestamps), more than the budget of 3,600.0 s" in \
        over.deviations[0].message
    assert over.path is None
    assert {u.quantity: u.source for u in over.usage} == {"duration_s": "timestamps",
                                                          "energy_wh": "model"}


def test_energy_over_the_budget_from_readings_is_named() -> None:
    orders = _with_budget(duration_s=43200, energy_wh=500)
    steps = [(g, o, f"{60 * i}") for i, (g, o) in enumerate(RUN)]
    fine = check_execution(orders, read_log(_timed(*steps, readings={1: {"energy_wh": 420}})))
    assert not fine.deviations
    over = check_execution(orders, read_log(_timed(
        *steps, readings={1: {"energy_wh": 420}, 2: {"energy_wh": 515.5}})))
    assert [(d.code, d.step) for d in over.deviations] == [("BUDGET", 3)]
    assert "515.5 Wh of energy (from its readings)" in over.deviations[0].message


def test_without_times_or_readings_the_cost_model_of_verify_is_used() -> None:
    graph, counts = paths_of(ORDERS)
    assert counts is not None
    worst = next(iter(report_worst(ORDERS).values()))  # verify's worst path, energy
    path = next(p for p in iter_paths(graph, counts)
                if p.goals == worst.goals and p.outcomes == worst.outcomes)
    steps = list(zip(path.goals, path.outcomes, strict=True))
    modelled = check_execution(ORDERS, read_log(_log(*steps)))
    energy = next(u for u in modelled.usage if u.quantity == "energy_wh")
    assert energy.source == "model" and abs(energy.used - worst.total) < 1e-6
    tight = _with_budget(energy_wh=worst.total - 1, duration_s=43200)
    assert [d.code for d in check_execution(tight, read_log(_log(*steps))).deviations] == \
        ["BUDGET"]


def report_worst(orders: Orders) -> dict[str, WorstPath]:
    graph, _ = paths_of(orders)
    worst = worst_paths(orders, graph)
    assert worst is not None
    return worst
