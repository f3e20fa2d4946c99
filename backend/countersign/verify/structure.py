"""Structural verification of the mission automaton (seed 000 III.H; MEO rules M1, M2, G3, G5,
G7, G10): a strategic-level mission has one start, no loops, no unreachable goals and no goal
with an outcome that leads nowhere.
"""

from __future__ import annotations

import itertools
from collections import Counter
from collections.abc import Iterator
from typing import TYPE_CHECKING

from ..orders.findings import Finding, error
from ..orders.model import OUTCOMES, Orders
from .graph import MISSING, MissionGraph, build_graph

if TYPE_CHECKING:
    import networkx as nx

MAX_LOOPS_REPORTED = 50

OUTCOME_PHRASE = {
    "succeed": "succeeds",
    "fail": "fails",
    "violate": "ends with an imminent constraint violation",
}


def check_structure(orders: Orders, graph: MissionGraph | None = None) -> list[Finding]:
    """Every structural finding of the orders, in a stable order."""
    graph = graph or build_graph(orders)
    findings: list[Finding] = []
    findings.extend(_goals_and_start(orders))
    findings.extend(_duplicates(orders))
    findings.extend(_outcome_targets(orders, graph))
    findings.extend(_loops(graph))
    findings.extend(_unreachable(graph))
    return findings


def _goals_and_start(orders: Orders) -> Iterator[Finding]:
    if not orders.goals:
        yield error("M2", [orders.id], "The orders include no goal: there is nothing to execute.")
    start = orders.start
    goal_ids = orders.goal_index()
    if start is None or start == []:
        yield error("M1", [orders.id], "The orders name no start goal.")
    elif isinstance(start, list):
        if len(start) == 1 and start[0] in goal_ids:
            yield error(
                "M1", start, f"The start goal {start[0]} is given as a list; name it directly."
            )
        else:
            yield error(
                "M1",
                start,
                f"The orders name {len(start)} start goals ({', '.join(start)}); "
                "a mission starts with exactly one goal.",
            )
    elif start not in goal_ids:
        is_terminal = start in orders.terminal_index()
        why = "is a terminal, not a goal" if is_terminal else "is not a goal of these orders"
        yield error("M1", [start], f"The start goal {start} {why}.")


def _duplicates(orders: Orders) -> Iterator[Finding]:
    named = [("goal", g.id) for g in orders.goals]
    named += [("terminal", t.id) for t in orders.effective_terminals]
    named += [("constraint", c.id) for c in orders.constraints]
    counts = Counter(element_id for _, element_id in named)
    for element_id, count in counts.items():
        if count > 1:
            kinds = [kind for kind, other in named if other == element_id]
            described = ", ".join(kinds)
            yield error(
                "DUP",
                [element_id],
                f"The id {element_id} is used {count} times ({described}); "
                "every goal, terminal and constraint needs its own id.",
            )


def _outcome_targets(orders: Orders, graph: MissionGraph) -> Iterator[Finding]:
    known = set(graph.goal_ids) | {t.id for t in graph.terminals}
    for node, goal in enumerate(graph.goals):
        for k, outcome in enumerate(OUTCOMES):
            targets = goal.successors(outcome)
            if graph.succ[node][k] == MISSING:
                yield error(
                    "SINK",
                    [goal.id],
                    f"Goal {goal.id} ({goal.label}) says nothing about what comes next when it "
                    f"{OUTCOME_PHRASE[outcome]}: every outcome needs a next goal or a terminal.",
                    outcome=outcome,
                )
                continue
            if len(targets) > 1:
                yield error(
                    "G5",
                    [goal.id, *targets],
                    f"Goal {goal.id} ({goal.label}) names {len(targets)} next steps when it "
                    f"{OUTCOME_PHRASE[outcome]} ({', '.join(targets)}); it must name exactly one.",
                    outcome=outcome,
                )
            for target in targets:
                if target not in known:
                    yield error(
                        "G3",
                        [goal.id, target],
                        f"When goal {goal.id} ({goal.label}) {OUTCOME_PHRASE[outcome]}, the "
                        f"orders continue with {target}, which is neither a goal nor a terminal.",
                        outcome=outcome,
                    )


