"""One campaign simulation: the rehearsal simulation run headless to its end, reduced to what
the statistics need (the path taken, its terminal, the energy)."""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

from ..orders.model import OUTCOMES, Orders
from ..rehearse.sim import Limits, Simulation
from ..rehearse.sim_nesting import rehearsed_form
from ..rehearse.sources import SimulateSource
from ..verify.graph import MissionGraph, build_graph
from ..verify.paths import PathCounts, count_paths

# Events are not kept by a campaign: a small bound saves the memory of thousands of them.
CAMPAIGN_LIMITS = Limits(max_events=200)
RUN_SECONDS = 10_000_000.0


class Mission:
    """The orders with their traversal graph and path counts, built once per worker. A
    refined mission is flown, and its paths counted, as its flat automaton: coverage counts
    the paths `countersign paths` lists."""

    def __init__(self, orders: Orders) -> None:
        self.orders = orders
        self.flown = rehearsed_form(orders)
        self.graph = build_graph(self.flown[0])
        self.counts = count_paths(self.graph)
        self._node = {goal: i for i, goal in enumerate(self.graph.goal_ids)}

    @property
    def total_paths(self) -> int | None:
        return None if self.counts is None else self.counts.total

    def path_index(self, goals: Sequence[str], outcomes: Sequence[str]) -> int | None:
        """The 1-based index of this outcome sequence among `countersign paths`, or None when
        it is not a complete path of the graph."""
        if self.counts is None:
            return None
        return path_rank(self.graph, self.counts, self._node, goals, outcomes)


def path_rank(graph: MissionGraph, counts: PathCounts, node_of: dict[str, int],
              goals: Sequence[str], outcomes: Sequence[str]) -> int | None:
    """Paths are enumerated depth first in the order succeed, fail, violate (verify.paths):
    a path's index is one plus the paths of every earlier sibling branch along it."""
    if not goals or len(goals) != len(outcomes) or graph.start is None:
        return None
    node = graph.start
    rank = 0
    per_node = counts.per_node
    for position, (goal, outcome) in enumerate(zip(goals, outcomes, strict=True)):
        if node_of.get(goal) != node or outcome not in OUTCOMES:
            return None
        k = OUTCOMES.index(outcome)
        successors = graph.succ[node]
        rank += sum(per_node[successors[j]] for j in range(k))
        node = successors[k]
        if node < 0:
            return None
        is_last = position == len(goals) - 1
        if graph.is_terminal(node) != is_last:
            return None
    return rank + 1


def simulate(mission: Mission, index: int, seed: int, faults: tuple[str, ...]) -> dict[str, Any]:
    sim = Simulation(mission.orders, seed=seed, source=SimulateSource(), faults=faults,
                     limits=CAMPAIGN_LIMITS, flown=mission.flown)
    sim.advance(RUN_SECONDS)
    run = sim.run
    return {
        "index": index,
        "seed": seed,
        "faults": list(faults),
        "path": mission.path_index(run.goals, run.outcomes),
        "goals": list(run.goals),
        "outcomes": list(run.outcomes),
        "terminal": run.terminal,
        "terminal_kind": run.terminal_kind,
        "energy_wh": round(sim.energy_used_wh, 3),
        "sim_time_s": round(sim.time_s, 3),
        "finished": sim.state == "finished",
    }
