"""A simulated fault that no constraint, rule or vehicle reaction can turn into
another outcome is reported before a run; one that something reads is not."""

from __future__ import annotations

import json

from countersign.orders.examples import example_bytes
from countersign.orders.expressions.reads import expression_quantities
from countersign.orders.model import Orders
from countersign.orders.reader import read_bytes
from countersign.rehearse.fault_reach import EFFECTS, fault_reach
from countersign.rehearse.sim import FAULTS, Simulation
from countersign.rehearse.sources import make_source


def orders(name: str) -> Orders:
    return read_bytes(example_bytes(name), name).orders


def without_hull_constraints() -> Orders:
    """The exemplar less its constraints on the safety equipment (C2, C3 read what a leak
    changes): a mission with nothing that reacts to a leak, as the issue found one."""
    data = json.loads(example_bytes("search-and-sample"))
    data["constraints"] = [c for c in data["constraints"]
                           if not {"safety_equipment_ok", "mission_systems_ok"}
                           & set(expression_quantities(c.get("expr")))]
    return read_bytes(json.dumps(data).encode(), "x").orders


def test_a_leak_nothing_reads_is_named_before_the_run() -> None:
    found = {r.fault: r for r in fault_reach(without_hull_constraints(),
                                             ["none", "leak", "low_energy", "leak"])}
    assert set(found) == {"leak", "low_energy"}
    assert not found["leak"].reacts
    assert found["leak"].because == ("leak: no rule or constraint reacts to it, so it cannot "
                                     "change any outcome")
    assert found["low_energy"].reacts and "energy check" in found["low_energy"].because


def test_a_constraint_or_a_rule_that_reads_the_fault_reacts() -> None:
    leak = fault_reach(orders("search-and-sample"), ["leak"])[0]
    assert leak.reacts and "C2 reads safety_equipment_ok" in leak.because, leak
    ruled = fault_reach(orders("search-and-sample-rules"), ["leak"])[0]
    assert ruled.reacts and "rule" in ruled.because, ruled


def test_the_table_covers_every_fault_and_names_what_the_simulation_changes() -> None:
    assert set(EFFECTS) == set(FAULTS)
    exemplar = orders("search-and-sample")
    sim = Simulation(exemplar, source=make_source("simulate", exemplar))
    measured, observed = sim.values(), sim.observations()
    for fault, effect in EFFECTS.items():
        assert effect.quantities <= set(measured), fault
        names = {atom.split("(")[0] for atom in observed}
        assert effect.observations - {"enough_energy"} <= names, fault
