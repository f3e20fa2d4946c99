"""A campaign's specification: how many simulations and the sweep they cover.

The sweep is the product of faults and the goals at which each is injected; simulation `i`
runs sweep cell `i mod cells` with seed `seed + i div cells`, so every cell meets the same
seeds (a paired design) and the index alone says what to simulate: a retried job recomputes
exactly the same simulation.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Any

from ..errors import Unprocessable
from ..orders.model import Orders
from ..rehearse.sim import FAULTS
from ..rehearse.sim_nesting import goal_names

MAX_SIMULATIONS = 10_000
MAX_SWEEP_CELLS = 64
MAX_FAULTS = len(FAULTS) + 1
MAX_GOALS = 32
MAX_SEED = 2**31 - 1
# A team simulation runs every member's: the bound is on member simulations (simulations x
# members), so a team's campaign costs at most what a single vehicle's may.
MAX_MEMBER_SIMULATIONS = MAX_SIMULATIONS
NO_FAULT = "none"
AT_START = "start"
DEFAULT_CHUNK = 10  # simulations per job: a killed worker loses at most one job's progress


@dataclass(frozen=True)
class CampaignSpec:
    simulations: int
    faults: tuple[str, ...] = (NO_FAULT,)
    goals: tuple[str, ...] = (AT_START,)
    seed: int = 0
    chunk: int = DEFAULT_CHUNK
    cells: tuple[tuple[str, ...], ...] = field(default=(), compare=False, repr=False)

    @classmethod
    def build(cls, *, simulations: int, faults: Sequence[str] = (NO_FAULT,),
              goals: Sequence[str] = (AT_START,), seed: int = 0, chunk: int = DEFAULT_CHUNK,
              orders: Orders | None = None) -> CampaignSpec:
        """A checked spec; Unprocessable naming the bad field otherwise. With `orders`, the
        goals must be goals of those orders."""
        if isinstance(simulations, bool) or not isinstance(simulations, int) \
                or not 1 <= simulations <= MAX_SIMULATIONS:
            raise Unprocessable(f"simulations: must be a whole number from 1 to "
                                f"{MAX_SIMULATIONS}, not {simulations!r}")
        if isinstance(seed, bool) or not isinstance(seed, int) or not 0 <= seed <= MAX_SEED:
            raise Unprocessable(f"seed: must be a whole number from 0 to {MAX_SEED}")
        if isinstance(chunk, bool) or not isinstance(chunk, int) or not 1 <= chunk <= 1_000:
            raise Unprocessable("chunk: must be a whole number from 1 to 1000")
        faults = tuple(dict.fromkeys(faults)) or (NO_FAULT,)
        goals = tuple(dict.fromkeys(goals)) or (AT_START,)
        if len(faults) > MAX_FAULTS:
            raise Unprocessable(f"faults: at most {MAX_FAULTS}")
        if len(goals) > MAX_GOALS:
            raise Unprocessable(f"goals: at most {MAX_GOALS}")
        # None: orders not given (a stored spec, checked when it was made); [] one vehicle.
        vehicles = None if orders is None else [m.vehicle for m in orders.team or ()]
        if vehicles and simulations * len(vehicles) > MAX_MEMBER_SIMULATIONS:
            raise Unprocessable(f"simulations: a team of {len(vehicles)} runs "
                                f"{len(vehicles)} member simulations each; at most "
                                f"{MAX_MEMBER_SIMULATIONS // len(vehicles)} for this team")
        for name in faults:
            _check_fault(name, vehicles)
        # A refined mission's goals inside (G1/G1.2) are goals a fault may wait for too.
        try:
            known = _goal_ids(orders) if orders is not None else None
        except ValueError as exc:  # refinements that cannot be unrolled cannot be flown
            raise Unprocessable(f"orders: {exc}") from None
        for goal in goals:
            if goal != AT_START and known is not None and goal not in known:
                raise Unprocessable(f"goals: {str(goal)[:100]!r} is not a goal of these "
                                    f"orders (use {AT_START!r} to inject at the start)")
        cells = _cells(faults, goals)
        if len(cells) > MAX_SWEEP_CELLS:
            raise Unprocessable(f"the sweep has {len(cells)} cells (faults x goals); at most "
                                f"{MAX_SWEEP_CELLS}")
        return cls(simulations, faults, goals, seed, chunk, cells)

    @classmethod
    def from_json(cls, data: dict[str, Any], orders: Orders | None = None) -> CampaignSpec:
        return cls.build(simulations=data["simulations"], faults=data.get("faults", ()),
                         goals=data.get("goals", ()), seed=data.get("seed", 0),
                         chunk=data.get("chunk", DEFAULT_CHUNK), orders=orders)

    def to_json(self) -> dict[str, Any]:
        return {"simulations": self.simulations, "faults": list(self.faults),
                "goals": list(self.goals), "seed": self.seed, "chunk": self.chunk}

    def simulation(self, index: int) -> tuple[int, tuple[str, ...]]:
        """(seed, faults) of simulation `index` (0-based)."""
        if not 0 <= index < self.simulations:
            raise IndexError(index)
        cells = self.cells or _cells(self.faults, self.goals)
        return self.seed + index // len(cells), cells[index % len(cells)]

    def chunks(self) -> list[tuple[int, int]]:
        """[start, stop) ranges of indexes, one per job."""
        return [(start, min(start + self.chunk, self.simulations))
                for start in range(0, self.simulations, self.chunk)]


def _check_fault(name: str, vehicles: Sequence[str] | None) -> None:
    """A fault of the sweep; a team's may name one member (`VEHICLE:FAULT`) or apply to
    every member. `vehicles`: the team's, [] for one vehicle's orders, None when unknown."""
    vehicle, sep, fault = str(name).rpartition(":")
    if sep and vehicles != []:
        if vehicles is not None and vehicle not in vehicles:
            raise Unprocessable(f"faults: {str(name)[:60]!r} names vehicle {vehicle[:40]!r}, "
                                f"which is not in the team ({', '.join(vehicles)})")
        name = fault
    if name != NO_FAULT and name not in FAULTS:
        raise Unprocessable(f"faults: unknown fault {str(name)[:40]!r}; choose from "
                            f"{NO_FAULT}, {', '.join(FAULTS)}"
                            + (" (VEHICLE:FAULT for one member)" if vehicles else ""))


def _goal_ids(orders: Orders) -> set[str]:
    """Goals a fault may be injected at: a team's are every member's (a fault at G1 is
    injected into each member with a G1)."""
    if orders.team is None:
        return set(goal_names(orders))
    return {g for m in orders.team for g in goal_names(m.orders)}


def _cells(faults: Sequence[str], goals: Sequence[str]) -> tuple[tuple[str, ...], ...]:
    cells: list[tuple[str, ...]] = []
    for name in faults:
        if name.rpartition(":")[2] == NO_FAULT:
            cells.append(())
            continue
        for goal in goals:
            cells.append((name,) if goal == AT_START else (f"{name}@{goal}",))
    return tuple(dict.fromkeys(cells))
