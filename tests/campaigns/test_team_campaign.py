"""Campaigns of teams: each simulation is the team rehearsal; the results count joint ends as
the verifier names them and hold them against its joint counts.

The oracle: two tiny member DAGs whose goals have fixed outcomes (each member replays the one
path those outcomes make), every interleaving of their moves enumerated; the joint ends the
campaign's simulations reach must be exactly those the enumeration reaches."""

from __future__ import annotations

import os
import subprocess
import sys
from collections import Counter
from pathlib import Path
from typing import Any

import pytest
from hypothesis import example, given, settings
from hypothesis import strategies as st

from countersign.campaigns.spec import MAX_MEMBER_SIMULATIONS, CampaignSpec
from countersign.campaigns.team import TeamMission, simulate_team, sweep_fault_reach
from countersign.campaigns.team_stats import summarize_team
from countersign.cli.campaign import status_text
from countersign.errors import Unprocessable
from countersign.orders.canonical import digest, orders_to_json
from countersign.orders.examples import load_example
from countersign.orders.model import OUTCOMES, Orders
from countersign.orders.reader import orders_from_data
from countersign.store import campaigns as store
from countersign.store.db import Database

EXEMPLAR = "search-and-sample-team"
V2_DRIFTS = "remus-100:waiting + vehicle-2:ABORT"  # nav_drift: vehicle 2 aborts before C


def _team(members: list[tuple[str, dict[str, Any]]]) -> Orders:
    return orders_from_data({"format": "countersign.orders/1", "id": "pair", "title": "pair",
                             "team": [{"vehicle": v, "orders": o} for v, o in members]})


@st.composite
def tiny_teams(draw: st.DrawFn) -> tuple[list[tuple[str, dict[str, Any]]], dict[str, str]]:
    """Two members of one to three goals (a DAG: successors come later), some naming R1 or
    R2, and one fixed outcome per goal; a meeting's outcome is fixed once for all its goals
    (one shared outcome, so each member's replayed path agrees with it)."""
    members = []
    fixed = {meet: draw(st.sampled_from(OUTCOMES)) for meet in ("R1", "R2")}
    for m in range(2):
        ids = [f"G{i}" for i in range(draw(st.integers(min_value=1, max_value=3)))]
        goals = []
        for i, gid in enumerate(ids):
            later = [*ids[i + 1:], "COMPLETE", "ABORT"]
            meet = draw(st.sampled_from([None, "R1", "R1", "R2"]))
            outcome = fixed[meet] if meet else draw(st.sampled_from(OUTCOMES))
            fixed[f"v{m}/{gid}"] = outcome
            goals.append({"id": gid, "behavior": "rendezvous" if meet else "transit",
                          **({"meet": meet} if meet else {}),
                          "next": {o: draw(st.sampled_from(later)) for o in OUTCOMES}})
        members.append((f"v{m}", {"id": f"m{m}", "start": "G0", "goals": goals}))
    # A meeting one member names alone is a TEAM error of the orders, which the verifier
    # passes through and the rehearsal waits at: only meetings both name stay meetings.
    named = [{g.get("meet") for g in o["goals"]} for _, o in members]
    for _, orders in members:
        for goal in orders["goals"]:
            if goal.get("meet") and not all(goal["meet"] in n for n in named):
                del goal["meet"]
                goal["behavior"] = "transit"
    return members, fixed


def _own_path(orders: Orders, vehicle: str, fixed: dict[str, str]) -> tuple[list[str],
                                                                            list[str]]:
    goals = orders.goal_index()
    node: str | None = orders.start
    walked: list[str] = []
    outcomes: list[str] = []
    while node in goals:
        walked.append(node)
        outcomes.append(fixed[f"{vehicle}/{node}"])
        node = goals[node].successors(outcomes[-1])[0]
    return walked, outcomes


