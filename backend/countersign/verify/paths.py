"""Exhaustive traversal (seed 000 III.B, Figure 6): exact path counts by dynamic programming
over the DAG, and lazy depth-first enumeration in the order succeed, fail, violate.

A path is one outcome sequence from the start goal to a terminal. Counts are Python ints, so
a 10,000-goal mission with more than 10^100 paths is counted exactly; enumeration never holds
more than one path in memory and skips to any offset using the counts.
"""

from __future__ import annotations

import json
from collections.abc import Iterator, Sequence
from dataclasses import dataclass

from ..orders.model import OUTCOMES, Orders
from .graph import MissionGraph, build_graph
from .nesting import Nesting

ANSWER = {"succeed": "succeed", "fail": "fail", "violate": "constraint"}


@dataclass(frozen=True)
class PathCounts:
    total: int
    by_terminal: dict[str, int]
    # Paths from each node to any terminal; index by node (goals, then terminals).
    per_node: tuple[int, ...]

    def to_json(self) -> dict[str, object]:
        return {"count": self.total, "by_terminal": dict(self.by_terminal)}


@dataclass(frozen=True)
class MissionPath:
    index: int  # 1-based position in the enumeration order
    goals: tuple[str, ...]
    outcomes: tuple[str, ...]
    terminal: str
    # The path's probability (a number, or [min, max] where goals give intervals or nothing).
    probability: float | tuple[float, float] | None = None

    def to_json(self) -> dict[str, object]:
        data: dict[str, object] = {
            "index": self.index,
            "goals": list(self.goals),
            "outcomes": list(self.outcomes),
            "terminal": self.terminal,
        }
        if self.probability is not None:
            data["probability"] = (list(self.probability)
                                   if isinstance(self.probability, tuple) else self.probability)
        return data


# Per goal node, (lo, hi) per outcome (verify.probability.path_probability_bounds).
PathBounds = Sequence[Sequence[tuple[float, float]]]


def _path_probability(
    bounds: PathBounds, goals: Sequence[int], outcomes: Sequence[int],
) -> float | tuple[float, float]:
    low = high = 1.0
    for g, k in zip(goals, outcomes, strict=True):
        lo, hi = bounds[g][k]
        low *= lo
        high *= hi
    return low if low == high else (low, high)


def topological_order(graph: MissionGraph) -> list[int] | None:
    """Goals reachable from the start in reverse topological order (successors first), or
    None when counting is impossible: no start, or a loop, dangling target or missing successor
    reachable from the start."""
    if graph.start is None:
        return None
    goal_count = graph.goal_count
    succ = graph.succ
    state = bytearray(goal_count)  # 0 new, 1 on the stack, 2 done
    order: list[int] = []
    stack: list[tuple[int, int]] = [(graph.start, 0)]
    state[graph.start] = 1
    while stack:
        node, k = stack[-1]
        if k == 3:
            stack.pop()
            state[node] = 2
            order.append(node)
            continue
        stack[-1] = (node, k + 1)
        target = succ[node][k]
        if target < 0:
            return None
        if target >= goal_count or state[target] == 2:
            continue
        if state[target] == 1:
            return None
        state[target] = 1
        stack.append((target, 0))
    return order


def count_paths(graph: MissionGraph) -> PathCounts | None:
    order = topological_order(graph)
    if order is None or graph.start is None:
        return None
    goal_count = graph.goal_count
    terminal_count = len(graph.terminals)
    totals = [0] * goal_count + [1] * terminal_count
    # Per-terminal vectors only where needed: most missions have two terminals.
    vectors: list[list[int] | None] = [None] * goal_count
    vectors.extend(
        [1 if j == t else 0 for j in range(terminal_count)] for t in range(terminal_count)
    )
    succ = graph.succ
    for node in order:
        a, b, c = succ[node]
        totals[node] = totals[a] + totals[b] + totals[c]
        va, vb, vc = vectors[a], vectors[b], vectors[c]
        assert va is not None and vb is not None and vc is not None
        vectors[node] = [x + y + z for x, y, z in zip(va, vb, vc, strict=True)]
    start_vector = vectors[graph.start]
    assert start_vector is not None
    by_terminal = {t.id: start_vector[j] for j, t in enumerate(graph.terminals)}
    return PathCounts(totals[graph.start], by_terminal, tuple(totals))


