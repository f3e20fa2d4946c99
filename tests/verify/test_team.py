"""Teams: TEAM on the product of the members' MEAs, joint counts against
brute-force interleavings, the exemplar as a two-vehicle team, and single-vehicle orders left
byte for byte as they were."""

from __future__ import annotations

import copy
import json
from collections import Counter
from pathlib import Path
from typing import Any

import pytest
from hypothesis import example, given, settings
from hypothesis import strategies as st

from countersign.orders.canonical import orders_to_json
from countersign.orders.examples import example_bytes, load_example
from countersign.orders.model import OUTCOMES, Orders
from countersign.orders.reader import OrdersReadError, orders_from_data
from countersign.verify import team as team_module
from countersign.verify.graph import MissionGraph, build_graph
from countersign.verify.report import validate
from countersign.verify.team import TeamMemberGraph, check_team

from .team_outputs import outputs

BASELINE = json.loads((Path(__file__).parent / "data" / "team_baseline.json").read_text())
EXEMPLAR = "search-and-sample-team"


def _team_data() -> dict[str, Any]:
    data: dict[str, Any] = json.loads(example_bytes(EXEMPLAR))
    return data


def _team_findings(data: dict[str, Any]) -> list[Any]:
    report = validate(orders_from_data(data))
    return [f for f in report.findings if f.code == "TEAM"]


@pytest.mark.parametrize("name", sorted(BASELINE))
def test_single_vehicle_outputs_are_byte_identical(name: str) -> None:
    # Captured from main before teams existed (tests/verify/team_outputs.py): digest, canonical
    # bytes, report, every export, paths, traces and the approval statement of every example
    # that existed then (later ones, such as the refined exemplar, have their own tests).
    assert outputs(name) == BASELINE[name]


def test_exemplar_team_names_the_rendezvous_and_a_path_where_vehicle_1_waits() -> None:
    report = validate(load_example(EXEMPLAR))
    assert not report.ok
    team = [f for f in report.findings if f.code == "TEAM"]
    waits_for_2 = [f for f in team if f.details["waiting"] == ["remus-100"]]
    assert len(waits_for_2) == 1
    finding = waits_for_2[0]
    assert finding.severity == "error"
    # Vehicle 2's search of Area D ends with a constraint: it aborts before Area C.
    assert finding.subjects == (
        "R1", "remus-100/G1 violate, vehicle-2/G1 violate -> (remus-100/G4, vehicle-2/ABORT)")
    assert "vehicle-2 has ended at ABORT" in finding.message
    # Every member is validated as alone: the exemplar's own report is clean.
    assert report.team is not None
    assert [m.report.ok for m in report.team.members] == [True, True]
    assert report.team.members[0].report.paths is not None
    assert report.team.members[0].report.paths.total == 75


def test_a_partner_that_always_reaches_area_c_leaves_vehicle_1_waiting_nowhere() -> None:
    data = _team_data()
    v2 = data["team"][1]["orders"]["goals"][0]
    v2["next"] = {"succeed": "G2", "fail": "G2", "violate": "G2"}
    team = _team_findings(data)
    assert not [f for f in team if "remus-100" in f.details["waiting"]]
    # The exemplar's vehicle 1 skips the rendezvous when its sample fails (G2 fail -> G5):
    # vehicle 2 would wait for it. Routed to the rendezvous too, the team is clean.
    assert [f.details["waiting"] for f in team] == [["vehicle-2"]]
    data["team"][0]["orders"]["goals"][1]["next"]["fail"] = "G4"
    report = validate(orders_from_data(data))
    assert report.ok, [f.message for f in report.findings]
    assert report.team is not None and report.team.joint is not None
    assert report.team.joint.deadlocked == 0


def test_member_findings_are_scoped_by_member() -> None:
    data = _team_data()
    data["team"][1]["orders"]["goals"][2]["next"]["succeed"] = "NOWHERE"
    report = validate(orders_from_data(data))
    g3 = [f for f in report.findings if f.code == "G3"]
    assert g3 and g3[0].subjects[0].startswith("vehicle-2/")
    assert g3[0].message.startswith("vehicle-2: ")
    # Paths of vehicle 2 cannot be counted: TEAM says the meetings were not checked.
    assert any(f.code == "TEAM" and f.severity == "warning" for f in report.findings)
    assert report.paths is None


