"""Which simulated faults can change an outcome of these orders, said before a run.
A fault changes what the vehicle measures and observes (sim_sensing.py: `values` and
`observations`); it can turn a goal into another outcome only through a constraint that reads a
changed quantity (the monitor ends the goal with violate), a contingency rule that reads a
changed observation (a safety action), or a reaction built into the vehicle (the energy check).
A fault that reaches none of them ends every run as it would have ended without it: a campaign
of it measures nothing, and the page says so instead of reporting 100% COMPLETE as evidence.
"""

from __future__ import annotations

from collections.abc import Iterable
from dataclasses import dataclass

from ..orders.expressions.reads import expression_quantities
from ..orders.model import Orders
from ..rules.theory import TheoryError, theory_for


@dataclass(frozen=True)
class Effect:
    quantities: frozenset[str]
    observations: frozenset[str]  # rule atom names (arguments aside)
    builtin: str | None = None  # the vehicle's own reaction, when it has one


# What each fault of sim.py changes; kept beside sim_sensing.py's values() and observations(),
# which tests/rehearse/test_fault_reach.py reads to hold the two together.
EFFECTS: dict[str, Effect] = {
    "gps_loss": Effect(frozenset({"gps_fix", "nav_error_m"}),
                       frozenset({"gps_captured", "gps_was_captured",
                                  "localisation_precision_low", "nav_error_high"})),
    "nav_drift": Effect(frozenset({"nav_error_m"}),
                        frozenset({"localisation_precision_low", "nav_error_high"})),
    "leak": Effect(frozenset({"safety_equipment_ok", "mission_systems_ok"}),
                   frozenset({"leak", "safety_sensor_failure"})),
    "low_energy": Effect(frozenset({"energy_remaining_wh", "energy_wh", "battery_pct",
                                    "battery_reserve_pct"}),
                         frozenset({"low_energy", "battery_low", "battery_critical",
                                    "enough_energy"}),
                         builtin="the vehicle's energy check ends a goal it cannot finish "
                                 "and still return from"),
    "contact_close": Effect(frozenset({"contact_distance_m", "contact_range_m", "contact_count"}),
                            frozenset({"contact_close", "surface_contact_close",
                                       "contact_within_1000m"})),
}


@dataclass(frozen=True)
class FaultReach:
    fault: str
    reacts: bool
    because: str


def _rule_atoms(orders: Orders) -> dict[str, list[str]]:
    """Rule ids by the atom names their conditions read."""
    try:
        theory = theory_for(orders)
    except (TheoryError, ValueError):
        return {}  # unreadable rules are a RULES finding; they react to nothing here
    atoms: dict[str, list[str]] = {}
    for rule in theory.rules if theory is not None else ():
        for literal in rule.body:
            atoms.setdefault(literal.name, []).append(rule.id)
    return atoms


def fault_reach(orders: Orders, faults: Iterable[str]) -> list[FaultReach]:
    """For each fault (unknown names and "none" skipped), whether anything in the orders, their
    rules or the vehicle reacts to it, and what."""
    reads: dict[str, list[str]] = {}
    for constraint in orders.constraints:
        for quantity in expression_quantities(constraint.expr):
            reads.setdefault(quantity, []).append(constraint.id)
    atoms = _rule_atoms(orders)
    out: list[FaultReach] = []
    for fault in dict.fromkeys(faults):
        effect = EFFECTS.get(fault)
        if effect is None:
            continue
        reasons = [f"{c} reads {q}" for q in sorted(effect.quantities) for c in reads.get(q, [])]
        reasons += [f"rule {r} reads {a}" for a in sorted(effect.observations)
                    for r in atoms.get(a, [])]
        if effect.builtin:
            reasons.append(effect.builtin)
        if reasons:
            out.append(FaultReach(fault, True, "; ".join(dict.fromkeys(reasons))))
        else:
            out.append(FaultReach(fault, False, f"{fault}: no rule or constraint reacts to it, "
                                                "so it cannot change any outcome"))
    return out
