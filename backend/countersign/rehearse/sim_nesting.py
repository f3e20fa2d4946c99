"""A refined mission in the rehearsal: the simulation flies the flat automaton every check
reads (verify/refine.py), so a refined goal is flown as its refinement.

Flying the flat form is what makes the rehearsal agree with the verifier by construction: the
inner goals are the flat goals (`G1/G1.2`, `G1/G1.2#k` in a `steps` refinement, `@Ts` in a
`duration_s` one), their successors already carry the time-outs as DESIGN.md and the README
define them (checked before a goal inside commences, on the goals' priced durations, not on
simulated time), and `--path N` numbers paths as `countersign paths` does on the same orders.
What the flat form forgets, where each flat goal sits in the hierarchy and which refinements an
outcome leaves, comes from its `Nesting`; this module turns it into the rehearsal's events
(the refined goal's `Commence:`, its `Time-out:` and the outcome its refinement returned),
indented as traces indent them (verify/paths.py).
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import TYPE_CHECKING, Any

from ..orders.model import Orders
from ..verify.nesting import Nesting
from ..verify.paths import ANSWER, INDENT, commence_line
from ..verify.refine import base_id, flatten, has_refinements

if TYPE_CHECKING:
    from .sim import Simulation


def rehearsed_form(orders: Orders) -> tuple[Orders, Nesting | None]:
    """The orders the simulation flies and their hierarchy (None: nothing is refined).
    ValueError when the refinements cannot be unrolled (REFINE names why)."""
    if not has_refinements(orders):
        return orders, None
    flat = flatten(orders)
    if flat.findings:
        raise ValueError(flat.findings[0].message)
    return flat.orders, flat.nesting


def goal_names(orders: Orders) -> set[str]:
    """Every goal name `NAME@GOAL` may give: the orders' goals, and for a refined mission the
    goals inside (`G1/G1.2`) and their flat copies (`G1/G1.2#3`)."""
    names = set(orders.goal_index())
    flown, nesting = rehearsed_form(orders)
    if nesting is not None:
        for goal in flown.goals:
            names.update(fault_names(nesting, goal.id))
    return names


def chain(nesting: Nesting | None, goal_id: str) -> tuple[tuple[str, str], ...]:
    """The refined goals a flat goal runs inside, outermost first: (flat id, label)."""
    return nesting.parents.get(goal_id, ()) if nesting is not None else ()


def fault_names(nesting: Nesting | None, goal_id: str) -> set[str]:
    """The names `NAME@GOAL` may give for the goal about to commence: its flat id, the id
    without unrolling marks (`G1/G1.2`), and the refined goals it runs inside (a fault at a
    refined goal applies when its refinement's first goal commences)."""
    names = {goal_id}
    if nesting is not None:
        names.add(base_id(goal_id))
        for parent, _ in chain(nesting, goal_id):
            names.update((parent, base_id(parent)))
    return names


def enter(sim: Simulation, goal_id: str) -> int:
    """Emit the Commence events of the refined goals `goal_id` is the first goal of (those not
    begun yet on this run); return the goal's depth, for its own Commence line."""
    parents = chain(sim.nesting, goal_id)
    inside = sim.inside
    for depth in range(len(inside), len(parents)):
        parent, label = parents[depth]
        inside.append(parent)
        sim._emit("refined", INDENT * depth + commence_line(label), parent,
                  {"depth": depth, "refined": True})
    return len(parents)


def leave(sim: Simulation, goal_id: str, outcome: str) -> None:
    """After a flat goal's outcome: each refinement that outcome leaves, innermost first, ends
    with the outcome it returns; a time-out says so first (seed 000 III.D)."""
    if sim.nesting is None:
        return
    labels = dict(chain(sim.nesting, goal_id))
    for leaving in sim.nesting.exits.get((goal_id, outcome), ()):
        depth = max(0, len(sim.inside) - 1)
        label = labels.get(leaving.parent, leaving.parent)
        data: dict[str, Any] = {"depth": depth, "returns": leaving.returns}
        if leaving.timed_out:
            sim._emit("timeout", INDENT * (depth + 1) + f"Time-out: {label}.", leaving.parent,
                      data)
            sim.timeouts.append({"goal": leaving.parent, "title": label,
                                 "returns": leaving.returns, "t": round(sim.time_s, 3)})
        if sim.inside:
            sim.inside.pop()
        sim._emit("returned", INDENT * depth + f"{label}: {leaving.returns} (its refinement "
                  f"returned {leaving.returns}{', timed out' if leaving.timed_out else ''}).",
                  leaving.parent, {**data, "outcome": leaving.returns,
                                   "timed_out": leaving.timed_out})


def status(sim: Simulation) -> dict[str, Any]:
    """What a live status adds for a refined mission (`refined`): the refined goals the
    current goal runs inside, outermost first (the breadcrumb), and the last time-out that
    ended a refinement. Nothing for orders without refinements: their status is unchanged."""
    if sim.nesting is None:
        return {}
    goal = sim.active.goal.id if sim.active is not None else ""
    inside = [{"id": p, "title": label} for p, label in chain(sim.nesting, goal)]
    return {"refined": {"inside": inside,
                        "timeout": sim.timeouts[-1] if sim.timeouts else None}}


def summary_lines(nesting: Nesting, goals: Sequence[str], outcomes: Sequence[str]
                  ) -> list[str]:
    """A run as trace-like lines: each refined goal's line, its goals indented under it, then
    the outcome its refinement returned (after `Time-out: G1.` when its time-out ended it)."""
    words = {o: f"{a}." for o, a in ANSWER.items()}
    lines: list[str] = []
    inside: list[str] = []
    for goal, outcome in zip(goals, outcomes, strict=False):
        parents = nesting.parents.get(goal, ())
        for depth in range(len(inside), len(parents)):
            lines.append(f"{INDENT * depth}{parents[depth][0]}: commence.")
            inside.append(parents[depth][0])
        lines.append(f"{INDENT * len(parents)}{goal}: {words[outcome]}")
        for leaving in nesting.exits.get((goal, outcome), ()):
            if leaving.timed_out:
                lines.append(f"{INDENT * len(inside)}Time-out: {leaving.parent}.")
            if inside:
                inside.pop()
            lines.append(f"{INDENT * len(inside)}{leaving.parent}: {words[leaving.returns]}")
    return lines
