"""Vehicle logs as execution input: IMC PlanControlState sequences (written with
imcpy, the vehicle side's own library) and MOOS alog lines become the NDJSON execution log and
go through the same checker."""

from __future__ import annotations

import json
from collections.abc import Sequence
from pathlib import Path

import imcpy
import pytest

from countersign.export.execution_input import (
    ExecutionInputError,
    detect,
    from_alog,
    from_imc,
    to_execution_log,
)
from countersign.export.moos import helm_modes, mode_names
from countersign.orders.examples import example_bytes
from countersign.orders.reader import orders_from_data, read_bytes, read_file
from countersign.rehearse.execution import check_execution, read_log
from countersign.verify.paths import iter_paths, paths_of
from countersign.verify.refine import checked_form

ORDERS = read_bytes(example_bytes("search-and-sample"), "exemplar").orders
CONDITION = {"succeed": "ManeuverIsDone", "fail": "ManeuverFailed",
             "violate": "ConstraintViolated"}
T0 = 1_796_000_000.0  # 2026-11-30


def _state(man_id: str, at: float, state: str = "EXECUTING",
           outcome: str = "NONE") -> bytes:
    message = imcpy.PlanControlState()
    message.state = getattr(imcpy.PlanControlState.StateEnum, state)
    message.plan_id, message.man_id = f"{ORDERS.id}@v3", man_id
    message.last_outcome = getattr(imcpy.PlanControlState.LastPlanOutcomeEnum, outcome)
    message.timestamp = at
    return bytes(message.serialize())


def _logbook(text: str, at: float) -> bytes:
    message = imcpy.LogBookEntry()
    message.text, message.context, message.timestamp = text, "monitor", at
    return bytes(message.serialize())


def _depth(depth: float, at: float) -> bytes:
    message = imcpy.EstimatedState()
    message.depth, message.alt, message.timestamp = depth, -1.0, at
    return bytes(message.serialize())


def imc_run(goals: Sequence[str], outcomes: Sequence[str], terminal: str, *,
            hints: bool = True, step_s: float = 600.0,
            depths: dict[int, float] | None = None, t0: float = T0) -> bytes:
    """PlanControlState as DUNE reports a plan: maneuver after maneuver, then READY."""
    data, at = b"", t0
    for i, (goal, outcome) in enumerate(zip(goals, outcomes, strict=True)):
        data += _state(goal, at) + _state(goal, at + 1)  # DUNE repeats the state at 1 Hz
        if depths and i in depths:
            data += _depth(depths[i], at + 2)
        at += step_s
        if hints:
            data += _logbook(CONDITION[outcome], at - 1)
    data += _state(terminal, at) + _state("", at + 60, "READY", "SUCCESS")
    return data


def _paths() -> list:  # type: ignore[type-arg]
    graph, counts = paths_of(ORDERS)
    assert counts is not None
    return list(iter_paths(graph, counts))


def test_every_exemplar_path_as_plan_control_state_gets_its_number() -> None:
    paths = _paths()
    assert len(paths) == 75
    for path in paths:
        data = imc_run(path.goals, path.outcomes, path.terminal)
        converted = to_execution_log(ORDERS, data)
        assert converted.fmt == "imc" and not converted.notes
        verdict = check_execution(ORDERS, read_log(converted.ndjson))
        assert not verdict.deviations, (path.index, verdict.deviations)
        assert (verdict.path, verdict.terminal) == (path.index, path.terminal)


def test_without_logged_outcomes_the_transition_taken_names_the_outcome() -> None:
    unique = [p for p in _paths() if all(
        [ORDERS.goal_index()[g].successors(o)[0] for o in ("succeed", "fail", "violate")]
        .count(ORDERS.goal_index()[g].successors(x)[0]) == 1
        for g, x in zip(p.goals, p.outcomes, strict=True))]
    assert unique
    for path in unique:
        converted = from_imc(ORDERS, imc_run(path.goals, path.outcomes, path.terminal,
                                             hints=False))
        assert check_execution(ORDERS, read_log(converted.ndjson)).path == path.index
    ambiguous = next(p for p in _paths() if p not in unique)
    converted = from_imc(ORDERS, imc_run(ambiguous.goals, ambiguous.outcomes,
                                         ambiguous.terminal, hints=False))
    assert any("no outcome was logged" in note for note in converted.notes)


