"""What stays asserted in the logic session between goals: z3's check time grows
with everything asserted, so only what every goal's checks assume (mission-wide constraints,
the vehicle, domains, norms) stays; a constraint scoped to a few goals, or a constraint's
negation (checked once for vacuity), is asserted in its unit's own scope."""

from __future__ import annotations

from countersign.verify.graph import build_graph
from countersign.verify.logic import LogicCache, check_logic
from countersign.verify.properties import check_properties
from tests.bench.bench_logic import logic_orders


def test_only_mission_wide_constraints_stay_asserted_between_goals() -> None:
    orders = logic_orders(goals=60, constraints=40, norms=6, seed=2)
    cache = LogicCache()
    check_logic(orders, cache)
    check_properties(orders, build_graph(orders), cache)
    session = cache.model(orders).session
    assert session is not None
    kept = {key for key in session._based if key.startswith(("con:", "neg:"))}
    mission = {f"con:{c.id}" for c in orders.constraints if c.applies_to == "mission"}
    scoped = {f"con:{c.id}" for c in orders.constraints if c.applies_to != "mission"}
    assert scoped, "the generated orders should scope some constraints to goals"
    assert kept and kept <= mission, sorted(kept - mission)
