"""Conformance with the NPS AVCL missions (../shared/reference/nps-ethical-control).

Every expectation is computed here from the raw XML by a small independent oracle (the NPS
defaults, a DFS for loops, a BFS for reachability, brute-force path enumeration) and compared
with what the reader and the verifiers report. A few facts read off the files by hand are
pinned as well.
"""

from __future__ import annotations

import xml.etree.ElementTree as ET
from collections import Counter, deque
from dataclasses import dataclass
from pathlib import Path

import pytest

from countersign.orders.findings import Finding
from countersign.orders.reader import ReadResult, read_file
from countersign.verify.graph import build_graph
from countersign.verify.paths import count_paths, iter_paths
from countersign.verify.structure import MAX_LOOPS_REPORTED, check_structure

NPS = Path(__file__).resolve().parents[2].parent / "shared" / "reference" / "nps-ethical-control"
AVCL_DIR = NPS / "missions" / "avcl"
MISSIONS = sorted(AVCL_DIR.glob("*.xml")) if AVCL_DIR.is_dir() else []

pytestmark = pytest.mark.skipif(
    not NPS.is_dir(),
    reason=f"NPS reference folder not found at {NPS}; conformance tests need ../shared",
)

OUTCOMES = ("succeed", "fail", "violate")


@dataclass
class Oracle:
    """The mission as the NPS conventions define it, read with plain xml.etree."""

    start: str
    goals: list[str]  # goals that are not terminal goals, in document order
    terminals: set[str]
    edges: dict[str, dict[str, str]]  # goal -> outcome -> target, after the defaults
    defaults: set[tuple[str, str, str]]  # (goal, outcome, target) filled in by a default
    missing: set[tuple[str, str]]  # (goal, outcome) still missing after the defaults

    def successors(self, goal: str) -> list[str]:
        return [t for t in self.edges[goal].values() if t in self.edges]

    def reachable(self) -> set[str]:
        seen = {self.start}
        queue = deque([self.start])
        while queue:
            for target in self.successors(queue.popleft()):
                if target not in seen:
                    seen.add(target)
                    queue.append(target)
        return seen

    def cycles(self) -> set[tuple[str, ...]]:
        """Every elementary cycle, each as a rotation starting at its first goal in document
        order: a DFS from each goal over goals listed after it."""
        order = {goal: i for i, goal in enumerate(self.goals)}
        found: set[tuple[str, ...]] = set()
        for first in self.goals:
            stack: list[tuple[str, list[str]]] = [(first, [first])]
            while stack:
                node, path = stack.pop()
                for target in set(self.successors(node)):
                    if target == first:
                        found.add(tuple(path))
                    elif order[target] > order[first] and target not in path:
                        stack.append((target, [*path, target]))
        return found

    def on_some_cycle(self) -> set[str]:
        on_cycle = set()
        for goal in self.goals:
            seen: set[str] = set()
            stack = list(self.successors(goal))
            while stack:
                node = stack.pop()
                if node == goal:
                    on_cycle.add(goal)
                    break
                if node not in seen:
                    seen.add(node)
                    stack.extend(self.successors(node))
        return on_cycle

    def paths(self) -> list[tuple[tuple[str, ...], tuple[str, ...], str]]:
        """Brute force: every (goals, outcomes, terminal) in the order succeed, fail, violate."""
        result: list[tuple[tuple[str, ...], tuple[str, ...], str]] = []

        def walk(goal: str, goals: tuple[str, ...], outcomes: tuple[str, ...]) -> None:
            for outcome in OUTCOMES:
                target = self.edges[goal][outcome]
                if target in self.terminals:
                    result.append(((*goals, goal), (*outcomes, outcome), target))
                else:
                    walk(target, (*goals, goal), (*outcomes, outcome))

        walk(self.start, (), ())
        return result


def local(tag: str) -> str:
    return tag.rsplit("}", 1)[-1]


