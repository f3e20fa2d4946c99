"""Paths through a given goal and/or ending at a given terminal, without listing the others.

The review's path list searches by goal and by terminal over missions whose paths are far too
many to filter one by one. Counting the matching continuations of every node (two dynamic
programmes over the DAG: to a matching terminal, and to one through the goal) lets the walk
skip every subtree with no match and jump to any offset among the matches: the walk is
`verify.paths`' own, given these counts in place of the counts of all paths. Each match keeps
its index in the full enumeration, so "path #12" is the same path in every view.
"""

from __future__ import annotations

from collections.abc import Iterator
from dataclasses import dataclass

from .graph import MissionGraph
from .paths import (
    MissionPath,
    PathBounds,
    PathCounts,
    PathMatch,
    iter_walk_paths,
    topological_order,
)


@dataclass(frozen=True)
class PathQuery:
    """Node numbers in the graph (goal, terminal), or None for no condition."""

    goal: int | None = None
    terminal: int | None = None


class UnknownNode(ValueError):
    """A search named a goal or terminal the orders do not have."""


def path_query(graph: MissionGraph, goal: str | None, terminal: str | None) -> PathQuery:
    """The query for goal and terminal ids; UnknownNode names the one the orders lack."""
    goal_node = terminal_node = None
    if goal:
        try:
            goal_node = graph.goal_ids.index(goal)
        except ValueError:
            raise UnknownNode(f"the orders have no goal {goal!r}") from None
    if terminal:
        found = [i for i, t in enumerate(graph.terminals) if t.id == terminal]
        if not found:
            raise UnknownNode(f"the orders have no terminal {terminal!r}")
        terminal_node = graph.goal_count + found[0]
    return PathQuery(goal_node, terminal_node)


def _match(graph: MissionGraph, query: PathQuery) -> PathMatch | None:
    order = topological_order(graph)
    if order is None:
        return None
    goal_count = graph.goal_count
    terminal_count = len(graph.terminals)
    ending = [0] * goal_count + [
        1 if query.terminal in (None, goal_count + j) else 0 for j in range(terminal_count)
    ]
    through = [0] * (goal_count + terminal_count)
    for node in order:  # successors first
        a, b, c = graph.succ[node]
        ending[node] = ending[a] + ending[b] + ending[c]
        through[node] = (ending[node] if node == query.goal
                         else through[a] + through[b] + through[c])
    return PathMatch(ending, through, query.goal)


def count_matching(graph: MissionGraph, query: PathQuery) -> int | None:
    """How many paths match, or None when the paths cannot be counted (no start, a loop)."""
    match = _match(graph, query)
    if match is None or graph.start is None:
        return None
    return match.size(graph.start, graph.start == query.goal)


def iter_matching(
    graph: MissionGraph, counts: PathCounts, query: PathQuery, offset: int = 0,
    limit: int | None = None, probabilities: PathBounds | None = None,
) -> Iterator[MissionPath]:
    """The matching paths from the `offset`-th match on, in the full enumeration's order, each
    with its index in that enumeration."""
    match = _match(graph, query)
    if match is None or graph.start is None:
        return
    if offset >= match.size(graph.start, graph.start == query.goal):
        return
    yield from iter_walk_paths(graph, counts, offset, limit, probabilities, match)
