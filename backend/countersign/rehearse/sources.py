"""Where a goal's outcome comes from (outcome sources).

- `manual`: a person answers each goal (the Figure 6 dialogue): the goal is animated to the
  end of its plan, then the rehearsal waits for succeed, fail or constraint.
- `replay`: one path of the exhaustive traversal (`verify.paths` order, 1-based index; a
  refined mission's paths are its flat automaton's, numbered as `countersign paths` numbers
  them); a goal that fails or violates on that path is cut short part-way so the scene shows it.
- `tour`: every path in traversal order, one run each, bounded.
- `simulate`: the simulation decides (rules, constraint monitors, energy, the plan).
"""

from __future__ import annotations

from typing import Literal

from ..orders.model import Orders
from ..verify.graph import MissionGraph
from ..verify.paths import MissionPath, PathCounts, count_paths, iter_paths
from ..verify.refine import checked_form

SourceKind = Literal["manual", "replay", "tour", "simulate"]
SOURCES: tuple[SourceKind, ...] = ("manual", "replay", "tour", "simulate")
Decision = Literal["end", "wait", "scripted", "continue"]


class OutcomeSource:
    kind: SourceKind = "simulate"
    # Whether the world's disturbances beyond the nominal case (seed 001's strong current)
    # happen: only when the simulation decides the outcomes. A replayed, toured or chosen
    # path is rehearsed nominally, as the verifier's budget figures assume.
    disturbed: bool = False

    def begin_run(self, run_index: int) -> int | None:
        """The path index of the next run, or None: no path (the first run of an unscripted
        source still runs; a later None ends the rehearsal)."""
        return None

    def scripted(self, goal_id: str, position: int) -> str | None:
        """The outcome the current path prescribes for the goal at this position."""
        return None

    def decide(self, outcome: str, *, plan_done: bool, scripted: str | None) -> Decision:
        return "end"


class SimulateSource(OutcomeSource):
    kind = "simulate"
    disturbed = True


class ManualSource(OutcomeSource):
    kind = "manual"

    def decide(self, outcome: str, *, plan_done: bool, scripted: str | None) -> Decision:
        return "wait" if plan_done else "continue"


class _PathSource(OutcomeSource):
    def __init__(self) -> None:
        self.path: MissionPath | None = None

    def scripted(self, goal_id: str, position: int) -> str | None:
        path = self.path
        if path is None or position >= len(path.goals) or path.goals[position] != goal_id:
            return None
        return path.outcomes[position]

    def decide(self, outcome: str, *, plan_done: bool, scripted: str | None) -> Decision:
        return "scripted" if plan_done else "continue"


def _paths_of(orders: Orders) -> tuple[MissionGraph, PathCounts | None]:
    """The graph and counts `countersign paths` reads: a refined mission's flat one."""
    graph = checked_form(orders)[1]
    return graph, count_paths(graph)


def _path(orders: Orders, index: int) -> MissionPath:
    graph, counts = _paths_of(orders)
    if counts is None:
        raise ValueError("the paths of these orders cannot be counted (no start, a loop or a "
                         "missing successor): fix the structural errors first")
    if not 1 <= index <= counts.total:
        raise ValueError(f"path index must be between 1 and {counts.total}, not {index}")
    return next(iter_paths(graph, counts, offset=index - 1, limit=1))


class ReplaySource(_PathSource):
    kind = "replay"

    def __init__(self, orders: Orders, path_index: int) -> None:
        super().__init__()
        self.index = path_index
        self.path = _path(orders, path_index)

    def begin_run(self, run_index: int) -> int | None:
        return self.index if run_index == 0 else None


class TourSource(_PathSource):
    kind = "tour"

    def __init__(self, orders: Orders, max_paths: int) -> None:
        super().__init__()
        graph, counts = _paths_of(orders)
        if counts is None:
            raise ValueError("the paths of these orders cannot be counted (no start, a loop or "
                             "a missing successor): fix the structural errors first")
        self.total = counts.total
        self.limit = min(counts.total, max_paths)
        self._paths = iter_paths(graph, counts, limit=self.limit)

    def begin_run(self, run_index: int) -> int | None:
        if run_index >= self.limit:
            return None
        self.path = next(self._paths, None)
        return None if self.path is None else self.path.index


def make_source(kind: str, orders: Orders, *, path_index: int | None = None,
                max_tour_paths: int = 100) -> OutcomeSource:
    if kind == "manual":
        return ManualSource()
    if kind == "simulate":
        return SimulateSource()
    if kind == "replay":
        return ReplaySource(orders, 1 if path_index is None else path_index)
    if kind == "tour":
        return TourSource(orders, max_tour_paths)
    raise ValueError(f"outcome source must be one of {', '.join(SOURCES)}, not {kind!r}")
