"""A refined mission's rehearsal steps inside its refined goals and agrees with the verifier.

Every path of example:search-and-sample-refined (867, through the Figure 3 loop bounded by 6
goals) is rehearsed, and the trace its events make, the refined goal's Commence line, the goals
inside indented under it, `Time-out:` and the refined goal's answer, equals `countersign paths
--format trace` line for line. `--path N` on the command line replays path N; faults and
constraint monitors act on the goals inside; a person decides the goals inside one by one; a
refinement nested in a refinement with a `duration_s` time-out is flown as its flat automaton.
"""

from __future__ import annotations

import json
from typing import Any

import pytest

from countersign.cli import main
from countersign.orders.examples import load_example
from countersign.orders.model import Orders
from countersign.rehearse.sim import Event, Limits, Simulation
from countersign.rehearse.sources import make_source
from countersign.verify.paths import (
    ANSWER,
    INDENT,
    QUESTION,
    MissionPath,
    count_paths,
    iter_paths,
    trace_text,
)
from countersign.verify.refine import checked_form

REFINED = "search-and-sample-refined"
# Paths of the example: the first, a time-out of G1's loop (118), a constraint inside (701),
# the last.
SAMPLE_PATHS = (1, 118, 701, 867)


def event_trace(index: int, events: list[Event], terminal_kind: str | None) -> str:
    """The trace the rehearsal's own events make (DESIGN.md's trace format)."""
    lines = [f"Ethical Mission Execution Trace #{index}:", "?- execute_mission."]
    for event in events:
        if event.kind in ("refined", "goal", "timeout"):
            lines.append(event.text)
        elif event.kind == "outcome":
            depth = int(event.data.get("depth", 0))
            lines.append(f"{INDENT * depth}{QUESTION} {ANSWER[event.data['outcome']]}.")
        elif event.kind == "returned":
            depth = int(event.data["depth"])
            lines.append(f"{INDENT * depth}{QUESTION} {ANSWER[event.data['outcome']]}.")
    lines.append("Mission Complete!" if terminal_kind == "complete" else "Mission Abort!")
    return "\n".join(lines)


def runs_of(events: list[Event]) -> list[list[Event]]:
    """A tour's events, run by run (each run after the first starts with a `run` event)."""
    runs: list[list[Event]] = [[]]
    for event in events:
        if event.kind == "run":
            runs.append([])
        runs[-1].append(event)
    return runs


def all_paths(orders: Orders) -> list[MissionPath]:
    _, graph = checked_form(orders)
    counts = count_paths(graph)
    assert counts is not None
    return list(iter_paths(graph, counts))


def test_every_path_rehearses_as_its_trace() -> None:
    orders = load_example(REFINED)
    _, graph = checked_form(orders)
    paths = all_paths(orders)
    assert len(paths) == 867
    # One tour of every path (the replay source's scripting, run after run); a coarse clock
    # step keeps it quick: the outcomes are the path's whatever the step.
    limits = Limits(step_s=60.0, max_tour_paths=len(paths), max_events=100_000)
    sim = Simulation(orders, source=make_source("tour", orders, max_tour_paths=len(paths)),
                     limits=limits)
    sim.advance(1e12)
    per_run = runs_of(sim.events)
    assert sim.state == "finished" and len(sim.runs) == len(paths)
    timeouts = 0
    for run, path, events in zip(sim.runs, paths, per_run, strict=True):
        assert run.path_index == path.index
        assert (tuple(run.goals), tuple(run.outcomes), run.terminal) == \
            (path.goals, path.outcomes, path.terminal), path.index
        assert event_trace(path.index, events, run.terminal_kind) == trace_text(graph, path)
        timeouts += any(e.kind == "timeout" for e in events)
    assert timeouts > 0  # the loop's time-out ended G1 on some paths


@pytest.mark.parametrize("index", SAMPLE_PATHS)
def test_cli_path_n_replays_path_n(index: int, capsys: pytest.CaptureFixture[str]) -> None:
    path = all_paths(load_example(REFINED))[index - 1]
    code = main(["rehearse", f"example:{REFINED}", "--source", "replay", "--path", str(index),
                 "--headless", "--format", "json"])
    assert code == 0
    record = json.loads(capsys.readouterr().out)["record"]
    assert record["goals"] == list(path.goals) and record["outcomes"] == list(path.outcomes)
    assert record["terminal"] == path.terminal


def test_cli_summary_indents_the_goals_inside(capsys: pytest.CaptureFixture[str]) -> None:
    code = main(["rehearse", f"example:{REFINED}", "--source", "replay", "--path", "118",
                 "--headless"])
    assert code == 0
    text = capsys.readouterr().out
    assert ("  G1: commence.\n    G1/G1.1#1: succeed.\n    G1/G1.2#2: fail.\n"
            in text)
    assert "    G1/G1.2#6: fail.\n    Time-out: G1.\n  G1: fail.\n  G3: succeed.\n" in text


