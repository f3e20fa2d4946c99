"""A team's rehearsal (rehearse/team.py): every member's simulation in one world
clock, meetings joint as verify/team.py defines a joint execution, a deadlock ended in the
TEAM finding's words, every event naming its vehicle, everything bounded."""

from __future__ import annotations

import re

import pytest

from countersign.orders.examples import load_example
from countersign.orders.model import Orders
from countersign.rehearse.geo import contains
from countersign.rehearse.sim import Limits
from countersign.rehearse.team import TeamSimulation, team_fault_specs
from countersign.verify.report import validate

EXEMPLAR = "search-and-sample-team"
# Paths of each member's own orders (`countersign paths`, from 1): remus-100 #1 succeeds at
# every goal; vehicle-2 #1 too, #19 ends Search Area D with a constraint (ABORT, before C);
# remus-100 #28 fails its sample and returns to base, going past the meeting.
ALL_SUCCEED = {"remus-100": 1, "vehicle-2": 1}
V2_ABORTS = {"remus-100": 1, "vehicle-2": 19}
V1_GOES_PAST = {"remus-100": 28, "vehicle-2": 1}


@pytest.fixture(scope="module")
def team() -> Orders:
    return load_example(EXEMPLAR)


def _run(team: Orders, paths: dict[str, int], **kwargs: object) -> TeamSimulation:
    sim = TeamSimulation(team, source="replay", paths=paths, **kwargs)  # type: ignore[arg-type]
    sim.advance(10_000_000)
    assert sim.state == "finished"
    return sim


def _outcome_at(sim: TeamSimulation, vehicle: str, goal: str) -> dict[str, object]:
    found = [e.event for e in sim.events if e.vehicle == vehicle and e.event.kind == "outcome"
             and e.event.goal == goal]
    assert len(found) == 1, (vehicle, goal)
    return found[0].data


def test_both_vehicles_meet_at_c_with_one_outcome_and_go_on(team: Orders) -> None:
    sim = _run(team, ALL_SUCCEED)
    assert [(m.id, m.goals, m.outcome) for m in sim.meetings] == [
        ("R1", {"remus-100": "G4", "vehicle-2": "G2"}, "succeed")]
    # One shared outcome, at one moment of the one clock, both standing in Area C.
    times = set()
    for vehicle, goal in (("remus-100", "G4"), ("vehicle-2", "G2")):
        data = _outcome_at(sim, vehicle, goal)
        assert data["outcome"] == "succeed"
        assert "meeting R1" in str(data["reason"])
        member = sim.member(vehicle)
        position = data["position"]
        assert isinstance(position, list)
        assert contains(member.sim.world.areas["C"].polygon, (position[0], position[1]))
        times.add(next(e.event.t for e in sim.events if e.vehicle == vehicle
                       and e.event.kind == "meeting"))
    assert len(times) == 1
    # The one who came first held (loitered) there until the other arrived.
    holding = [e for e in sim.events if e.event.kind == "holding"]
    assert [e.vehicle for e in holding] == ["vehicle-2"]
    assert holding[0].event.t < min(times)
    # ... and both went on, each to its own successor.
    runs = {m.vehicle: m.sim.runs[0] for m in sim.members}
    assert runs["remus-100"].goals == ["G1", "G2", "G3", "G4", "G5"]
    assert runs["vehicle-2"].goals == ["G1", "G2", "G3"]
    assert sim.joint_end() == "remus-100:COMPLETE + vehicle-2:COMPLETE"
    assert not [e for e in sim.events if e.event.kind == "deadlock"]


