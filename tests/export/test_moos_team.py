"""A team's meeting flown by the real MOOS-IvP 24.8 programs (../shared/tools/moos-ivp): both
members of example:search-and-sample-team exported with --member, each run as its own MOOS
community (pAntler: MOOSDB, uSimMarine, pMarinePID, pHelmIvP, pLogger) on a port of its own.

pShare is not among the tools, so the test is the bridge: it reads each member's arrival
(MEET_R1_ARRIVED) from its alog and, once both arrived, posts MEET_R1_ALL = true and the shared
outcome into both with uPokeDB. What must hold: the member that arrives first keeps its mode at
the meeting, its own outcome posted, while the bridge has not posted (its partner elsewhere),
also long past the meeting goal's ordered duration; both leave once the bridge posts; no
configuration error or BHV_ERROR; each alog read by `countersign execution check --member` as
that member's path.

One flight shows both the wait and the departure: remus-100's meeting goal is ordered to last
ORDERED_S, and it is watched at the meeting, alone, for five times that before its partner is
sent (a second run of remus-100 alone, for the wait only, cost 47 s of the suite's time)."""

from __future__ import annotations

import json
import re
from collections.abc import Iterator
from dataclasses import dataclass, field
from functools import partial
from pathlib import Path

import pytest

from countersign.cli import main
from countersign.export.vehicle import export_vehicle
from countersign.orders.examples import example_bytes
from countersign.orders.model import Orders
from countersign.orders.reader import read_bytes
from countersign.verify.paths import iter_paths, paths_of

from .moos_community import SHARED, Community, running, tools_missing

pytestmark = pytest.mark.skipif(tools_missing() is not None,
                                reason=f"{tools_missing()} ({SHARED} absent)")

TEAM = "example:search-and-sample-team"
CONFIG_ERRORS = re.compile(r"Duplicate behavior name|all_builds_ok: false|MALCONFIG|"
                           r"Unhandled|BHV_ERROR|Unrecognized|[Ff]ailed to", re.M)
# The meeting goal's ordered duration in the flight, and the simulated seconds the first arriver
# is watched holding, its outcome posted, before its partner is even sent to the meeting (the
# bridge posts nothing meanwhile): the goal's behaviour ends at ORDERED_S, so anything that lets
# the member go with it (or a multiple of it) shows within a few durations.
ORDERED_S = 60
ALONE_S = 5.0 * ORDERED_S
# Each vehicle starts this far west of the meeting point: the exemplar's areas are kilometres
# apart, which would take the simulator an hour of simulated time.
START_OFFSET_M = 250.0
# The members' paths as driven: (goal, outcome) then the terminal.
PATHS = {"remus-100": ((("G1", "violate"), ("G4", "succeed"), ("G5", "succeed")), "COMPLETE"),
         "vehicle-2": ((("G1", "succeed"), ("G2", "succeed"), ("G3", "succeed")), "COMPLETE")}


@dataclass
class Flight:
    """What the test saw: each member's alog and mode changes, and the facts of the wait."""

    alogs: dict[str, Path] = field(default_factory=dict)
    modes: dict[str, list[str]] = field(default_factory=dict)
    errors: list[str] = field(default_factory=list)
    # remus-100's modes from entering the meeting until the bridge posted, and vehicle-2's
    # mode and arrivals when remus-100 had held ALONE_S simulated seconds.
    first_modes_before_all: list[str] = field(default_factory=list)
    first_goal_when_alone: str | None = None
    first_outcome_when_alone: str | None = None
    first_results_when_alone: list[str] = field(default_factory=list)
    partner_mode_when_alone: str | None = None
    partner_arrivals_when_alone: int = -1
    results: dict[str, list[str]] = field(default_factory=dict)


def _orders() -> Orders:
    return read_bytes(example_bytes("search-and-sample-team"), "team").orders


