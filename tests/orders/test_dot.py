"""Graphviz DOT writer: structure, colours and escaping."""

from __future__ import annotations

import html
import re
import shutil
import subprocess
from typing import Any

import pytest

from countersign.orders.dot import quote, to_dot
from countersign.orders.examples import load_example
from countersign.orders.model import Orders

ODD = 'He said "go" \\ now\nand then\r\nleft \\'


def orders(goals: list[dict[str, Any]], **extra: Any) -> Orders:
    data: dict[str, Any] = {"id": "t", "title": "Test", "start": goals[0]["id"], "goals": goals}
    data.update(extra)
    return Orders.model_validate(data)


def unescaped_quotes(line: str) -> int:
    """Double quotes that delimit DOT strings (a backslash escapes the next character)."""
    count, escaped, inside = 0, False, False
    for ch in line:
        if escaped:
            escaped = False
        elif ch == "\\" and inside:
            escaped = True
        elif ch == '"':
            count += 1
            inside = not inside
    return count


def assert_well_formed(dot: str) -> None:
    lines = dot.splitlines()
    assert lines[0].startswith("digraph ") and lines[0].endswith("{")
    assert lines[-1] == "}"
    assert dot.endswith("}\n")
    for line in lines:
        assert unescaped_quotes(line) % 2 == 0, line
        assert line == line.rstrip()
    for line in lines[1:-1]:
        assert line.endswith(";"), line


@pytest.fixture(scope="module")
def exemplar() -> str:
    return to_dot(load_example("search-and-sample"))


def test_exemplar_graph(exemplar: str) -> None:
    assert_well_formed(exemplar)
    assert exemplar.startswith('digraph "search-and-sample" {\n')
    assert "rankdir=LR" in exemplar
    assert 'label="Search and sample (seed 000 exemplar)"' in exemplar
    assert exemplar == to_dot(load_example("search-and-sample"))


def test_goals_are_rounded_boxes_and_the_start_is_marked(exemplar: str) -> None:
    assert (
        '  "G1" [shape=box, style="rounded,bold", penwidth="2.5", label="G1\\nSearch Area A"];'
        in exemplar.splitlines()
    )
    assert '  "G2" [shape=box, style="rounded", penwidth="1", ' in exemplar
    assert '  "(start)" -> "G1";' in exemplar.splitlines()
    assert '"(start)" [shape=point' in exemplar


def test_terminals_coloured_by_kind(exemplar: str) -> None:
    lines = exemplar.splitlines()
    assert (
        '  "COMPLETE" [shape=doubleoctagon, style="filled", color="forestgreen", '
        'fillcolor="palegreen", label="COMPLETE\\nMission complete"];'
    ) in lines
    assert (
        '  "ABORT" [shape=doubleoctagon, style="filled", color="red", '
        'fillcolor="mistyrose", label="ABORT\\nMission abort"];'
    ) in lines


def test_edges_coloured_and_labelled_by_outcome(exemplar: str) -> None:
    lines = exemplar.splitlines()
    assert '  "G1" -> "G2" [label="s", color="forestgreen", fontcolor="forestgreen"];' in lines
    assert '  "G1" -> "G3" [label="f", color="darkorange", fontcolor="darkorange"];' in lines
    assert '  "G1" -> "G4" [label="c", color="red", fontcolor="red"];' in lines
    assert (
        '  "G5" -> "COMPLETE" [label="s", color="forestgreen", fontcolor="forestgreen"];' in lines
    )
    outcome_edges = [line for line in lines if "->" in line and "(start)" not in line]
    assert len(outcome_edges) == 15  # five goals, three outcomes each


def test_escaping_odd_text() -> None:
    assert quote(ODD) == '"He said \\"go\\" \\\\ now\\nand then\\nleft \\\\"'
    assert quote("bell\x07tab\tend") == '"belltab\tend"'
    o = orders(
        [{"id": "G1", "title": ODD, "next": {"succeed": "COMPLETE"}}],
        title='Mission "X" \\',
        terminals=[{"id": "COMPLETE", "kind": "complete", "title": 'say "done"\\'}],
    )
    dot = to_dot(o)
    assert_well_formed(dot)
    assert 'label="G1\\nHe said \\"go\\" \\\\ now\\nand then\\nleft \\\\"];' in dot
    assert 'label="Mission \\"X\\" \\\\"' in dot
    assert 'label="COMPLETE\\nsay \\"done\\"\\\\"];' in dot
    assert len(dot.splitlines()) == dot.count(";") + 2  # no statement was split or added


def test_unknown_target_gets_a_dashed_red_node() -> None:
    o = orders(
        [
            {"id": "G1", "next": {"succeed": "G9", "fail": "G9", "violate": "ABORT"}},
        ],
        start="G1",
    )
    dot = to_dot(o)
    assert_well_formed(dot)
    lines = dot.splitlines()
    node = '  "?G9" [shape=box, style="dashed", color="red", fontcolor="red", label="? G9"];'
    assert lines.count(node) == 1
    assert '  "G1" -> "?G9" [label="s", color="forestgreen", fontcolor="forestgreen"];' in lines
    assert '  "G1" -> "?G9" [label="f", color="darkorange", fontcolor="darkorange"];' in lines


def test_missing_outcomes_are_absent() -> None:
    o = orders([{"id": "G1", "title": "Alone", "next": {"fail": "ABORT"}}])
    edges = [line for line in to_dot(o).splitlines() if '"G1" ->' in line]
    assert edges == ['  "G1" -> "ABORT" [label="f", color="darkorange", fontcolor="darkorange"];']


def test_several_starts_and_an_unknown_start() -> None:
    goals = [{"id": "G1", "next": {}}, {"id": "G2", "next": {}}]
    dot = to_dot(orders(goals, start=["G1", "G7"]))
    assert_well_formed(dot)
    assert '  "(start)" -> "G1";' in dot and '  "(start)" -> "?G7";' in dot
    assert 'style="rounded,bold"' in dot and dot.count("rounded,bold") == 1
    no_start = to_dot(orders(goals, start=None))
    assert "(start)" not in no_start


def test_harbor_example() -> None:
    dot = to_dot(load_example("harbor-approach-survey"))
    assert_well_formed(dot)
    assert dot.count("shape=box") == 8
    assert sum(1 for line in dot.splitlines() if "-> " in line and "(start)" not in line) == 24
    assert "?" not in dot


@pytest.mark.skipif(shutil.which("dot") is None, reason="Graphviz `dot` is not installed")
def test_graphviz_accepts_the_output() -> None:
    for o in (
        load_example("search-and-sample"),
        orders([{"id": "G1", "title": ODD, "next": {"succeed": "G9"}}], title=ODD),
    ):
        result = subprocess.run(
            ["dot", "-Tsvg"],
            input=to_dot(o).encode(),
            capture_output=True,
            timeout=60,
            check=False,
        )
        assert result.returncode == 0, result.stderr.decode()
        assert b"<svg" in result.stdout
    # The odd title renders as written, one line per line of the title.
    texts = [
        html.unescape(t) for t in re.findall(r"<text[^>]*>(.*?)</text>", result.stdout.decode())
    ]
    assert texts[texts.index("G1") + 1 :][:3] == ['He said "go" \\ now', "and then", "left \\"]