def test_vehicle_2_aborting_before_c_ends_vehicle_1s_wait_as_the_team_finding_says(
        team: Orders) -> None:
    sim = _run(team, V2_ABORTS)
    deadlocks = [e for e in sim.events if e.event.kind == "deadlock"]
    assert [(e.vehicle, e.event.goal) for e in deadlocks] == [("remus-100", "G4")]
    # The finding's own words: who waits where, and why the partner can no longer come.
    finding = next(f for f in validate(team).findings
                   if f.code == "TEAM" and f.details.get("waiting") == ["remus-100"])
    why = re.search(r"deadlock: (.*, so it can no longer come)", finding.message)
    assert why is not None, finding.message
    assert why.group(1) in deadlocks[0].event.text
    assert deadlocks[0].event.text.startswith("Meeting R1 deadlocks:")
    # The wait ended (no hang): vehicle 1 is left waiting, as in the joint counts' ends.
    assert sim.member("remus-100").state == "deadlocked"
    assert sim.meetings == []
    assert sim.joint_end() == "remus-100:waiting + vehicle-2:ABORT"
    report = validate(team)
    assert report.team is not None
    assert report.team.joint is not None
    assert sim.joint_end() in report.team.joint.by_key()


def test_a_partner_that_went_past_the_meeting_ends_the_wait(team: Orders) -> None:
    sim = _run(team, V1_GOES_PAST)
    deadlocks = [e for e in sim.events if e.event.kind == "deadlock"]
    assert [e.vehicle for e in deadlocks] == ["vehicle-2"]
    assert "remus-100 has gone past it" in deadlocks[0].event.text
    assert sim.joint_end() == "remus-100:COMPLETE + vehicle-2:waiting"


@pytest.mark.parametrize("paths", [ALL_SUCCEED, V2_ABORTS, V1_GOES_PAST])
def test_every_event_names_its_vehicle(team: Orders, paths: dict[str, int]) -> None:
    sim = _run(team, paths)
    vehicles = set(sim.vehicles)
    assert vehicles == {"remus-100", "vehicle-2"}
    assert sim.events
    for event in sim.events:
        assert event.vehicle in vehicles
        assert event.to_json()["vehicle"] == event.vehicle
    for line in sim.lines():
        assert re.match(r"\[\d+h\d\dm\] (remus-100|vehicle-2)[ :]", line), line
    times = [e["t"] for e in sim.to_json()["events"]]
    assert times == sorted(times)


def test_simulated_team_is_deterministic_and_bounded(team: Orders) -> None:
    one = TeamSimulation(team, seed=3)
    one.advance(10_000_000)
    two = TeamSimulation(team, seed=3)
    two.advance(10_000_000)
    assert one.to_json() == two.to_json()
    assert one.state == "finished"
    # The team clock is bounded: a bound shorter than the mission stops it in words.
    short = TeamSimulation(team, source="replay", paths=ALL_SUCCEED, max_team_s=3_600.0)
    short.advance(10_000_000)
    assert short.state == "finished"
    assert short.time_s <= 3_600.0
    assert any("time bound" in e.event.text for e in short.events)
    # Events are bounded too; the rest are counted.
    few = TeamSimulation(team, source="replay", paths=ALL_SUCCEED,
                         limits=Limits(max_events=10))
    few.advance(10_000_000)
    assert len(few.events) == 10
    assert few.events_dropped > 0


def test_bad_team_options_are_refused_naming_what(team: Orders) -> None:
    with pytest.raises(ValueError, match="simulate or replay"):
        TeamSimulation(team, source="manual")
    with pytest.raises(ValueError, match="vehicle-9"):
        TeamSimulation(team, paths={"vehicle-9": 1})
    with pytest.raises(ValueError, match="between 1 and 19"):
        TeamSimulation(team, source="replay", paths={"vehicle-2": 99})
    with pytest.raises(ValueError, match="one vehicle's"):
        TeamSimulation(load_example("search-and-sample"))
    with pytest.raises(ValueError, match="vehicle 'x'"):
        team_fault_specs(["x:leak"], ["remus-100", "vehicle-2"])
    with pytest.raises(ValueError, match="unknown fault"):
        team_fault_specs(["remus-100:melt"], ["remus-100", "vehicle-2"])
    assert team_fault_specs(["leak@G1", "vehicle-2:gps_loss"], ["remus-100", "vehicle-2"]) == {
        "remus-100": ["leak@G1"], "vehicle-2": ["leak@G1", "gps_loss"]}