def oracle(path: Path) -> Oracle:
    root = ET.parse(path).getroot()
    goal_list = next(e for e in root.iter() if local(e.tag) == "GoalList")
    raw = [
        (g.get("id", ""), g.get("nextOnSuccess"), g.get("nextOnFailure"), g.get("nextOnException"))
        for g in goal_list
        if local(g.tag) == "Goal"
    ]
    terminals = {gid for gid, s, f, x in raw if s is None and f is None and x is None}
    goals: list[str] = []
    edges: dict[str, dict[str, str]] = {}
    defaults: set[tuple[str, str, str]] = set()
    missing: set[tuple[str, str]] = set()
    for gid, s, f, x in raw:
        if gid in terminals:
            continue
        goals.append(gid)
        fail = f if f is not None else s
        violate = x if x is not None else fail
        if f is None and fail is not None:
            defaults.add((gid, "fail", fail))
        if x is None and violate is not None:
            defaults.add((gid, "violate", violate))
        targets = {"succeed": s, "fail": fail, "violate": violate}
        missing.update((gid, o) for o, t in targets.items() if t is None)
        edges[gid] = {o: t for o, t in targets.items() if t is not None}
    return Oracle(raw[0][0], goals, terminals, edges, defaults, missing)


def canonical(cycle: tuple[str, ...] | list[str], order: dict[str, int]) -> tuple[str, ...]:
    first = min(range(len(cycle)), key=lambda i: order[cycle[i]])
    return tuple(cycle[first:]) + tuple(cycle[:first])


def load(path: Path) -> tuple[ReadResult, list[Finding]]:
    result = read_file(path)
    return result, check_structure(result.orders)


def by_code(findings: list[Finding], code: str) -> list[Finding]:
    return [f for f in findings if f.code == code]


def mission(name: str) -> Path:
    return AVCL_DIR / name


def test_reference_holds_the_ten_avcl_missions() -> None:
    assert len(MISSIONS) == 10


@pytest.mark.parametrize("path", MISSIONS, ids=lambda p: p.stem)
def test_every_mission_loads(path: Path) -> None:
    result = read_file(path)
    expected = oracle(path)
    assert result.orders.start == expected.start
    assert [g.id for g in result.orders.goals] == expected.goals
    assert {t.id for t in result.orders.effective_terminals} == expected.terminals
    for goal in result.orders.goals:
        assert {o: goal.successors(o)[0] for o in OUTCOMES if goal.successors(o)} == (
            expected.edges[goal.id]
        )


@pytest.mark.parametrize("path", MISSIONS, ids=lambda p: p.stem)
def test_sink_warnings_are_exactly_the_defaulted_handlers(path: Path) -> None:
    result, findings = load(path)
    expected = oracle(path)
    assert all(f.code == "SINK" and f.severity == "warning" for f in result.findings)
    reported = [
        (f.subjects[0], f.details["outcome"], f.details["defaulted_to"]) for f in result.findings
    ]
    assert len(reported) == len(set(reported))
    assert set(reported) == expected.defaults
    sink_errors = {(f.subjects[0], f.details["outcome"]) for f in by_code(findings, "SINK")}
    assert sink_errors == expected.missing


@pytest.mark.parametrize("path", MISSIONS, ids=lambda p: p.stem)
def test_unreachable_goals_match_a_breadth_first_search(path: Path) -> None:
    _, findings = load(path)
    expected = oracle(path)
    unreachable = [f.subjects[0] for f in by_code(findings, "G10")]
    assert len(unreachable) == len(set(unreachable))
    assert set(unreachable) == set(expected.goals) - expected.reachable()


@pytest.mark.parametrize("path", MISSIONS, ids=lambda p: p.stem)
def test_loops_match_a_depth_first_search(path: Path) -> None:
    _, findings = load(path)
    expected = oracle(path)
    order = {goal: i for i, goal in enumerate(expected.goals)}
    loops = [f for f in by_code(findings, "G7") if not f.details.get("truncated")]
    reported = [canonical(f.subjects, order) for f in loops]
    assert len(reported) == len(set(reported)), "a loop is reported twice"
    for cycle in reported:
        assert len(set(cycle)) == len(cycle)
        for position, goal in enumerate(cycle):
            following = cycle[(position + 1) % len(cycle)]
            assert following in expected.successors(goal), f"{goal} -> {following} is no edge"
    cycles = expected.cycles()
    if len(cycles) <= MAX_LOOPS_REPORTED:
        assert set(reported) == cycles
    on_loops = {goal for f in by_code(findings, "G7") for goal in f.subjects}
    assert on_loops == expected.on_some_cycle()


