"""Paths through a goal and/or ending at a terminal (verify.path_search), held against the
plain enumeration filtered one path at a time."""

from __future__ import annotations

import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from countersign.orders.examples import load_example
from countersign.orders.model import Orders
from countersign.verify.graph import build_graph
from countersign.verify.path_search import (
    PathQuery,
    UnknownNode,
    count_matching,
    iter_matching,
    path_query,
)
from countersign.verify.paths import count_paths, iter_paths

from .test_paths_properties import acyclic_orders


def _brute(orders: Orders, goal: str | None, terminal: str | None) -> list[tuple[object, ...]]:
    graph = build_graph(orders)
    counts = count_paths(graph)
    assert counts is not None
    return [(p.index, p.goals, p.outcomes, p.terminal) for p in iter_paths(graph, counts)
            if (goal is None or goal in p.goals) and (terminal is None or p.terminal == terminal)]


def _searched(orders: Orders, goal: str | None, terminal: str | None, offset: int = 0,
              limit: int | None = None) -> list[tuple[object, ...]]:
    graph = build_graph(orders)
    counts = count_paths(graph)
    assert counts is not None
    query = path_query(graph, goal, terminal)
    return [(p.index, p.goals, p.outcomes, p.terminal)
            for p in iter_matching(graph, counts, query, offset, limit)]


def test_the_exemplar_searched_by_each_goal_and_terminal_equals_the_filtered_list() -> None:
    orders = load_example("search-and-sample")
    graph = build_graph(orders)
    for goal in (None, *graph.goal_ids):
        for terminal in (None, *(t.id for t in graph.terminals)):
            expected = _brute(orders, goal, terminal)
            assert _searched(orders, goal, terminal) == expected, (goal, terminal)
            assert count_matching(graph, path_query(graph, goal, terminal)) == len(expected)


@settings(max_examples=150, deadline=None)
@given(orders=acyclic_orders(), data=st.data())
def test_random_graphs_any_offset_and_limit(orders: Orders, data: st.DataObject) -> None:
    graph = build_graph(orders)
    goal = data.draw(st.sampled_from([None, *graph.goal_ids]))
    terminal = data.draw(st.sampled_from([None, *(t.id for t in graph.terminals)]))
    expected = _brute(orders, goal, terminal)
    offset = data.draw(st.integers(min_value=0, max_value=len(expected) + 1))
    limit = data.draw(st.one_of(st.none(), st.integers(min_value=1, max_value=5)))
    end = None if limit is None else offset + limit
    assert _searched(orders, goal, terminal, offset, limit) == expected[offset:end]


def test_no_condition_is_the_plain_enumeration() -> None:
    orders = load_example("search-and-sample")
    graph = build_graph(orders)
    assert count_matching(graph, PathQuery()) == 75
    assert _searched(orders, None, None) == _brute(orders, None, None)


def test_unknown_goal_or_terminal_is_named() -> None:
    graph = build_graph(load_example("search-and-sample"))
    with pytest.raises(UnknownNode, match="no goal 'G99'"):
        path_query(graph, "G99", None)
    with pytest.raises(UnknownNode, match="no terminal 'NOWHERE'"):
        path_query(graph, None, "NOWHERE")