def test_a_fault_at_a_goal_inside_acts_there() -> None:
    orders = load_example(REFINED)
    # A leak when the first scan commences: the mission-wide C2 (safety equipment) is about to
    # break inside G1, so G1.2 ends with a constraint, G1's HALT returns violate, G4 follows.
    sim = Simulation(orders, source=make_source("simulate", orders), faults=["leak@G1/G1.2"])
    sim.advance(1e9)
    run = sim.runs[0]
    assert run.goals[:3] == ["G1/G1.1#1", "G1/G1.2#2", "G4"], run.goals
    assert run.outcomes[1] == "violate"
    leak = next(e for e in sim.events if e.kind == "fault")
    assert leak.goal == "G1/G1.2#2"
    returned = next(e for e in sim.events if e.kind == "returned")
    assert (returned.goal, returned.data["outcome"]) == ("G1", "violate")
    # A fault at the refined goal applies when its first goal commences.
    sim = Simulation(orders, source=make_source("simulate", orders), faults=["leak@G1"])
    sim.advance(1e9)
    assert next(e for e in sim.events if e.kind == "fault").goal == "G1/G1.1#1"


def test_a_person_decides_the_goals_inside_and_sees_the_time_out() -> None:
    orders = load_example(REFINED)
    sim = Simulation(orders, source=make_source("manual", orders))
    asked: list[str] = []
    crumbs: list[list[str]] = []
    for outcome in ("succeed", "fail") * 3:
        sim.advance(1e9)
        assert sim.state == "waiting_for_outcome"
        assert sim.current_goal is not None
        asked.append(sim.current_goal)
        crumbs.append([p["id"] for p in sim.refined_status()["refined"]["inside"]])
        sim.choose(outcome)
    sim.advance(1e9)
    assert asked == ["G1/G1.1#1", "G1/G1.2#2", "G1/G1.1#3", "G1/G1.2#4", "G1/G1.1#5",
                     "G1/G1.2#6"]
    assert crumbs == [["G1"]] * 6
    # Six goals commenced: the seventh may not, G1 ends with its on_timeout (fail) -> G3.
    assert sim.current_goal == "G3"
    refined = sim.refined_status()["refined"]
    assert refined["inside"] == []
    assert refined["timeout"]["goal"] == "G1" and refined["timeout"]["returns"] == "fail"


def test_orders_without_refinements_have_no_refined_status() -> None:
    orders = load_example("search-and-sample")
    sim = Simulation(orders, source=make_source("simulate", orders))
    sim.advance(600)
    assert sim.refined_status() == {} and sim.nesting is None
    assert all("depth" not in e.data for e in sim.events)


def nested_orders() -> Orders:
    """G1 refined into a duration-bounded loop whose first goal is itself refined."""
    def goal(gid: str, nxt: dict[str, str], **extra: Any) -> dict[str, Any]:
        return {"id": gid, "behavior": "loiter", "area": "A", "next": nxt, **extra}

    inner = {"start": "G1.1.1", "goals": [
        goal("G1.1.1", {"succeed": "OK", "fail": "G1.1.2", "violate": "BAD"},
             cost={"energy_wh": 5, "duration_s": 100}),
        goal("G1.1.2", {"succeed": "OK", "fail": "NO", "violate": "BAD"},
             cost={"energy_wh": 5, "duration_s": 100})],
        "terminals": [{"id": "OK", "kind": "complete", "returns": "succeed"},
                      {"id": "NO", "kind": "abort", "returns": "fail"},
                      {"id": "BAD", "kind": "abort", "returns": "violate"}]}
    outer = {"start": "G1.1", "goals": [
        goal("G1.1", {"succeed": "G1.2", "fail": "G1.2", "violate": "HALT"}, refines=inner),
        goal("G1.2", {"succeed": "DONE", "fail": "G1.2", "violate": "HALT"},
             cost={"energy_wh": 5, "duration_s": 150})],
        "terminals": [{"id": "DONE", "kind": "complete", "returns": "succeed"},
                      {"id": "HALT", "kind": "abort", "returns": "violate"}],
        "within": {"steps": 4}, "on_timeout": "fail"}
    return Orders.model_validate({
        "id": "nested", "vehicle": "auv", "start": "G1",
        "vehicles": [{"id": "auv", "speed_mps": 1.5, "power_w": 100,
                      "budget": {"energy_wh": 100000, "duration_s": 10000000}}],
        "areas": [{"id": "A", "polygon": [[36.7, -121.9], [36.7, -121.89], [36.69, -121.89],
                                         [36.69, -121.9]]}],
        "goals": [goal("G1", {"succeed": "G2", "fail": "G2", "violate": "ABORT"},
                       refines=outer),
                  goal("G2", {"succeed": "DONE", "fail": "ABORT", "violate": "ABORT"},
                       cost={"energy_wh": 5, "duration_s": 60})],
        "terminals": [{"id": "DONE", "kind": "complete"}, {"id": "ABORT", "kind": "abort"}]})


def test_refinements_nested_two_deep_rehearse_as_their_traces() -> None:
    orders = nested_orders()
    _, graph = checked_form(orders)
    paths = all_paths(orders)
    limits = Limits(step_s=10.0, max_tour_paths=len(paths), max_events=100_000)
    sim = Simulation(orders, source=make_source("tour", orders, max_tour_paths=len(paths)),
                     limits=limits)
    sim.advance(1e12)
    per_run = runs_of(sim.events)
    assert len(sim.runs) == len(paths) > 10
    deep = 0
    for run, path, events in zip(sim.runs, paths, per_run, strict=True):
        assert tuple(run.goals) == path.goals and tuple(run.outcomes) == path.outcomes
        assert event_trace(path.index, events, run.terminal_kind) == trace_text(graph, path)
        deep += any(e.kind == "refined" and e.data["depth"] == 1 for e in events)
    assert deep > 0
