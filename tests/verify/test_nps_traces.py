"""The built-in exemplar against the NPS Allegro Lisp run of the paper mission.

`traces/ExhaustiveTestingAndExecution.output.txt` prints every outcome sequence that reaches
the final goal (PHASE5, our G5) twice: as `(results)` with phases and outcome words, and as
`*abbreviated-algorithmic-paths*` with the letters S, F, X (succeed, fail, violate).
"""

from __future__ import annotations

import re
from collections import Counter
from pathlib import Path

import pytest

from countersign.orders.examples import load_example
from countersign.verify.graph import build_graph
from countersign.verify.paths import count_paths, iter_paths

NPS = Path(__file__).resolve().parents[2].parent / "shared" / "reference" / "nps-ethical-control"
TRACE = NPS / "traces" / "ExhaustiveTestingAndExecution.output.txt"

pytestmark = pytest.mark.skipif(
    not NPS.is_dir(),
    reason=f"NPS reference folder not found at {NPS}; conformance tests need ../shared",
)

LETTER = {"S": "succeed", "F": "fail", "X": "violate"}
WORD = {"Success": "succeed", "Failure": "fail", "Exception": "violate"}


def section(command: str) -> str:
    """What the Lisp listener printed after a command, up to the next prompt."""
    text = TRACE.read_text(encoding="utf-8")
    start = text.index(command) + len(command)
    end = text.index("CG-USER(", start)
    return text[start:end]


def abbreviated_paths() -> list[tuple[str, ...]]:
    printed = section("(pprint *abbreviated-algorithmic-paths*)")
    return [
        tuple(LETTER[letter] for letter in group.split())
        for group in re.findall(r"\(([SFX](?: [SFX])*)\)", printed)
    ]


def full_results() -> list[tuple[tuple[str, ...], tuple[str, ...]]]:
    """(phases, outcomes) of each `(results)` entry, e.g. ((PHASE1, PHASE4), (violate, ...))."""
    printed = section("CG-USER(5): (results)")
    entries = []
    for entry in re.findall(r"\(PHASE1 .*?PHASE5\)", printed, flags=re.DOTALL):
        phases = tuple(re.findall(r"PHASE(\d)", entry))
        outcomes = tuple(WORD[w] for w in re.findall(r'"(Success|Failure|Exception)\."', entry))
        entries.append((phases, outcomes))
    return entries


def example_paths_to_g5() -> list[tuple[tuple[str, ...], tuple[str, ...]]]:
    """(goals, outcomes) before G5 of every path of the built-in example, in order."""
    graph = build_graph(load_example("search-and-sample"))
    counts = count_paths(graph)
    assert counts is not None
    prefixes = []
    for path in iter_paths(graph, counts):
        at = path.goals.index("G5")
        prefixes.append((path.goals[:at], path.outcomes[:at]))
    return prefixes


def test_trace_lists_25_distinct_sequences() -> None:
    sequences = abbreviated_paths()
    assert len(sequences) == 25
    assert len(set(sequences)) == 25


def test_example_reaches_g5_by_exactly_the_traced_sequences() -> None:
    prefixes = example_paths_to_g5()
    outcome_sequences = Counter(outcomes for _, outcomes in prefixes)
    # Each sequence reaching G5 is followed by G5's three outcomes.
    assert set(outcome_sequences.values()) == {3}
    assert set(outcome_sequences) == set(abbreviated_paths())


def test_example_visits_the_traced_phases() -> None:
    results = full_results()
    assert len(results) == 25
    assert {outcomes for _, outcomes in results} == set(abbreviated_paths())
    ours = {
        (tuple(goal.removeprefix("G") for goal in goals), outcomes)
        for goals, outcomes in example_paths_to_g5()
    }
    assert {(phases[:-1], outcomes) for phases, outcomes in results} == ours


def test_example_has_75_paths() -> None:
    graph = build_graph(load_example("search-and-sample"))
    counts = count_paths(graph)
    assert counts is not None
    assert counts.total == 75
    assert counts.by_terminal == {"COMPLETE": 25, "ABORT": 50}
    assert sum(1 for _ in iter_paths(graph, counts)) == 75