@pytest.mark.parametrize("path", MISSIONS, ids=lambda p: p.stem)
def test_path_counts_match_brute_force_enumeration(path: Path) -> None:
    result = read_file(path)
    expected = oracle(path)
    graph = build_graph(result.orders)
    counts = count_paths(graph)
    if expected.reachable() & expected.on_some_cycle():
        assert counts is None
        return
    assert counts is not None
    brute = expected.paths()
    assert counts.total == len(brute)
    by_terminal = Counter(terminal for _, _, terminal in brute)
    assert {t: n for t, n in counts.by_terminal.items() if n} == dict(by_terminal)
    enumerated = [(p.goals, p.outcomes, p.terminal) for p in iter_paths(graph, counts)]
    assert enumerated == brute


def test_loop_free_missions_are_the_expected_ones() -> None:
    counted = {p.stem for p in MISSIONS if count_paths(build_graph(read_file(p).orders))}
    assert counted == {
        "AvclMissionGoalsTemplate",
        "HospitalShipEmDecoy1.Opponent",
        "HospitalShipEmDecoy2.Defender.SenseDecideAct",
        "HospitalShipEmDecoy3.Defender.EthicalControlOODA",
        "SailorOverboard",
        "SailorOverboard3.1",
        "TCE22-2MemsAcousticVectorSensorTesting",
    }


def test_pirates_analysis_finds_its_loops_without_counting_paths() -> None:
    """The largest NPS mission: its cycles are found and its paths not enumerated (the count
    is None). Its speed is bench_incremental's to print, not this test's to time."""
    result = read_file(mission("PiratesSeizingMerchantDefense.xml"))
    findings = check_structure(result.orders)
    counts = count_paths(build_graph(result.orders))
    assert len(result.orders.goals) + len(result.orders.effective_terminals) == 49
    assert by_code(findings, "G7") and counts is None


# Facts read off the files by hand.


def test_coffee_mission_loop_and_unreachable_goals() -> None:
    _, findings = load(mission("CoffeeSearchRetrievalMission.xml"))
    assert [f.subjects for f in by_code(findings, "G7")] == [("Goal3",)]
    assert {f.subjects[0] for f in by_code(findings, "G10")} == {"Goal2.2", "Goal99"}


def test_lifeboat_loop_and_unreachable_low_fuel_group() -> None:
    result, findings = load(mission("LifeboatTracking.xml"))
    assert {f.subjects[0] for f in by_code(findings, "G10")} == {"LBT6.0", "LBT6.1", "LBT6.2"}
    assert ("LBT2.0", "LBT3.0") in {f.subjects for f in by_code(findings, "G7")}
    assert ("LBT4.0", "fail", "LBT4.1") in {
        (f.subjects[0], f.details["outcome"], f.details["defaulted_to"]) for f in result.findings
    }
    kinds = {t.id: t.kind for t in result.orders.effective_terminals}
    assert kinds == {"LBT99.1": "complete", "LBT99.2": "abort", "LBT99.3": "abort"}
    assert result.orders.vehicle == "rescuedrone"


def test_sailor_overboard_paths() -> None:
    result = read_file(mission("SailorOverboard.xml"))
    counts = count_paths(build_graph(result.orders))
    assert counts is not None
    assert counts.total == 29
    assert counts.by_terminal == {"Goal6": 9, "Goal7": 10, "Goal8": 10}
    assert result.findings == []


def test_opponent_mission_defaults_and_terminal() -> None:
    result, findings = load(mission("HospitalShipEmDecoy1.Opponent.xml"))
    assert [t.id for t in result.orders.effective_terminals] == ["HSEMD.Foe.7"]
    assert result.orders.effective_terminals[0].kind == "complete"
    defaulted = [(f.subjects[0], f.details["defaulted_to"]) for f in result.findings]
    assert defaulted == [(f"HSEMD.Foe.{i}", f"HSEMD.Foe.{i + 1}") for i in range(2, 7)]
    assert findings == []