def test_plan_control_state_deviations_are_named() -> None:
    path = next(p for p in _paths() if p.outcomes == ("violate", "succeed", "succeed"))
    # A depth of 15.5 m during G5 (C7: depth_m >= 20), read from EstimatedState.
    deep = from_imc(ORDERS, imc_run(path.goals, path.outcomes, path.terminal,
                                    depths={0: 30.0, 2: 15.5}))
    verdict = check_execution(ORDERS, read_log(deep.ndjson))
    assert [(d.code, d.step) for d in verdict.deviations] == [("CONSTRAINT", 3)]
    assert "depth_m=15.5 break C7" in verdict.deviations[0].message
    # A skipped goal: the vehicle went from G1 straight to G3.
    skipped = from_imc(ORDERS, imc_run(("G1", "G3", "G4", "G5"), ("succeed",) * 4,
                                       "COMPLETE"))
    assert check_execution(ORDERS, read_log(skipped.ndjson)).deviations[0].code == \
        "SKIPPED-GOAL"
    # Four hours per goal against a budget of two hours: timestamps say so.
    data = json.loads(example_bytes("search-and-sample"))
    data["vehicles"][0]["budget"]["duration_s"] = 7200
    tight = orders_from_data(data)
    slow = from_imc(tight, imc_run(path.goals, path.outcomes, path.terminal,
                                   step_s=4 * 3600))
    over = check_execution(tight, read_log(slow.ndjson))
    assert [d.code for d in over.deviations] == ["BUDGET"]
    assert "43,200.0 s of time (from its timestamps)" in over.deviations[0].message
    first = json.loads(slow.ndjson.splitlines()[0])
    assert first["start"] == "2026-11-30T00:53:20Z" and first["goal"] == "G1"


def alog_run(goals: Sequence[str], outcomes: Sequence[str], terminal: str,
             depths: dict[int, float] | None = None) -> str:
    ids = [g.id for g in ORDERS.goals] + [t.id for t in ORDERS.effective_terminals]
    mode = mode_names(ids)
    lines = ["%% LOGSTART 1796000000.0", "%% (MOOS alog, subset)"]
    at = 10.0
    for i, (goal, outcome) in enumerate(zip(goals, outcomes, strict=True)):
        lines.append(f"{at:.3f} MODE pHelmIvP ACTIVE:{mode[goal]}")
        if depths and i in depths:
            lines.append(f"{at + 5:.3f} NAV_DEPTH uSimMarine {depths[i]}")
        at += 300
        if outcome != "succeed":
            lines.append(f"{at - 1:.3f} GOAL_OUTCOME pMonitor {outcome}")
        else:
            lines.append(f"{at - 1:.3f} MISSION_GOAL pHelmIvP "
                         f"{mode[ORDERS.goal_index()[goal].successors('succeed')[0]]}")
    lines.append(f"{at:.3f} MODE pHelmIvP ACTIVE:{mode[terminal]}")
    lines.append(f"{at + 1:.3f} MISSION_RESULT pHelmIvP {terminal}")
    return "\n".join(lines) + "\n"


def test_every_exemplar_path_as_a_moos_alog_gets_its_number() -> None:
    for path in _paths():
        text = alog_run(path.goals, path.outcomes, path.terminal)
        assert detect(text.encode()) == "alog"
        verdict = check_execution(ORDERS, read_log(from_alog(ORDERS, text).ndjson))
        assert (verdict.deviations, verdict.path) == ((), path.index), verdict.deviations
    path = next(p for p in _paths() if p.outcomes == ("violate", "succeed", "succeed"))
    deep = from_alog(ORDERS, alog_run(path.goals, path.outcomes, path.terminal, {2: 12.0}))
    assert check_execution(ORDERS, read_log(deep.ndjson)).deviations[0].code == "CONSTRAINT"