def test_a_meeting_only_one_member_names_is_an_error() -> None:
    data = _team_data()
    data["team"][1]["orders"]["goals"][1]["meet"] = "R2"
    team = _team_findings(data)
    lonely = [f for f in team if "no partner" in f.message]
    assert {f.subjects[0] for f in lonely} == {"R1", "R2"}


def test_crossed_meetings_deadlock_and_disagreeing_successors_are_named() -> None:
    # Vehicle 1 meets R1 then R2; vehicle 2 meets R2 then R1: each waits for the other.
    member = {"start": "A", "terminals": [{"id": "END", "kind": "complete"}]}
    one = {**member, "id": "one", "goals": [
        {"id": "A", "behavior": "rendezvous", "meet": "R1", "next": dict.fromkeys(OUTCOMES, "B")},
        {"id": "B", "behavior": "rendezvous", "meet": "R2",
         "next": dict.fromkeys(OUTCOMES, "END")}]}
    two = {**member, "id": "two", "goals": [
        {"id": "A", "behavior": "rendezvous", "meet": "R2", "next": dict.fromkeys(OUTCOMES, "B")},
        {"id": "B", "behavior": "rendezvous", "meet": "R1",
         "next": dict.fromkeys(OUTCOMES, "END")}]}
    graphs = _graphs([("v1", one), ("v2", two)])
    result = check_team(graphs)
    assert result.counts is not None
    assert result.counts.total == 1 and result.counts.deadlocked == 1
    crossed = [f for f in result.findings if f.code == "TEAM"]
    assert crossed and "waits at A for meeting R2 first" in crossed[0].message
    assert crossed[0].subjects[1] == "start -> (v1/A, v2/A)"
    # After R1 succeed, v1 goes on to R2 but v2 goes home: a disagreement on what follows.
    two = {**member, "id": "two", "goals": [
        {"id": "A", "behavior": "rendezvous", "meet": "R1",
         "next": {"succeed": "END", "fail": "B", "violate": "B"}},
        {"id": "B", "behavior": "rendezvous", "meet": "R2",
         "next": dict.fromkeys(OUTCOMES, "END")}]}
    result = check_team(_graphs([("v1", one), ("v2", two)]))
    (finding,) = [f for f in result.findings if f.details.get("waiting") == ["v1"]]
    assert finding.subjects == ("R2", "R1[v1/A v2/A] succeed -> (v1/B, v2/END)")
    assert "After their shared outcome R1 succeed, v1 goes on to R2 and v2 does not" \
        in finding.message


@pytest.mark.parametrize(("change", "where"), [
    (lambda d: d.__setitem__("goals", [{"id": "G1"}]), "goals"),
    (lambda d: d["team"][1].__setitem__("vehicle", "remus-100"), "team[1].vehicle"),
    (lambda d: d["team"][1].__setitem__("orders", {"id": "inner", "team": copy.deepcopy(
        d["team"])}), "team[1].orders.team"),
    (lambda d: d["team"][1]["orders"].__setitem__("vehicle", "other"), "team[1].orders.vehicle"),
    (lambda d: d.__setitem__("team", d["team"][:1]), "team"),
    (lambda d: d.__setitem__("team", d["team"] * 5), "team"),
])
def test_orders_that_cannot_be_a_team_are_read_errors_naming_where(change: Any,
                                                                   where: str) -> None:
    data = _team_data()
    change(data)
    with pytest.raises(OrdersReadError) as raised:
        orders_from_data(data)
    assert where in str(raised.value)