@dataclass(frozen=True)
class PathMatch:
    """Path counts for a search (verify.path_search): ending[n] is the number of paths from
    node n to a matching terminal, through[n] those of them that also pass `goal`."""

    ending: Sequence[int]
    through: Sequence[int]
    goal: int | None

    def size(self, node: int, passed: bool) -> int:
        return self.ending[node] if passed or self.goal is None else self.through[node]


def _walk(
    graph: MissionGraph, counts: PathCounts, offset: int, match: PathMatch | None = None,
) -> Iterator[tuple[list[int], list[int], int, int, int]]:
    """Depth-first over every path from the `offset`-th on (of the matching ones, with a
    `match`), yielding live (goals, outcomes, terminal, changed, index) where `changed` is the
    first position that differs from the previous path and `index` the path's 1-based place in
    the full enumeration. Subtrees with no path left to skip or to match are jumped over by
    their counts. The lists change after each step: copy what must outlive the iteration."""
    assert graph.start is not None
    succ = graph.succ
    per_node = counts.per_node
    goal_count = graph.goal_count
    goals: list[int] = [graph.start]
    outcomes: list[int] = []
    next_outcome: list[int] = [0]
    # Only a search by goal needs to know whether the path so far passed it.
    goal = None if match is None else match.goal
    passed: list[bool] = [graph.start == goal]
    before = 0  # paths of the full enumeration before the current position
    changed = 0
    while goals:
        depth = len(goals) - 1
        k = next_outcome[depth]
        if k == 3:
            goals.pop()
            next_outcome.pop()
            if goal is not None:
                passed.pop()
            if outcomes:
                outcomes.pop()
            continue
        next_outcome[depth] = k + 1
        target = succ[goals[depth]][k]
        if match is None:
            size = per_node[target]
        else:
            now_passed = goal is not None and (passed[depth] or target == goal)
            size = match.size(target, now_passed)
        if offset >= size:  # before the offset, or no match below
            offset -= size
            before += per_node[target]
            continue
        outcomes.append(k)
        if depth < changed:
            changed = depth
        if target >= goal_count:
            before += 1
            yield goals, outcomes, target, changed, before
            outcomes.pop()
            changed = depth + 1
        else:
            goals.append(target)
            next_outcome.append(0)
            if goal is not None:
                passed.append(now_passed)


def iter_walk_paths(
    graph: MissionGraph, counts: PathCounts, offset: int, limit: int | None,
    probabilities: PathBounds | None, match: PathMatch | None = None,
) -> Iterator[MissionPath]:
    """The walk's paths as MissionPath, at most `limit` of them (verify.path_search shares
    this with iter_paths)."""
    if limit is not None and limit <= 0:
        return
    ids = graph.goal_ids
    walk = _walk(graph, counts, offset, match)
    for produced, (goals, outcomes, terminal, _, index) in enumerate(walk, 1):
        yield MissionPath(
            index,
            tuple(ids[g] for g in goals),
            tuple(OUTCOMES[k] for k in outcomes),
            graph.node_id(terminal),
            None if probabilities is None else _path_probability(probabilities, goals, outcomes),
        )
        if limit is not None and produced >= limit:
            return


def iter_paths(
    graph: MissionGraph, counts: PathCounts, offset: int = 0, limit: int | None = None,
    probabilities: PathBounds | None = None,
) -> Iterator[MissionPath]:
    """Paths in the order of Figure 6's exhaustive testing (succeed, fail, violate first)."""
    if offset >= counts.total:
        return
    yield from iter_walk_paths(graph, counts, offset, limit, probabilities)