# What pLogger writes with WildCardLogging = true (lines as MOOS-IvP 24.8 wrote them): a
# framed header, any variables, values with no text, and DB_VARSUMMARY, whose value runs over
# several lines that do not start with a time.
PLOGGER_HEADER = """%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%
%% LOG FILE:       ./search_and_sample/search_and_sample.alog
%% FILE OPENED ON  Thu Jan  1 00:00:00 1970
%% LOGSTART           17963612569.86093
%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%%
-5.18998        USM_FSUMMARY         uSimMarine      ang=0, mag=0, xmag=0, ymag=0 
-1.30739        DEPLOY               pHelmIvP        false 
0.10000         MOOS_MANUAL_OVERIDE  pHelmIvP        
0.32415  DB_VARSUMMARY  MOOSDB_remus_100 AIS_REPORT  23:59:59.000  (write pending)  0.0 Hz ~  
AIS_REPORT_LOCAL     23:59:59.000         (write pending)      0.0 Hz ~  
APPCAST_REQ          23:59:59.000         (write pending)      0.0 Hz ~  
BHV_STATUS           20:45:52.653         pHelmIvP             0.0 Hz S  name=b54_ABORT_stop,pc...
"""  # noqa: W291


def test_what_plogger_writes_is_read_and_the_skipped_lines_are_counted() -> None:
    path = next(p for p in _paths() if p.index == 17)
    body = alog_run(path.goals, path.outcomes, path.terminal).split("\n", 2)[2]
    text = PLOGGER_HEADER + body + "20:45:52.125 MODE pHelmIvP ACTIVE:G1\n"
    converted = from_alog(ORDERS, text)
    assert check_execution(ORDERS, read_log(converted.ndjson)).path == 17
    assert converted.notes == ("4 alog line(s) are no TIME VAR SOURCE VALUE entry (the "
                               "first: line 10), e.g. the continuation of a multi-line value; "
                               "skipped",)


def test_values_plogger_writes_again_with_their_old_times_are_passed_over() -> None:
    # WildCardLogging: pLogger now and then writes every variable's current value again with
    # the time it was posted; one such batch written after G2 began held G1's MISSION_GOAL and
    # MODE (a CI run read G1, G2, G1, G2, ... from it).
    path = next(p for p in _paths() if p.index == 17)
    lines = alog_run(path.goals, path.outcomes, path.terminal).splitlines()
    second = next(i for i, line in enumerate(lines) if line.endswith("ACTIVE:G2"))
    first = lines[2:second]
    assert any("MISSION_GOAL" in line for line in first)
    again = [*lines[:second + 1], "-1.36191 MISSION_GOAL pHelmIvP G1",
             *first, lines[second], *lines[second + 1:]]
    converted = from_alog(ORDERS, "\n".join(again) + "\n")
    assert check_execution(ORDERS, read_log(converted.ndjson)).path == 17
    assert [json.loads(line)["goal"] for line in converted.ndjson.splitlines()] == \
        list(path.goals)
    assert converted.notes == (f"{len(first) + 2} alog entries repeat a variable's earlier "
                               "value with its old time (pLogger's wildcard logging writes "
                               "them); skipped",)


@pytest.mark.parametrize(("data", "fmt", "words"), [
    (b"\x00\x01garbage", "auto", "none of"),
    (b"\x54\xfe" + b"\x00" * 30, "auto", "no IMC message"),
    (b"12.0 MODE x\n", "alog", "shows no goal"),
    (b"abc MODE pHelmIvP ACTIVE:G1\n", "alog", "line 1"),
    (b"{}", "yaml", "unknown execution format"),
    (b"\xff\xfe{", "ndjson", "not UTF-8"),
])
def test_unreadable_vehicle_logs_are_named(data: bytes, fmt: str, words: str) -> None:
    with pytest.raises(ExecutionInputError, match=words):
        to_execution_log(ORDERS, data, fmt)


