"""The verifier's figures bound the simulation on any mission, not only the exemplar.

Random small missions (hypothesis): a DAG of goals in random areas with random behaviours,
depths and envelopes, costs given or estimated, for a vehicle with a speed and a power; one
random path replayed nominally, at a random step of the simulation's clock. Every goal of the
run uses at most its own cost (verify/costs.py, the model BUDGET and the probabilities charge)
plus the leg flown into it, in energy and in time; the leg flown is at most the verifier's leg
of that edge when the goal before ran its plan to the end, so there each goal stays within its
verified figure, and a path whose goals all ran to the end within BUDGET's worst path."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

from hypothesis import HealthCheck, given, note, settings
from hypothesis import strategies as st

from countersign.orders.model import BUDGET_QUANTITIES, OUTCOMES, Orders
from countersign.rehearse.sim import Event, Limits, Simulation
from countersign.rehearse.sources import make_source
from countersign.verify.budget import worst_paths
from countersign.verify.costs import leg_cost, mission_costs
from countersign.verify.paths import paths_of

BEHAVIORS = ("area_search", "survey", "transect", "sample", "loiter", "rendezvous", "transit",
             "return_to_base")
# Floats: the simulation sums a goal's energy step by step, the verifier in one product.
EPSILON = 1e-6


@dataclass(frozen=True)
class GoalRun:
    goal: str
    outcome: str
    energy_wh: float
    duration_s: float
    leg_m: float  # geodesic metres flown on the leg into the goal


@st.composite
def areas(draw: st.DrawFn, name: str) -> dict[str, Any]:
    lat = 36.7 + draw(st.floats(-0.03, 0.03))
    lon = -121.9 + draw(st.floats(-0.03, 0.03))
    height = draw(st.floats(0.001, 0.008))
    width = draw(st.floats(0.001, 0.008))
    return {"id": name, "polygon": [[lat, lon], [lat, lon + width], [lat - height, lon + width],
                                    [lat - height, lon]]}


@st.composite
def missions(draw: st.DrawFn) -> Orders:
    area_ids = [f"A{j}" for j in range(draw(st.integers(1, 2)))]
    count = draw(st.integers(1, 5))
    goals: list[dict[str, Any]] = []
    for i in range(count):
        later = [f"G{j}" for j in range(i + 1, count)] + ["DONE", "ABORT"]
        goal: dict[str, Any] = {
            "id": f"G{i}", "behavior": draw(st.sampled_from(BEHAVIORS)),
            "next": {o: draw(st.sampled_from(later)) for o in OUTCOMES}}
        # Every goal runs somewhere: the verifier prices a leg between two places only (a goal
        # without an area has none, and the transit into or out of it is not priced).
        goal["area"] = draw(st.sampled_from(area_ids))
        if draw(st.booleans()):
            goal["cost"] = {"energy_wh": draw(st.integers(0, 400)),
                            "duration_s": draw(st.integers(0, 5_000))}
        if draw(st.booleans()):
            low = draw(st.integers(0, 80))
            goal["envelope"] = {"depth_m": [low, low + draw(st.integers(0, 60))]}
        params: dict[str, Any] = {}
        if draw(st.booleans()):
            # Far apart, so that the vehicle often changes depth between goals.
            params["depth_m"] = draw(st.sampled_from([0, 5, 60, 120]))
        if draw(st.booleans()):
            params["swath_width_m"] = draw(st.integers(50, 800))
        if draw(st.booleans()):
            params["duration_s"] = draw(st.integers(0, 1_200))
        if params:
            goal["params"] = params
        goals.append(goal)
    vehicle: dict[str, Any] = {
        "id": "auv", "speed_mps": draw(st.sampled_from([0.8, 1.5, 2.5])),
        "power_w": draw(st.sampled_from([40.0, 110.0, 300.0])),
        # Ample energy: the rehearsal's own energy check never gives a goal up.
        "budget": {"energy_wh": 1_000_000, "duration_s": 10_000_000}}
    if draw(st.booleans()):
        vehicle["envelope"] = {"depth_m": [0, draw(st.integers(20, 200))]}
    return Orders.model_validate({
        "id": "random", "vehicle": "auv", "start": "G0", "goals": goals,
        "areas": [draw(areas(a)) for a in area_ids], "vehicles": [vehicle],
        "terminals": [{"id": "DONE", "kind": "complete"}, {"id": "ABORT", "kind": "abort"}]})


def rehearse(orders: Orders, path_index: int, step_s: float) -> list[GoalRun]:
    """A nominal replay of one path: each goal's energy and time, the leg into it included."""
    sim = Simulation(orders, seed=path_index, limits=Limits(step_s=step_s),
                     source=make_source("replay", orders, path_index=path_index))
    runs: list[GoalRun] = []

    def ended(event: Event) -> None:
        active = sim.active
        if event.kind == "outcome" and active is not None:
            runs.append(GoalRun(active.goal.id, str(event.data["outcome"]), active.used_wh,
                                sim.time_s - active.started_s, active.leg_m))

    sim.listeners.append(ended)
    sim.advance(10_000_000)
    assert sim.state == "finished"
    return runs


@settings(max_examples=100, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(missions(), st.integers(1, 10_000), st.sampled_from([1.0, 7.0, 30.0]))
def test_every_goal_rehearses_within_the_verifiers_figure(orders: Orders, pick: int,
                                                          step_s: float) -> None:
    graph, counts = paths_of(orders)
    assert counts is not None
    path_index = 1 + pick % counts.total
    note(f"path {path_index} of {orders.model_dump_json(exclude_defaults=True)}")
    runs = rehearse(orders, path_index, step_s)
    costs = mission_costs(orders)
    goals = orders.goal_index()
    worst = worst_paths(orders, graph)
    assert worst is not None
    vehicle = orders.target_vehicle()
    totals = dict.fromkeys(BUDGET_QUANTITIES, 0.0)
    previous: GoalRun | None = None
    for run in runs:
        planned_leg = costs.lengths.get((previous.goal, previous.outcome), 0.0) \
            if previous else 0.0
        if previous is None or previous.outcome == "succeed":
            # The goal before ended where the verifier's leg starts: the leg flown is it (or
            # its first part, when the goal is cut short on the way).
            assert run.leg_m <= planned_leg * (1 + EPSILON) + EPSILON, (run, planned_leg)
        for quantity in BUDGET_QUANTITIES:
            own, _ = costs.goal(goals[run.goal], quantity)
            assert own is not None, (run.goal, quantity)
            leg = leg_cost(run.leg_m, quantity, vehicle)
            used = getattr(run, quantity)
            assert used <= (own + leg) * (1 + EPSILON) + EPSILON, (
                f"{run.goal} used {used} {quantity}, the verifier charges {own} + leg {leg}")
            totals[quantity] += used
        previous = run
    if all(run.outcome == "succeed" for run in runs[:-1]):
        for quantity, total in totals.items():
            assert total <= worst[quantity].total * (1 + EPSILON) + EPSILON