def _short_meeting() -> Orders:
    """The team with remus-100's meeting goal ordered to last ORDERED_S seconds."""
    data = _orders().model_dump(mode="json", exclude_unset=True)
    goal = next(g for g in data["team"][0]["orders"]["goals"] if g["id"] == "G4")
    goal["cost"] = {**goal.get("cost", {}), "duration_s": ORDERED_S}
    return Orders.model_validate(data)


def _latest(community: Community, var: str) -> str | None:
    values = community.values(var)
    return values[-1] if values else None


def _is(community: Community, var: str, value: str) -> bool:
    return _latest(community, var) == value


def _more(community: Community, var: str, before: int) -> bool:
    return community.poked(var) > before


def _outcome(community: Community, outcome: str) -> None:
    community.poke("GOAL_OUTCOME", outcome, partial(
        _more, community, "GOAL_OUTCOME", community.poked("GOAL_OUTCOME")))


def _write(vehicle: str, folder: Path, orders: Orders | None = None) -> Path:
    """The member's export, started START_OFFSET_M west of its meeting point."""
    folder.mkdir(parents=True)
    export = export_vehicle(orders or _orders(), "moos", member=vehicle)
    for item in export.files:
        (folder / item.name).write_bytes(item.content)
    bhv = next(folder.glob("*.bhv")).read_text()
    # The meeting's hold (not another goal's station keeping) names the meeting point.
    hold = re.search(r"name = b\d+_\w+_hold\n(?:.*\n)*?.*format=radial, x=(\S+), y=(\S+),", bhv)
    assert hold is not None
    x, y = float(hold.group(1)), float(hold.group(2))
    moos = next(folder.glob("*.moos"))
    text, count = re.subn(r"start_pos = x=0, y=0,",
                          f"start_pos = x={x - START_OFFSET_M:g}, y={y:g},", moos.read_text())
    assert count == 1
    moos.write_text(text)
    return moos


def _since(community: Community, var: str, value: str) -> list[str]:
    """MODE values from the first time `var` read `value` on."""
    entries = community.entries()
    begin = next((i for i, e in enumerate(entries) if e.var == var and e.value == value), None)
    if begin is None:
        return []
    return [e.value for e in entries[begin:] if e.var == "MODE"]


def _fly(root: Path) -> Flight:
    flight = Flight()
    first = _write("remus-100", root / "remus-100", _short_meeting())
    second = _write("vehicle-2", root / "vehicle-2")
    with running(first) as a, running(second) as b:
        members = {"remus-100": a, "vehicle-2": b}
        for community in members.values():
            community.wait_for("the helm's first report", lambda c=community: _latest(
                c, "IVPHELM_STATE") is not None)
            community.poke("DEPLOY", "true", lambda c=community: c.poked("DEPLOY") > 0)
        for community in members.values():
            community.wait_for("mode G1", partial(_is, community, "MODE", "ACTIVE:G1"))
        # remus-100 goes to the meeting (G1 violate -> G4); vehicle-2 stays at its search.
        _outcome(a, "violate")
        a.wait_for("remus-100 at the meeting", partial(_is, a, "MEET_R1_ARRIVED", "remus_100"))
        arrived = next(e.time for e in a.entries() if e.var == "MEET_R1_ARRIVED")
        # Its own monitors say the goal is done; the meeting is not: it must stay.
        _outcome(a, "succeed")
        a.wait_for(f"{ALONE_S:g} simulated seconds at the meeting",
                   lambda: a.entries()[-1].time >= arrived + ALONE_S)
        flight.first_goal_when_alone = _latest(a, "MISSION_GOAL")
        flight.first_outcome_when_alone = _latest(a, "GOAL_OUTCOME")
        flight.first_results_when_alone = a.values("MISSION_RESULT")
        flight.partner_mode_when_alone = _latest(b, "MODE")
        flight.partner_arrivals_when_alone = len(b.values("MEET_R1_ARRIVED"))
        # Now vehicle-2 comes (G1 succeed -> G2); the bridge waits for its arrival.
        _outcome(b, "succeed")
        b.wait_for("vehicle-2 at the meeting", partial(_is, b, "MEET_R1_ARRIVED", "vehicle_2"))
        flight.first_modes_before_all = _since(a, "MODE", "ACTIVE:G4")
        for community in members.values():
            community.poke("MEET_R1_ALL", "true", lambda c=community: c.poked("MEET_R1_ALL") > 0)
        _outcome(b, "succeed")  # the shared outcome; remus-100's is posted already
        a.wait_for("remus-100 leaves for G5", partial(_is, a, "MODE", "ACTIVE:G5"))
        b.wait_for("vehicle-2 leaves for G3", partial(_is, b, "MODE", "ACTIVE:G3"))
        for vehicle, community in members.items():
            _outcome(community, "succeed")
            community.wait_for(f"{vehicle} completes", partial(
                _is, community, "MISSION_RESULT", "complete"))
            output = community.output.read_text(errors="replace")
            flight.errors += [f"{vehicle}: {e}" for e in sorted(set(CONFIG_ERRORS.findall(
                output))) + community.values("BHV_ERROR")]
            modes = [v for v in community.values("MODE") if v.startswith("ACTIVE:")]
            flight.modes[vehicle] = [m for i, m in enumerate(modes)
                                     if i == 0 or modes[i - 1] != m]
            flight.results[vehicle] = community.values("MISSION_RESULT")
            flight.alogs[vehicle] = community.alog
    return flight