def _oracle(team: Orders, fixed: dict[str, str]) -> tuple[set[str], Counter[str], set[str]]:
    """Every interleaving of the members' moves with the fixed outcomes: the joint ends
    reached, the meetings fired on the way and those a member is left waiting at."""
    assert team.team is not None
    members = [(m.vehicle, m.orders.goal_index(), m.orders.start) for m in team.team]
    names: dict[str, list[int]] = {}
    for i, (_, goals, _) in enumerate(members):
        for meet in {g.meet for g in goals.values() if g.meet}:
            names.setdefault(meet, []).append(i)
    ends: set[str] = set()
    fired_at_end: Counter[str] = Counter()
    waits: set[str] = set()

    def walk(position: tuple[str, ...], fired: tuple[str, ...]) -> None:
        moved = False
        for i, (vehicle, goals, _) in enumerate(members):
            goal = goals.get(position[i])
            if goal is None or goal.meet:
                continue
            moved = True
            nxt = goal.successors(fixed[f"{vehicle}/{goal.id}"])[0]
            walk((*position[:i], nxt, *position[i + 1:]), fired)
        for meet, who in names.items():
            if len(who) > 1 and all(members[i][1].get(position[i]) is not None
                                    and members[i][1][position[i]].meet == meet for i in who):
                moved = True
                new = list(position)
                for i in who:
                    new[i] = members[i][1][position[i]].successors(fixed[meet])[0]
                walk(tuple(new), (*fired, meet))
        if not moved:
            ends.add(" + ".join(f"{v}:{'waiting' if position[i] in goals else position[i]}"
                                for i, (v, goals, _) in enumerate(members)))
            fired_at_end.update(set(fired))
            waits.update(str(goals[position[i]].meet) for i, (_, goals, _) in enumerate(members)
                         if position[i] in goals)

    walk(tuple(str(start) for _, _, start in members), ())
    return ends, fired_at_end, waits


_TWICE = {"succeed": "G1", "fail": "G1", "violate": "G1"}
_DONE = {"succeed": "COMPLETE", "fail": "COMPLETE", "violate": "COMPLETE"}


@settings(max_examples=100, deadline=None)
@given(tiny_teams())
@example(([(v, {"id": v, "start": "G0", "goals": [
              {"id": "G0", "behavior": "rendezvous", "meet": "R1", "next": _TWICE},
              {"id": "G1", "behavior": "rendezvous", "meet": "R1", "next": _DONE}]})
           for v in ("v0", "v1")],
          {"R1": "fail", "R2": "succeed", "v0/G0": "fail", "v0/G1": "fail", "v1/G0": "fail",
           "v1/G1": "fail"}))  # one meeting completing twice in a run
@example(([("v0", {"id": "m0", "start": "G0", "goals": [
              {"id": "G0", "behavior": "rendezvous", "meet": "R1",
               "next": {"succeed": "G1", "fail": "G1", "violate": "G1"}},
              {"id": "G1", "behavior": "rendezvous", "meet": "R2",
               "next": {"succeed": "COMPLETE", "fail": "COMPLETE", "violate": "COMPLETE"}}]}),
           ("v1", {"id": "m1", "start": "G0", "goals": [
              {"id": "G0", "behavior": "rendezvous", "meet": "R2",
               "next": {"succeed": "G1", "fail": "G1", "violate": "G1"}},
              {"id": "G1", "behavior": "rendezvous", "meet": "R1",
               "next": {"succeed": "COMPLETE", "fail": "COMPLETE", "violate": "COMPLETE"}}]})],
          {"R1": "succeed", "R2": "succeed", "v0/G0": "succeed", "v0/G1": "succeed",
           "v1/G0": "succeed", "v1/G1": "succeed"}))  # crossed meetings: both wait
def test_joint_ends_equal_every_interleaving_with_fixed_outcomes(
        drawn: tuple[list[tuple[str, dict[str, Any]]], dict[str, str]]) -> None:
    members, fixed = drawn
    team = _team(members)
    mission = TeamMission(team)
    paths = {}
    for member in team.team or ():
        walked, outcomes = _own_path(member.orders, member.vehicle, fixed)
        index = mission.members[member.vehicle].path_index(walked, outcomes)
        assert index is not None
        paths[member.vehicle] = index
    runs = [simulate_team(mission, i, seed, (), paths=paths) for i, seed in enumerate((0, 5))]
    expected_ends, fired, waits = _oracle(team, fixed)
    summary = summarize_team(runs, mission)["team"]
    reached = {row["end"] for row in summary["joint"] if row["count"]}
    assert reached == expected_ends
    assert summary["findings"] == []  # the verifier counts every end the oracle reaches
    assert summary["unfinished"]["count"] == 0
    completed = {m["meet"]: m["completed"]["count"] for m in summary["meetings"]}
    assert {m: n for m, n in completed.items() if n} == {m: 2 for m in fired}
    deadlocked = {m["meet"]: m["deadlocked"]["count"] for m in summary["meetings"]}
    assert {m for m, n in deadlocked.items() if n} == waits


