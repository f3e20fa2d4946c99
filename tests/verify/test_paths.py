from __future__ import annotations

import re
import tracemalloc

from countersign.orders.examples import load_example
from countersign.orders.model import Orders
from countersign.verify.graph import build_graph
from countersign.verify.paths import count_paths, iter_path_lines, iter_paths, trace_text

FIGURE_6_TRACE_1 = """Ethical Mission Execution Trace #1:
?- execute_mission.
Commence: Search Area A.
Did goal Succeed (s), Fail (f), or end with a Constraint (c)? constraint.
Commence: Rendezvous with vehicle 2 in Area C.
Did goal Succeed (s), Fail (f), or end with a Constraint (c)? constraint.
Commence: Return to Base.
Did goal Succeed (s), Fail (f), or end with a Constraint (c)? constraint.
Mission Abort!"""

FIGURE_6_TRACE_2 = """Ethical Mission Execution Trace #2:
?- execute_mission.
Commence: Search Area A.
Did goal Succeed (s), Fail (f), or end with a Constraint (c)? succeed.
Commence: Take environmental sample from Area A.
Did goal Succeed (s), Fail (f), or end with a Constraint (c)? succeed.
Commence: Search Area B.
Did goal Succeed (s), Fail (f), or end with a Constraint (c)? succeed.
Commence: Rendezvous with vehicle 2 in Area C.
Did goal Succeed (s), Fail (f), or end with a Constraint (c)? succeed.
Commence: Return to Base.
Did goal Succeed (s), Fail (f), or end with a Constraint (c)? succeed.
Mission Complete!"""


def _body(trace: str) -> str:
    return trace.split("\n", 1)[1]


def test_exemplar_counts() -> None:
    graph = build_graph(load_example("search-and-sample"))
    counts = count_paths(graph)
    assert counts is not None
    assert counts.total == 75
    assert counts.by_terminal == {"COMPLETE": 25, "ABORT": 50}


def test_exemplar_traces_read_as_figure_6() -> None:
    graph = build_graph(load_example("search-and-sample"))
    counts = count_paths(graph)
    assert counts is not None
    paths = list(iter_paths(graph, counts))
    all_succeed = paths[0]
    all_violate = paths[-1]
    assert all_succeed.outcomes == ("succeed",) * 5
    assert all_violate.outcomes == ("violate",) * 3
    assert _body(trace_text(graph, all_violate)) == _body(FIGURE_6_TRACE_1)
    assert _body(trace_text(graph, all_succeed)) == _body(FIGURE_6_TRACE_2)
    assert trace_text(graph, all_violate).startswith("Ethical Mission Execution Trace #75:\n")


def _wide_dag(goals: int) -> Orders:
    """Each goal's outcomes go to the next two goals and a terminal: paths grow like Fibonacci."""
    items = []
    for i in range(goals):
        a = f"G{i + 1}" if i + 1 < goals else "COMPLETE"
        b = f"G{i + 2}" if i + 2 < goals else "ABORT"
        items.append({"id": f"G{i}", "next": {"succeed": a, "fail": b, "violate": "ABORT"}})
    return Orders.model_validate({"id": "wide", "start": "G0", "goals": items})


def test_huge_counts_are_exact_and_offsets_are_instant() -> None:
    graph = build_graph(_wide_dag(600))
    counts = count_paths(graph)
    assert counts is not None
    assert counts.total > 10**100
    assert counts.total == sum(counts.by_terminal.values())
    # The last path is all violate at once; reach it without enumerating anything else.
    last = list(iter_paths(graph, counts, offset=counts.total - 1))
    assert len(last) == 1 and last[0].outcomes == ("violate",) and last[0].index == counts.total
    middle = next(iter_paths(graph, counts, offset=counts.total // 2, limit=1))
    assert middle.index == counts.total // 2 + 1


def test_enumeration_memory_is_constant() -> None:
    graph = build_graph(_wide_dag(40))
    counts = count_paths(graph)
    assert counts is not None and counts.total > 10**8
    tracemalloc.start()
    lines = iter_path_lines(graph, counts)
    for _ in range(2_000):
        next(lines)
    _, first_peak = tracemalloc.get_traced_memory()
    tracemalloc.reset_peak()
    for _ in range(50_000):
        next(lines)
    _, second_peak = tracemalloc.get_traced_memory()
    tracemalloc.stop()
    assert second_peak < first_peak + 64 * 1024


def test_ndjson_lines_escape_ids() -> None:
    orders = Orders.model_validate({
        "id": "odd", "start": "a.b:c-d",
        "goals": [{"id": "a.b:c-d", "next": {"succeed": "COMPLETE", "fail": "ABORT",
                                              "violate": "ABORT"}}],
    })
    graph = build_graph(orders)
    counts = count_paths(graph)
    assert counts is not None
    lines = list(iter_path_lines(graph, counts))
    assert lines[0] == (
        '{"index":1,"goals":["a.b:c-d"],"outcomes":["succeed"],"terminal":"COMPLETE"}'
    )
    assert all(re.fullmatch(r"\{.*\}", line) for line in lines)
