"""Path output holds one path at a time: memory linear in the path's length."""

from __future__ import annotations

import json
import tracemalloc

from countersign.verify.paths import iter_path_lines, iter_paths, paths_of, trace_text

from .builders import orders_from


def chain(n: int) -> tuple[object, object]:
    edges = {f"G{i}": (f"G{i + 1}" if i < n else "COMPLETE", "ABORT", "ABORT")
             for i in range(1, n + 1)}
    graph, counts = paths_of(orders_from(edges))
    assert counts is not None
    return graph, counts


def peak_of(run: object) -> tuple[int, object]:
    tracemalloc.start()
    try:
        value = run()  # type: ignore[operator]
        return tracemalloc.get_traced_memory()[1], value
    finally:
        tracemalloc.stop()


def test_first_line_of_a_long_path_takes_memory_linear_in_its_length() -> None:
    graph, counts = chain(4000)
    peak, line = peak_of(lambda: next(iter(iter_path_lines(graph, counts, 0, 1))))  # type: ignore[arg-type]
    assert isinstance(line, str)
    assert len(json.loads(line)["goals"]) == 4000
    # A JSON prefix per depth would hold about n^2/2 characters (~60 MB here).
    assert peak < 30 * len(line)


def test_offset_lines_and_traces_stay_linear() -> None:
    graph, counts = chain(4000)
    offset = counts.total // 2  # type: ignore[attr-defined]
    peak, line = peak_of(lambda: next(iter(iter_path_lines(graph, counts, offset, 1))))  # type: ignore[arg-type]
    assert isinstance(line, str)
    assert json.loads(line)["index"] == offset + 1
    assert peak < 30 * len(line)
    peak, text = peak_of(
        lambda: trace_text(graph, next(iter(iter_paths(graph, counts, 0, 1))))  # type: ignore[arg-type]
    )
    assert isinstance(text, str)
    assert peak < 30 * len(text)


def test_lines_equal_the_paths() -> None:
    graph, counts = chain(30)
    lines = [json.loads(x) for x in iter_path_lines(graph, counts, 5, 20)]  # type: ignore[arg-type]
    paths = [p.to_json() for p in iter_paths(graph, counts, 5, 20)]  # type: ignore[arg-type]
    assert lines == paths