def iter_path_lines(
    graph: MissionGraph, counts: PathCounts, offset: int = 0, limit: int | None = None,
    probabilities: PathBounds | None = None,
) -> Iterator[str]:
    """The same paths as NDJSON lines (without newline), built with as little work per path as
    possible so that streaming millions of paths stays fast."""
    if offset >= counts.total or (limit is not None and limit <= 0):
        return
    encoded = [json.dumps(i) for i in graph.goal_ids]
    encoded += [json.dumps(t.id) for t in graph.terminals]
    words = ['"succeed"', '"fail"', '"violate"']
    stop = counts.total if limit is None else min(counts.total, offset + limit)
    # One encoded piece per position, kept in step with the walk and joined per line: memory
    # stays linear in the path's length (a JSON prefix per depth would be quadratic).
    goal_json: list[str] = []
    outcome_json: list[str] = []
    for goals, outcomes, terminal, changed, index in _walk(graph, counts, offset):
        del goal_json[changed:], outcome_json[changed:]
        goal_json.extend(encoded[g] for g in goals[changed:])
        outcome_json.extend(words[k] for k in outcomes[changed:])
        tail = ""
        if probabilities is not None:
            tail = ',"probability":' + json.dumps(
                _path_probability(probabilities, goals, outcomes))
        yield (
            f'{{"index":{index},"goals":[{",".join(goal_json)}],'
            f'"outcomes":[{",".join(outcome_json)}],"terminal":{encoded[terminal]}{tail}}}'
        )
        if index >= stop:
            return


def trace_text(orders_graph: MissionGraph, path: MissionPath) -> str:
    """The path as an ethical mission execution trace, exactly as seed 000 Figure 6 prints it."""
    labels = _labels(orders_graph)
    lines = [f"Ethical Mission Execution Trace #{path.index}:", "?- execute_mission."]
    nesting = orders_graph.nesting
    if nesting is None:
        for goal_id, outcome in zip(path.goals, path.outcomes, strict=True):
            lines.append(commence_line(labels[goal_id]))
            lines.append(f"{QUESTION} {ANSWER[outcome]}.")
    else:
        inside: list[str] = []
        for goal_id, outcome in zip(path.goals, path.outcomes, strict=True):
            lines.extend(nested_commence(nesting, inside, goal_id, labels[goal_id]))
            lines.extend(nested_answer(nesting, inside, goal_id, outcome))
    terminal = next(t for t in orders_graph.terminals if t.id == path.terminal)
    lines.append(END_LINE[terminal.kind])
    return "\n".join(lines)


def _labels(orders_graph: MissionGraph) -> dict[str, str]:
    # Cached on the graph so a page of traces costs its paths' length, not the mission's size
    # again for every path.
    cached: dict[str, str] | None = getattr(orders_graph, "_trace_labels", None)
    if cached is None:
        cached = {g.id: g.label for g in orders_graph.goals}
        object.__setattr__(orders_graph, "_trace_labels", cached)
    return cached


QUESTION = "Did goal Succeed (s), Fail (f), or end with a Constraint (c)?"
END_LINE = {"complete": "Mission Complete!", "abort": "Mission Abort!"}


def commence_line(label: str) -> str:
    return f"Commence: {label.rstrip('.')}."


INDENT = "  "  # per level of refinement


def nested_commence(nesting: Nesting, inside: list[str], goal_id: str, label: str
                    ) -> list[str]:
    """The Commence lines of a flat goal of a refined mission: first those of the refined
    goals it runs inside that have not begun yet, each indented by its depth. `inside` holds
    the refined goals begun and not ended; it is updated."""
    lines: list[str] = []
    chain = nesting.parents.get(goal_id, ())
    for depth in range(len(inside), len(chain)):
        parent, parent_label = chain[depth]
        lines.append(INDENT * depth + commence_line(parent_label))
        inside.append(parent)
    lines.append(INDENT * len(chain) + commence_line(label))
    return lines


def nested_answer(nesting: Nesting, inside: list[str], goal_id: str, outcome: str
                  ) -> list[str]:
    """The answer for a flat goal, then for each refinement its outcome leaves the outcome
    that refinement returns (after `Time-out: ...` when its time-out ended it)."""
    depth = len(nesting.parents.get(goal_id, ()))
    lines = [f"{INDENT * depth}{QUESTION} {ANSWER[outcome]}."]
    labels = dict(nesting.parents.get(goal_id, ()))
    for leaving in nesting.exits.get((goal_id, outcome), ()):
        depth = len(inside)
        if leaving.timed_out:
            lines.append(f"{INDENT * depth}Time-out: {labels.get(leaving.parent, '')}.")
        if inside:
            inside.pop()
        lines.append(f"{INDENT * (depth - 1)}{QUESTION} {ANSWER[leaving.returns]}.")
    return lines


def paths_of(orders: Orders) -> tuple[MissionGraph, PathCounts | None]:
    graph = build_graph(orders)
    return graph, count_paths(graph)
