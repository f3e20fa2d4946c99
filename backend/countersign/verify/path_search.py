"""Paths through a given goal and/or ending at a given terminal, without listing the others.

The review's path list searches by goal and by terminal over missions whose paths are far too
many to filter one by one. Counting the matching continuations of every node (two dynamic
programmes over the DAG: to a matching terminal, and to one through the goal) lets the walk
skip every subtree with no match and jump to any offset among the matches, as `verify.paths`
does for all paths. Each match keeps its index in the full enumeration, so "path #12" is the
same path in every view.
"""

from __future__ import annotations

from collections.abc import Iterator
from dataclasses import dataclass

from ..orders.model import OUTCOMES
from .graph import MissionGraph
from .paths import MissionPath, PathBounds, PathCounts, _path_probability, topological_order


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


@dataclass(frozen=True)
class _Weights:
    # ending[n]: paths from n to a matching terminal; through[n]: those that also pass the goal.
    ending: list[int]
    through: list[int]
    goal: int | None

    def of(self, node: int, passed: bool) -> int:
        return self.ending[node] if passed or self.goal is None else self.through[node]


def _weights(graph: MissionGraph, query: PathQuery) -> _Weights | None:
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
    return _Weights(ending, through, query.goal)


def count_matching(graph: MissionGraph, query: PathQuery) -> int | None:
    """How many paths match, or None when the paths cannot be counted (no start, a loop)."""
    weights = _weights(graph, query)
    if weights is None or graph.start is None:
        return None
    return weights.of(graph.start, graph.start == query.goal)


def iter_matching(
    graph: MissionGraph, counts: PathCounts, query: PathQuery, offset: int = 0,
    limit: int | None = None, probabilities: PathBounds | None = None,
) -> Iterator[MissionPath]:
    """The matching paths from the `offset`-th match on, in the full enumeration's order, each
    with its index in that enumeration."""
    weights = _weights(graph, query)
    if weights is None or graph.start is None or (limit is not None and limit <= 0):
        return
    start = graph.start
    if offset >= weights.of(start, start == query.goal):
        return
    succ = graph.succ
    per_node = counts.per_node
    goal_count = graph.goal_count
    ids = graph.goal_ids
    goals = [start]
    outcomes: list[int] = []
    passed = [start == query.goal]
    next_outcome = [0]
    before = 0  # paths of the full enumeration before the current position
    produced = 0
    while goals:
        depth = len(goals) - 1
        k = next_outcome[depth]
        if k == 3:
            goals.pop()
            passed.pop()
            next_outcome.pop()
            if outcomes:
                outcomes.pop()
            continue
        next_outcome[depth] = k + 1
        target = succ[goals[depth]][k]
        now_passed = passed[depth] or target == query.goal
        size = weights.of(target, now_passed)
        if size == 0 or offset >= size:
            offset -= size
            before += per_node[target]
            continue
        if target >= goal_count:  # a matching terminal, and the offset is reached
            before += 1
            path_outcomes = (*outcomes, k)
            yield MissionPath(
                before, tuple(ids[g] for g in goals), tuple(OUTCOMES[o] for o in path_outcomes),
                graph.node_id(target),
                None if probabilities is None
                else _path_probability(probabilities, goals, path_outcomes),
            )
            produced += 1
            if limit is not None and produced >= limit:
                return
            continue
        outcomes.append(k)
        goals.append(target)
        passed.append(now_passed)
        next_outcome.append(0)
