"""The mission as a compact automaton (seed 000, Table 1): integer nodes, three outcome edges.

Goals are nodes 0..n-1 in the order of the orders; terminals follow as n..n+t-1. Every check
that walks the graph works on this form so that 10,000-goal orders stay fast.
"""

from __future__ import annotations

from collections import deque
from dataclasses import dataclass
from functools import cached_property

from ..orders.model import OUTCOMES, Goal, Orders, Terminal
from .nesting import Nesting

MISSING = -1  # the goal names no successor for this outcome (SINK)
UNKNOWN = -2  # the goal names something that is neither a goal nor a terminal (G3)


@dataclass(frozen=True)
class MissionGraph:
    goal_ids: tuple[str, ...]
    goals: tuple[Goal, ...]
    terminals: tuple[Terminal, ...]
    # succ[node][k]: node for outcome OUTCOMES[k], or MISSING / UNKNOWN.
    succ: tuple[tuple[int, int, int], ...]
    # Every target named per outcome, for the rare G5 case of several (Turtle/AVCL input).
    extra_targets: dict[int, tuple[int, ...]]
    start: int | None
    # The hierarchy of a refined mission's flat graph (verify.refine), for traces and runs.
    nesting: Nesting | None = None

    @property
    def goal_count(self) -> int:
        return len(self.goal_ids)

    def is_terminal(self, node: int) -> bool:
        return node >= len(self.goal_ids)

    def terminal(self, node: int) -> Terminal:
        return self.terminals[node - len(self.goal_ids)]

    def node_id(self, node: int) -> str:
        if self.is_terminal(node):
            return self.terminal(node).id
        return self.goal_ids[node]

    def out_nodes(self, node: int) -> list[int]:
        """Successor nodes of a goal over all outcomes, including extra G5 targets."""
        targets = [t for t in self.succ[node] if t >= 0]
        targets.extend(self.extra_targets.get(node, ()))
        return targets

    @cached_property
    def reachable(self) -> list[bool]:
        """Which goals the start reaches (all False without a valid start)."""
        seen = [False] * self.goal_count
        if self.start is None:
            return seen
        seen[self.start] = True
        queue = deque([self.start])
        while queue:
            node = queue.popleft()
            for target in self.out_nodes(node):
                if target < self.goal_count and not seen[target]:
                    seen[target] = True
                    queue.append(target)
        return seen

    @cached_property
    def shortest_outcomes(self) -> dict[int, tuple[int, int]]:
        """Breadth-first parents from the start: node -> (parent goal, outcome index)."""
        parents: dict[int, tuple[int, int]] = {}
        if self.start is None:
            return parents
        queue = deque([self.start])
        visited = {self.start}
        while queue:
            node = queue.popleft()
            for k, target in enumerate(self.succ[node]):
                if target >= 0 and target not in visited:
                    visited.add(target)
                    parents[target] = (node, k)
                    if target < self.goal_count:
                        queue.append(target)
        return parents

    def outcomes_to(self, node: int) -> list[str] | None:
        """The shortest outcome sequence from the start that reaches a node, if any does."""
        if self.start is None:
            return None
        if node == self.start:
            return []
        parents = self.shortest_outcomes
        if node not in parents:
            return None
        sequence: list[str] = []
        while node != self.start:
            node, k = parents[node]
            sequence.append(OUTCOMES[k])
        sequence.reverse()
        return sequence


def build_graph(orders: Orders) -> MissionGraph:
    goal_index = orders.goal_index()
    goal_ids = tuple(goal_index)
    goals = tuple(goal_index.values())
    terminals = tuple(
        t for t in orders.terminal_index().values() if t.id not in goal_index
    )
    node_of: dict[str, int] = {gid: i for i, gid in enumerate(goal_ids)}
    for offset, terminal in enumerate(terminals):
        node_of[terminal.id] = len(goal_ids) + offset

    succ: list[tuple[int, int, int]] = []
    extra: dict[int, tuple[int, ...]] = {}
    for node, goal in enumerate(goals):
        row: list[int] = []
        others: list[int] = []
        for outcome in OUTCOMES:
            targets = goal.successors(outcome)
            if not targets:
                row.append(MISSING)
                continue
            row.append(node_of.get(targets[0], UNKNOWN))
            others.extend(node_of[t] for t in targets[1:] if t in node_of)
        succ.append((row[0], row[1], row[2]))
        if others:
            extra[node] = tuple(others)

    start: int | None = None
    if isinstance(orders.start, str) and orders.start in goal_index:
        start = node_of[orders.start]
    return MissionGraph(goal_ids, goals, terminals, tuple(succ), extra, start)
