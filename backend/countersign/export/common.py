"""What every vehicle format decides the same way: which maneuver a goal becomes, at what depth
and speed, and which parts of the orders no vehicle format carries."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Literal

from ..orders.model import Goal, Orders
from ..verify.nesting import Nesting
from ..verify.refine import flatten, has_refinements, refine_findings
from ..verify.structure import check_structure
from .geometry import Box, bounding_box
from .notes import ExportError, ExportNote

Kind = Literal["rows", "loiter", "station", "goto", "here"]

# Behaviours that cover an area, wait at a place, or hold a point; anything else travels.
SWEEPS = frozenset({"area_search", "hydro_survey", "survey", "search", "mine_hunt", "mapping"})
LOITERS = frozenset({"rendezvous", "reacquire", "loiter", "orbit", "track"})
HOLDS = frozenset({"sample", "surface_report", "hold", "station_keeping", "report"})
TRAVELS = frozenset({"transit", "transect", "return", "return_to_base", "goto", "recover"})
DEFAULT_SPEED_MPS = 1.0
DEFAULT_LANE_M = 50.0


@dataclass(frozen=True)
class Placement:
    goal: Goal
    index: int
    kind: Kind
    box: Box | None
    depth_m: float | None


# Without these the automaton has no well-defined next step; loops and unreachable goals still
# load on a vehicle (and are named as notes), since approval, not export, judges them.
BLOCKING = frozenset({"M1", "M2", "DUP", "G3", "G5", "SINK"})


def require_sound(orders: Orders, notes: list[ExportNote]) -> None:
    """Refuse orders a vehicle cannot load (no start, a dangling or missing outcome, a
    duplicate id), naming the findings; note the other structural errors."""
    errors = [f for f in check_structure(orders) if f.severity == "error"]
    blocking = [f for f in errors if f.code in BLOCKING]
    if blocking:
        named = "; ".join(f"{f.code} {', '.join(f.subjects)}" for f in blocking[:5])
        raise ExportError(f"the orders cannot become a vehicle plan ({named}); fix them first")
    for finding in errors:
        notes.append(ExportNote(f"STRUCTURE-{finding.code}", "/goals",
                                f"exported despite a structural error: {finding.message}"))


def flat_with_nesting(orders: Orders, notes: list[ExportNote]) -> tuple[Orders, Nesting | None]:
    """A vehicle runs a refined mission as its flat automaton: each goal inside a
    refinement becomes a maneuver or mode of its own, named by its flat id (`G1/G1.2`; `#k`
    for the k-th goal commenced inside a time-out's unrolling), so the plan is exactly the
    automaton whose paths were counted and signed, and the hierarchy (the refined goals each
    flat goal runs inside) for the formats that can show it. A broken refinement is refused."""
    if not has_refinements(orders):
        return orders, None
    broken = [f for f in refine_findings(orders) if f.severity == "error"]
    flat = flatten(orders)
    broken += flat.findings
    if broken:
        named = "; ".join(f"{f.code} {', '.join(f.subjects)}" for f in broken[:5])
        raise ExportError(f"the refinements cannot become a vehicle plan ({named}); "
                          "fix them first")
    notes.append(ExportNote("REFINE", "/goals", "refined goals are exported flat: their "
                            "refinements' goals are named G1/G1.1 (#k: the k-th goal commenced "
                            "inside a time-out's unrolling); /goals/N below counts flat goals"))
    return flat.orders, flat.nesting


def placements(orders: Orders, notes: list[ExportNote]) -> list[Placement]:
    areas = orders.area_index()
    result: list[Placement] = []
    for index, goal in enumerate(orders.goals):
        where = f"/goals/{index}"
        area = areas.get(goal.area) if goal.area else None
        box = bounding_box(list(area.polygon)) if area is not None else None
        behavior = (goal.behavior or "").lower()
        if box is None:
            kind: Kind = "here"
            notes.append(ExportNote("NO-AREA", where, f"goal {goal.id} has no charted area: "
                                    "it holds station where the vehicle is"))
        elif behavior in SWEEPS and box.height_m > 1 and box.width_m > 1:
            kind = "rows"
        elif behavior in LOITERS:
            kind = "loiter"
        elif behavior in HOLDS:
            kind = "station"
        else:
            kind = "goto"
            if behavior not in TRAVELS:
                notes.append(ExportNote(
                    "BEHAVIOR", f"{where}/behavior", f"goal {goal.id}: behaviour "
                    f"{goal.behavior or '(none)'!r} has no vehicle counterpart; written as a "
                    "transit to the centre of its area"))
        depth = goal.envelope.get("depth_m")
        result.append(Placement(goal, index, kind, box,
                                None if depth is None else (depth[0] + depth[1]) / 2))
        for quantity in sorted(set(goal.envelope) - {"depth_m"}):
            notes.append(ExportNote("ENVELOPE", f"{where}/envelope/{quantity}",
                                    f"goal {goal.id}: the bound on {quantity} is not carried"))
    return result


def speed_of(orders: Orders, notes: list[ExportNote]) -> float:
    vehicle = orders.target_vehicle()
    if vehicle is not None and vehicle.speed_mps:
        return vehicle.speed_mps
    notes.append(ExportNote("SPEED", "/vehicles", "the target vehicle names no speed_mps: "
                            f"maneuvers use {DEFAULT_SPEED_MPS:g} m/s"))
    return DEFAULT_SPEED_MPS


def lane_width(goal: Goal) -> float:
    value = goal.params.get("line_spacing_m")
    return float(value) if isinstance(value, int | float) and value > 0 else DEFAULT_LANE_M


def duration_s(goal: Goal) -> int:
    """Seconds the goal is ordered to last (its cost), 0 when unbounded."""
    if goal.cost is not None and goal.cost.duration_s:
        return int(goal.cost.duration_s)
    return 0


def uncarried(orders: Orders, fmt: str, notes: list[ExportNote]) -> None:
    """Norms, contingency rules and path properties: judged before signing, never on board."""
    for index, norm in enumerate(orders.norms):
        notes.append(ExportNote("NORM", f"/norms/{index}", f"norm {norm.id} has no {fmt} "
                                "counterpart: it was checked against the orders, not carried"))
    if orders.rules is not None:
        notes.append(ExportNote("RULES", "/rules", f"contingency rules have no {fmt} "
                                "counterpart; the vehicle's own fault handling applies"))
    for index, prop in enumerate(orders.properties):
        notes.append(ExportNote("PROPERTY", f"/properties/{index}", f"path property {prop.id} "
                                "is a check before signing, not carried"))