def _has_loop(graph: MissionGraph) -> bool:
    """Whether any goal can be reached again (Kahn's algorithm over the goals).

    Most orders have no loop: answering this without networkx spares every such validation
    the import of networkx (a quarter of a second of start-up)."""
    indegree = [0] * graph.goal_count
    for node in range(graph.goal_count):
        for target in graph.out_nodes(node):
            if target < graph.goal_count:
                indegree[target] += 1
    ready = [n for n in range(graph.goal_count) if indegree[n] == 0]
    removed = 0
    while ready:
        node = ready.pop()
        removed += 1
        for target in graph.out_nodes(node):
            if target < graph.goal_count:
                indegree[target] -= 1
                if indegree[target] == 0:
                    ready.append(target)
    return removed < graph.goal_count


def _cyclic_components(graph: MissionGraph) -> nx.DiGraph:
    """The goal subgraph restricted to goals that lie on some loop."""
    import networkx as nx

    digraph = nx.DiGraph()
    digraph.add_nodes_from(range(graph.goal_count))
    for node in range(graph.goal_count):
        for target in graph.out_nodes(node):
            if target < graph.goal_count:
                digraph.add_edge(node, target)
    on_loop: set[int] = set()
    for component in nx.strongly_connected_components(digraph):
        if len(component) > 1:
            on_loop.update(component)
    on_loop.update(n for n in range(graph.goal_count) if digraph.has_edge(n, n))
    return digraph.subgraph(on_loop).copy()


def _entry_distance(graph: MissionGraph, node: int) -> int:
    path = graph.outcomes_to(node)
    return len(path) if path is not None else graph.goal_count + 1


def _rotate_to_entry(graph: MissionGraph, cycle: list[int]) -> list[int]:
    """Start the loop at the goal the mission reaches first (else the first goal listed)."""
    entry = min(range(len(cycle)), key=lambda i: (_entry_distance(graph, cycle[i]), cycle[i]))
    return cycle[entry:] + cycle[:entry]


def _loop_outcomes(graph: MissionGraph, cycle: list[int]) -> list[list[str]]:
    steps = []
    for position, node in enumerate(cycle):
        following = cycle[(position + 1) % len(cycle)]
        steps.append([OUTCOMES[k] for k, t in enumerate(graph.succ[node]) if t == following])
    return steps


def _loops(graph: MissionGraph) -> Iterator[Finding]:
    if not _has_loop(graph):
        return
    import networkx as nx

    looping = _cyclic_components(graph)
    if looping.number_of_nodes() == 0:
        return
    cycles = itertools.islice(nx.simple_cycles(looping), MAX_LOOPS_REPORTED + 1)
    loops = sorted(
        (_rotate_to_entry(graph, list(c)) for c in cycles),
        key=lambda c: (_entry_distance(graph, c[0]), c),
    )
    for cycle in loops[:MAX_LOOPS_REPORTED]:
        ids = [graph.goal_ids[n] for n in cycle]
        steps = _loop_outcomes(graph, cycle)
        reached_by = graph.outcomes_to(cycle[0])
        ring = " -> ".join(
            f"{ids[i]} ({'/'.join(steps[i])})" for i in range(len(ids))
        ) + f" -> {ids[0]}"
        if len(ids) == 1:
            lead = f"Goal {ids[0]} can follow itself: {ring}."
        else:
            lead = f"Goals {', '.join(ids)} form a loop: {ring}."
        if reached_by is None:
            where = " The start never reaches this loop."
        elif not reached_by:
            where = " The mission enters it at its start goal."
        else:
            where = f" The mission first enters it after the outcomes {', '.join(reached_by)}."
        yield error(
            "G7",
            ids,
            lead + where + " A strategic-level mission must not loop.",
            loop_outcomes=steps,
            reached_by=reached_by,
        )
    if len(loops) > MAX_LOOPS_REPORTED:
        remaining = sorted(looping.nodes)
        yield error(
            "G7",
            [graph.goal_ids[n] for n in remaining],
            f"More than {MAX_LOOPS_REPORTED} loops exist; only the first {MAX_LOOPS_REPORTED} are "
            f"listed. These {len(remaining)} goals all lie on loops.",
            truncated=True,
        )


def _unreachable(graph: MissionGraph) -> Iterator[Finding]:
    if graph.start is None:
        return
    reachable = graph.reachable
    for node, goal in enumerate(graph.goals):
        if not reachable[node]:
            yield error(
                "G10",
                [goal.id],
                f"Goal {goal.id} ({goal.label}) can never run: no sequence of outcomes from the "
                f"start goal {graph.goal_ids[graph.start]} leads to it.",
            )