# The exemplar team has 6 joint positions after the first moves and 10 in all: 3 stops at
# the first moves, 6 in the exploration.
@pytest.mark.parametrize("bound", [3, 6])
def test_a_product_beyond_its_bound_is_a_warning_not_a_hang(
        monkeypatch: pytest.MonkeyPatch, bound: int) -> None:
    monkeypatch.setattr(team_module, "MAX_JOINT_POSITIONS", bound)
    result = check_team(_graphs([(m["vehicle"], m["orders"]) for m in _team_data()["team"]]))
    assert result.counts is None
    assert [f.severity for f in result.findings] == ["warning"]
    assert "not checked" in result.findings[0].message


def test_team_json_report_and_digests() -> None:
    orders = load_example(EXEMPLAR)
    data = validate(orders).to_json()
    assert data["team"]["meetings"] == {"R1": ["remus-100", "vehicle-2"]}
    assert [m["vehicle"] for m in data["team"]["members"]] == ["remus-100", "vehicle-2"]
    joint = data["team"]["joint"]
    assert joint["count"] == data["paths"]["count"] == sum(r["count"] for r in joint["by_ends"])
    # A member's digest is the digest of its orders alone.
    assert orders.team is not None
    alone = orders_from_data(orders_to_json(orders.team[0].orders))
    assert data["team"]["members"][0]["digest"] == validate(alone).digest


# --- joint counts against brute force -------------------------------------------------


def _graphs(members: list[tuple[str, dict[str, Any]]]) -> list[TeamMemberGraph]:
    return [TeamMemberGraph(v, build_graph(Orders.model_validate(o))) for v, o in members]


@st.composite
def small_teams(draw: st.DrawFn) -> list[tuple[str, dict[str, Any]]]:
    size = draw(st.integers(min_value=2, max_value=3))
    most = 3 if size == 2 else 2
    members = []
    for m in range(size):
        n = draw(st.integers(min_value=1, max_value=most))
        ids = [f"G{i}" for i in range(n)]
        goals = []
        for i, gid in enumerate(ids):
            later = [*ids[i + 1:], "COMPLETE", "ABORT"]
            meet = draw(st.sampled_from([None, None, "R1", "R2"]))
            goals.append({"id": gid, "behavior": "rendezvous" if meet else "transit",
                          **({"meet": meet} if meet else {}),
                          "next": {o: draw(st.sampled_from(later)) for o in OUTCOMES}})
        members.append((f"v{m}", {"id": f"m{m}", "start": "G0", "goals": goals}))
    return members


def _brute_force(graphs: list[MissionGraph]) -> tuple[Counter[Any], dict[Any, int]]:
    """Every interleaving, one move at a time; joint executions are the distinct projections
    (what each member did). Returns counts by (ends, waiting) and the shortest deadlock per
    (meeting, waiting member)."""
    meet_of = [{n: g.meet for n, g in enumerate(gr.goals) if g.meet} for gr in graphs]
    members_of: dict[str, list[int]] = {}
    for i, meets in enumerate(meet_of):
        for meet in set(meets.values()):
            members_of.setdefault(meet, []).append(i)
    runs: set[Any] = set()

    def walk(position: tuple[int, ...], done: tuple[tuple[Any, ...], ...]) -> None:
        moved = False
        for i, node in enumerate(position):
            if graphs[i].is_terminal(node) or node in meet_of[i]:
                continue
            for k in range(3):
                moved = True
                walk((*position[:i], graphs[i].succ[node][k], *position[i + 1:]),
                     (*done[:i], (*done[i], (node, k)), *done[i + 1:]))
        for meet, members in members_of.items():
            if all(meet_of[i].get(position[i]) == meet for i in members):
                for k in range(3):
                    moved = True
                    new, did = list(position), list(done)
                    for i in members:
                        new[i] = graphs[i].succ[position[i]][k]
                        did[i] = did[i] + ((position[i], k),)
                    walk(tuple(new), tuple(did))
        if not moved:
            runs.add((done, position))

    walk(tuple(g.start for g in graphs if g.start is not None), tuple(() for _ in graphs))
    counts: Counter[Any] = Counter()
    shortest: dict[Any, int] = {}
    for done, position in runs:
        waiting = tuple(meet_of[i].get(n) for i, n in enumerate(position))
        ends = tuple(None if meet else g.node_id(n)
                     for g, n, meet in zip(graphs, position, waiting, strict=True))
        counts[ends] += 1
        meetings_fired = _meetings_in(done, meet_of)
        length = sum(len(d) for d in done) - meetings_fired
        for i, meet in enumerate(waiting):
            if meet is not None:
                key = (meet, i)
                counts[key] += 1
                shortest[key] = min(shortest.get(key, length), length)
    return counts, shortest