def test_the_command_line_reads_plan_control_state(tmp_path: Path,
                                                   capsys: pytest.CaptureFixture[str]) -> None:
    from countersign.cli import main

    path = next(p for p in _paths() if p.outcomes == ("violate", "succeed", "succeed"))
    log = tmp_path / "run.imc"
    log.write_bytes(imc_run(path.goals, path.outcomes, path.terminal))
    # No readings: unverified.
    assert main(["execution", "check", "example:search-and-sample", str(log)]) == 3
    assert capsys.readouterr().out.startswith(f"executed as path {path.index} to COMPLETE")
    alog = tmp_path / "run.alog"
    alog.write_text(alog_run(("G1", "G2"), ("succeed", "succeed"), "COMPLETE"))
    assert main(["execution", "check", "example:search-and-sample", str(alog),
                 "--input-format", "alog"]) == 1
    assert "INCOMPLETE" in capsys.readouterr().out
    log.write_bytes(b"\x54\xfe" + b"\x00" * 10)
    assert main(["execution", "check", "example:search-and-sample", str(log)]) == 2
    assert "no IMC message" in capsys.readouterr().err


def test_messages_across_chunk_boundaries_are_all_read() -> None:
    from countersign.export.execution_input import IMC_CHUNK, _imc_messages

    parts = [_logbook("x" * n, T0 + n) for n in (10, IMC_CHUNK, 3 * IMC_CHUNK + 7, 1, 500)]
    parts += [_state("G1", T0 + i) for i in range(200)]
    data = b"".join(parts)
    assert len(data) > 5 * IMC_CHUNK
    assert sum(1 for _ in _imc_messages(data)) == len(parts)


def test_an_alog_of_nested_helm_modes_reads_as_the_flat_goals_run() -> None:
    """A refined mission's helm reports the innermost mode last (ACTIVE:G1:G1_2_k2:G1_2_1,
    as pHelmIvP 24.8 writes it); the run is the flat goal's, not its refined goal's."""
    written = read_file(str(Path(__file__).with_name("refined_twice.json"))).orders
    flat, graph = checked_form(written)
    helm = helm_modes(flat, graph.nesting)
    counted = paths_of(flat)
    assert counted[1] is not None
    path = next(p for p in iter_paths(*counted) if "G1/G1.2#2/G1.2.2" in p.goals)
    lines, at = ["%% LOGSTART 1796000000.0"], 10.0
    for goal, outcome in zip(path.goals, path.outcomes, strict=True):
        lines.append(f"{at:.3f} MODE pHelmIvP {helm.path[goal]}")
        at += 300
        lines.append(f"{at - 1:.3f} GOAL_OUTCOME pMonitor {outcome}")
    lines.append(f"{at:.3f} MODE pHelmIvP {helm.path[str(path.terminal)]}")
    lines.append(f"{at + 1:.3f} MISSION_RESULT pHelmIvP {path.terminal}")
    assert "ACTIVE:G1:G1_2_k2:G1_2_1" in lines[2 * path.goals.index("G1/G1.2#2/G1.2.1") + 1]
    converted = to_execution_log(written, ("\n".join(lines) + "\n").encode(), "alog")
    runs = [json.loads(line) for line in converted.ndjson.splitlines()]
    assert [(r["goal"], r["outcome"]) for r in runs] == list(zip(path.goals, path.outcomes,
                                                                 strict=True))


@pytest.mark.parametrize("t0", [1e300, -1e300, 4e11, 2.0**64])
def test_vehicle_times_beyond_any_calendar_date_are_refused_by_name(t0: float) -> None:
    data = imc_run(["G1", "G2", "G5"], ["succeed"] * 3, "COMPLETE", t0=t0)
    with pytest.raises(ExecutionInputError, match="is not a date"):
        to_execution_log(ORDERS, data)