@pytest.fixture(scope="module")
def exemplar() -> TeamMission:
    return TeamMission(load_example(EXEMPLAR))


def test_a_deterministic_fault_that_deadlocks_is_counted_as_that_deadlock(
        exemplar: TeamMission) -> None:
    spec = CampaignSpec.build(simulations=4, faults=["none", "vehicle-2:nav_drift"], seed=2,
                              orders=exemplar.orders)
    runs = [simulate_team(exemplar, i, *spec.simulation(i)) for i in range(spec.simulations)]
    drifted = [r for r in runs if r["faults"]]
    assert len(drifted) == 2
    assert {r["joint_end"] for r in drifted} == {V2_DRIFTS}
    assert all(r["deadlocks"] == [{"meet": "R1", "vehicle": "remus-100"}] for r in drifted)
    summary = summarize_team(runs, exemplar)["team"]
    row = next(r for r in summary["joint"] if r["end"] == V2_DRIFTS)
    assert (row["count"], row["possible"], row["executions"]) == (2, True, 8)
    r1 = summary["meetings"][0]
    assert (r1["meet"], r1["deadlocked"]["count"]) == ("R1", 2)
    assert r1["completed"]["count"] + r1["deadlocked"]["count"] == 4
    members = {m["vehicle"]: m["terminals"] for m in summary["members"]}
    assert members["remus-100"]["waiting"]["count"] == 2
    assert members["vehicle-2"]["ABORT"]["count"] >= 2
    assert summary["coverage"]["possible"] == 7
    assert V2_DRIFTS not in summary["coverage"]["missed"]
    # The same index and seed simulate the same run (a retried job stores the same result).
    assert simulate_team(exemplar, 1, *spec.simulation(1)) == runs[1]
    text = status_text({"id": "c", "state": "finished", "done": 4, "simulations": 4,
                        "results": {"simulations": 4, "team": summary}})
    assert any(line.endswith(V2_DRIFTS) and line.split()[0] == "2"
               for line in text.splitlines())
    assert "Meeting R1 (remus-100, vehicle-2):" in text and "deadlocked 2" in text


def test_a_run_ending_where_the_verifier_says_none_can_is_a_team_finding() -> None:
    always_meet = {"succeed": "COMPLETE", "fail": "COMPLETE", "violate": "COMPLETE"}
    team = _team([(v, {"id": v, "start": "G0", "goals": [
        {"id": "G0", "behavior": "rendezvous", "meet": "R1", "next": always_meet}]})
        for v in ("a", "b")])
    mission = TeamMission(team)
    assert mission.possible == {"a:COMPLETE + b:COMPLETE": 3}
    real = simulate_team(mission, 0, 0, ())
    forged = {**real, "index": 1, "joint_end": "a:waiting + b:COMPLETE"}
    summary = summarize_team([real, forged], mission)["team"]
    [finding] = summary["findings"]
    assert (finding["code"], finding["end"], finding["count"], finding["runs"]) == (
        "TEAM", "a:waiting + b:COMPLETE", 1, [1])
    assert "no joint execution" in finding["message"]
    row = next(r for r in summary["joint"] if r["end"] == "a:waiting + b:COMPLETE")
    assert (row["possible"], row["executions"]) == (False, None)


def test_a_run_a_bound_stopped_has_no_joint_end(exemplar: TeamMission) -> None:
    run = simulate_team(exemplar, 0, 0, ())
    stopped = {**run, "index": 1, "finished": False, "joint_end": "remus-100:waiting + "
               "vehicle-2:waiting"}
    summary = summarize_team([run, stopped], exemplar)["team"]
    assert summary["unfinished"]["count"] == 1
    assert summary["findings"] == []
    assert sum(r["count"] for r in summary["joint"]) == 1