def _meetings_in(done: tuple[tuple[Any, ...], ...], meet_of: list[dict[int, str]]) -> int:
    # A meeting is one joint step but appears in each participant's projection: count each
    # firing once per extra participant (projections of one firing are at the same depth of
    # each member's meeting sequence).
    extra = 0
    sequences = [[n for n, _ in d if n in meet_of[i]] for i, d in enumerate(done)]
    per_meeting: Counter[tuple[str, int]] = Counter()
    for i, sequence in enumerate(sequences):
        seen: Counter[str] = Counter()
        for node in sequence:
            meet = meet_of[i][node]
            per_meeting[(meet, seen[meet])] += 1
            seen[meet] += 1
    for participants in per_meeting.values():
        extra += participants - 1
    return extra


# CI found it: after a three-member meeting, the second member's next goal was read as the
# meeting step when wording the deadlock.
_AFTER_A_THREE_WAY_MEETING = [
    ("v0", {"id": "m0", "start": "G0", "goals": [
        {"id": "G0", "behavior": "rendezvous", "meet": "R1",
         "next": {"succeed": "G1", "fail": "G1", "violate": "G1"}},
        {"id": "G1", "behavior": "transit",
         "next": {"succeed": "COMPLETE", "fail": "COMPLETE", "violate": "COMPLETE"}}]}),
    ("v1", {"id": "m1", "start": "G0", "goals": [
        {"id": "G0", "behavior": "rendezvous", "meet": "R1",
         "next": {"succeed": "COMPLETE", "fail": "COMPLETE", "violate": "COMPLETE"}}]}),
    ("v2", {"id": "m2", "start": "G0", "goals": [
        {"id": "G0", "behavior": "rendezvous", "meet": "R1",
         "next": {"succeed": "G1", "fail": "G1", "violate": "G1"}},
        {"id": "G1", "behavior": "rendezvous", "meet": "R1",
         "next": {"succeed": "COMPLETE", "fail": "COMPLETE", "violate": "COMPLETE"}}]}),
]


@settings(max_examples=150, deadline=None)
@given(small_teams())
@example(_AFTER_A_THREE_WAY_MEETING)
def test_joint_counts_and_shortest_deadlocks_match_brute_force(
        members: list[tuple[str, dict[str, Any]]]) -> None:
    graphs = _graphs(members)
    result = check_team(graphs)
    assert result.counts is not None
    expected, shortest = _brute_force([g.graph for g in graphs])
    vehicles = [v for v, _ in members]
    got = Counter(dict(result.counts.by_ends))
    got.update({(m, vehicles.index(v)): n for m, v, n in result.counts.waiting})
    assert got == expected
    assert result.counts.total == sum(n for key, n in expected.items()
                                      if isinstance(key[1], str | None))
    deadlocks = {(f.details["meeting"], f.details["waiting"][0]): len(f.details["joint_path"])
                 for f in result.findings if "joint_path" in f.details}
    assert {(m, vehicles.index(v)): n for (m, v), n in deadlocks.items()} == shortest


def test_the_offline_verifier_holds_the_signed_member_digests_to_the_orders() -> None:
    from countersign.approvals.team_rules import team_problems
    from countersign.orders.team import member_digests

    orders = load_example(EXEMPLAR)
    data = orders_to_json(orders)
    signed = {"team": member_digests(orders)}
    assert team_problems(data, signed) == []
    other = copy.deepcopy(data)
    other["team"][1]["orders"]["goals"][0]["next"]["violate"] = "G2"
    assert team_problems(other, signed) == [
        f"team member vehicle-2: the signed digest {signed['team']['vehicle-2']} is not that of "
        f"its orders ({member_digests(orders_from_data(other))['vehicle-2']})"]
    assert team_problems(orders_to_json(load_example("search-and-sample")), signed)