@pytest.fixture(scope="module")
def flight(tmp_path_factory: pytest.TempPathFactory) -> Iterator[Flight]:
    yield _fly(tmp_path_factory.mktemp("moos-team"))


def test_the_first_arriver_waits_while_its_partner_has_not_arrived(flight: Flight) -> None:
    # The bridge has posted nothing: remus-100 holds at G4, its own outcome notwithstanding,
    # five times the goal's ordered duration and on until its partner arrives.
    assert flight.first_goal_when_alone == "G4"
    assert flight.first_outcome_when_alone == "succeed"  # posted by its monitors, not acted on
    assert flight.first_results_when_alone == ["none"]
    assert flight.partner_mode_when_alone == "ACTIVE:G1"
    assert flight.partner_arrivals_when_alone == 0
    assert set(flight.first_modes_before_all) == {"ACTIVE:G4"}


def test_both_leave_once_the_bridge_says_all_arrived(flight: Flight) -> None:
    assert flight.errors == []
    assert flight.modes["remus-100"] == ["ACTIVE:G1", "ACTIVE:G4", "ACTIVE:G5",
                                         "ACTIVE:COMPLETE"]
    assert flight.modes["vehicle-2"] == ["ACTIVE:G1", "ACTIVE:G2", "ACTIVE:G3",
                                         "ACTIVE:COMPLETE"]
    assert flight.results == {"remus-100": ["none", "complete"],
                              "vehicle-2": ["none", "complete"]}


@pytest.mark.parametrize("vehicle", sorted(PATHS))
def test_each_alog_is_its_members_path(flight: Flight, vehicle: str,
                                       capsys: pytest.CaptureFixture[str]) -> None:
    own = next(m.orders for m in _orders().team or () if m.vehicle == vehicle)
    steps, terminal = PATHS[vehicle]
    graph, counts = paths_of(own)
    assert counts is not None
    index = next(p.index for p in iter_paths(graph, counts)
                 if tuple(zip(p.goals, p.outcomes, strict=True)) == steps)
    code = main(["execution", "check", TEAM, str(flight.alogs[vehicle]), "--member", vehicle,
                 "--format", "json"])
    captured = capsys.readouterr()
    verdict = json.loads(captured.out)
    assert verdict["terminal"] == terminal and verdict["path"] == index, captured
    # The helm logs no readings of most constraints: followed, but unverified (exit 3).
    assert code == {"no-deviation": 0, "unverified": 3}[verdict["status"]], captured