def test_team_specs_are_bounded_and_name_what_is_wrong(exemplar: TeamMission) -> None:
    team = exemplar.orders
    most = MAX_MEMBER_SIMULATIONS // 2
    assert CampaignSpec.build(simulations=most, orders=team).simulations == most
    for bad, words in [({"simulations": most + 1}, "team of 2"),
                       ({"simulations": 2, "faults": ["auv-9:leak"]}, "auv-9"),
                       ({"simulations": 2, "faults": ["vehicle-2:boom"]}, "boom"),
                       ({"simulations": 2, "goals": ["G99"]}, "G99")]:
        with pytest.raises(Unprocessable, match=words):
            CampaignSpec.build(**bad, orders=team)  # type: ignore[arg-type]
    spec = CampaignSpec.build(simulations=3, faults=["vehicle-2:leak", "leak"],
                              goals=["G2", "G5"], orders=team)  # G5: remus-100's only
    assert spec.cells == (("vehicle-2:leak@G2",), ("vehicle-2:leak@G5",), ("leak@G2",),
                          ("leak@G5",))
    # One vehicle's orders name no member.
    with pytest.raises(Unprocessable, match="unknown fault"):
        CampaignSpec.build(simulations=2, faults=["vehicle-2:leak"],
                           orders=load_example("search-and-sample"))


def test_a_fault_reacts_when_it_does_in_a_member_it_is_injected_into(
        exemplar: TeamMission) -> None:
    reach = {r.fault: r for r in sweep_fault_reach(
        exemplar.orders, ["none", "nav_drift", "vehicle-2:nav_drift", "contact_close"])}
    assert set(reach) == {"nav_drift", "vehicle-2:nav_drift", "contact_close"}
    assert reach["vehicle-2:nav_drift"].reacts
    assert "vehicle-2:" in reach["vehicle-2:nav_drift"].because
    assert "remus-100" not in reach["vehicle-2:nav_drift"].because


def test_a_team_jobs_rerun_stores_each_simulation_once_and_seals_the_joint_table(
        tmp_path: Path) -> None:
    """A job retried after its worker was killed (or run twice) skips what was stored; the
    last result seals a record whose results are the team's."""
    from countersign.jobs.tasks import missing_chunks, run_chunk

    database = Database(f"sqlite:///{tmp_path / 'c.db'}")
    database.migrate()
    team = _team([(v, {"id": v, "start": "G0", "goals": [
        {"id": "G0", "behavior": "rendezvous", "meet": "R1",
         "next": {"succeed": "COMPLETE", "fail": "ABORT", "violate": "ABORT"}}]})
        for v in ("a", "b")])
    spec = CampaignSpec.build(simulations=3, chunk=2, faults=["none", "b:leak"], orders=team)
    with database.session() as db:
        row = store.create(db, orders=orders_to_json(team), orders_digest=digest(team),
                           spec=spec.to_json(), simulations=3, owner=None,
                           signer=database.log_signer)
    assert run_chunk(database, row.id, 0, 2) == 2
    assert missing_chunks(database, row.id) == [(2, 3)]
    assert run_chunk(database, row.id, 0, 2) == 0  # the retry stores nothing twice
    assert run_chunk(database, row.id, 2, 3) == 1
    with database.session(write=False) as db:
        sealed = store.get(db, row.id)
        assert sealed.state == "finished"
        results = sealed.record["results"]
    assert results["simulations"] == 3
    assert sum(r["count"] for r in results["team"]["joint"]) == 3
    assert results["team"]["findings"] == []


def test_the_cli_runs_a_team_campaign_and_prints_its_joint_table(tmp_path: Path) -> None:
    env = {**os.environ, "COUNTERSIGN_DATA_DIR": str(tmp_path)}
    env.pop("COUNTERSIGN_DATABASE_URL", None)
    cli = [sys.executable, "-m", "countersign.cli", "campaign", "run", f"example:{EXEMPLAR}"]
    done = subprocess.run([*cli, "-n", "2", "--fault", "vehicle-2:nav_drift"], env=env,
                          capture_output=True, text=True, timeout=1200)
    assert done.returncode == 0, done.stderr
    lines = done.stdout.splitlines()
    assert any(line.split()[:1] == ["2"] and line.endswith(V2_DRIFTS) for line in lines), lines
    assert "Meeting R1 (remus-100, vehicle-2): completed 0, deadlocked 2" in lines
    assert any(line.startswith("Joint ends reached: 1 of 7") for line in lines), lines
    bad = subprocess.run([*cli, "-n", "2", "--fault", "auv-9:leak"], env=env,
                         capture_output=True, text=True, timeout=600)
    assert bad.returncode == 2
    assert "auv-9" in bad.stderr and "Traceback" not in bad.stderr