def test_budget_and_norms_are_each_vehicles_own() -> None:
    data = _team_data()
    v2 = data["team"][1]["orders"]
    v2["vehicles"][0]["budget"]["energy_wh"] = 300
    v2["norms"] = [{"id": "N1", "context": "coastal", "forbidden": "behavior == 'area_search'",
                    "text": "No searching in coastal waters"}]
    report = validate(orders_from_data(data))
    budget = [f for f in report.findings if f.code == "BUDGET" and f.severity == "error"]
    norms = [f for f in report.findings if f.code == "NORM" and f.severity == "error"]
    # Vehicle 2's 300 Wh is its own bound (remus-100 keeps 1500 Wh and needs 1137).
    assert budget and all(s.startswith("vehicle-2/") for f in budget for s in f.subjects)
    assert norms and all(s.startswith("vehicle-2/") for f in norms for s in f.subjects)
    assert report.team is not None and report.team.members[0].report.ok


def test_deadlock_findings_are_bounded(monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(team_module, "MAX_DEADLOCK_FINDINGS", 1)
    result = check_team(_graphs([(m["vehicle"], m["orders"]) for m in _team_data()["team"]]))
    paths = [f for f in result.findings if "joint_path" in f.details]
    assert len(paths) == 1
    assert "1 more meetings can leave a member waiting" in result.findings[-1].message


def test_a_meeting_is_one_step_of_the_joint_path() -> None:
    # v1 can reach W (meeting R3, which v2 names at a goal it never reaches) either through
    # meetings R1 and R2 (three steps) or by two moves of its own: the shortest is the latter,
    # so a meeting must count as one step.
    one = {"id": "one", "start": "S", "goals": [
        {"id": "S", "behavior": "transit", "next": {"succeed": "A", "fail": "T",
                                                     "violate": "T"}},
        {"id": "T", "behavior": "transit", "next": dict.fromkeys(OUTCOMES, "W")},
        {"id": "A", "behavior": "rendezvous", "meet": "R1", "next": dict.fromkeys(OUTCOMES, "B")},
        {"id": "B", "behavior": "rendezvous", "meet": "R2", "next": dict.fromkeys(OUTCOMES, "W")},
        {"id": "W", "behavior": "rendezvous", "meet": "R3",
         "next": dict.fromkeys(OUTCOMES, "COMPLETE")}]}
    two = {"id": "two", "start": "A2", "goals": [
        {"id": "A2", "behavior": "rendezvous", "meet": "R1",
         "next": dict.fromkeys(OUTCOMES, "B2")},
        {"id": "B2", "behavior": "rendezvous", "meet": "R2",
         "next": dict.fromkeys(OUTCOMES, "W2")},
        {"id": "W2", "behavior": "rendezvous", "meet": "R3",
         "next": {"succeed": "COMPLETE", "fail": "COMPLETE", "violate": "COMPLETE"}}]}
    two["goals"][1]["next"] = dict.fromkeys(OUTCOMES, "COMPLETE")  # v2 never reaches R3
    result = check_team(_graphs([("v1", one), ("v2", two)]))
    (finding,) = [f for f in result.findings
                  if f.details.get("meeting") == "R3" and f.details["waiting"] == ["v1"]]
    assert finding.subjects[1] == "v1/S fail, v1/T succeed -> (v1/W, v2/A2)"


@pytest.mark.parametrize(("name", "bound"), [("MAX_JOINT_MOVES", 1),
                                             ("MAX_LOCAL_ENTRIES", 3)])
def test_moves_and_local_tables_are_bounded_too(monkeypatch: pytest.MonkeyPatch, name: str,
                                                 bound: int) -> None:
    monkeypatch.setattr(team_module, name, bound)
    result = check_team(_graphs([(m["vehicle"], m["orders"]) for m in _team_data()["team"]]))
    assert result.counts is None and result.findings[0].details["undecided"] is True
