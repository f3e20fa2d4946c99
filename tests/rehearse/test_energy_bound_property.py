"""The verifier's figures bound the simulation on any mission, not only the exemplar.

Random small missions (hypothesis): a DAG of goals in random areas with random behaviours,
depths and envelopes, costs given or estimated, for a vehicle with a speed and a power; one
random path replayed nominally, at a random step of the simulation's clock. Every goal of the
run uses at most its own cost (verify/costs.py, the model BUDGET and the probabilities charge)
plus the leg flown into it, in energy and in time; the leg flown is at most the verifier's leg
of that edge when the goal before ran its plan to the end, so there each goal stays within its
verified figure, and a path whose goals all ran to the end within BUDGET's worst path.

Refined missions too: a goal refined into a loop bounded by `steps` or `duration_s` (nested
once at random) is flown as the flat automaton the verifier prices, so each goal inside stays
within the figure of its copy (`G1/G1.2#3`)."""

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
from countersign.verify.paths import count_paths
from countersign.verify.refine import checked_form

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


@st.composite
def refined_missions(draw: st.DrawFn) -> Orders:
    """A random mission whose goals may be refined: each refinement a loop of 1-3 goals
    bounded by steps or by duration_s (then every goal inside has a positive duration), one
    level of it possibly refined again."""
    base = draw(missions()).model_dump(mode="json", exclude_defaults=True)
    area_ids = [a["id"] for a in base["areas"]]

    def refinement(prefix: str, depth: int) -> dict[str, Any]:
        count = draw(st.integers(1, 3))
        by_steps = depth > 1 or draw(st.booleans())
        ids = [f"{prefix}.{j}" for j in range(1, count + 1)]
        inner: list[dict[str, Any]] = []
        for gid in ids:
            goal: dict[str, Any] = {
                "id": gid, "behavior": draw(st.sampled_from(BEHAVIORS)),
                "area": draw(st.sampled_from(area_ids)),
                "next": {o: draw(st.sampled_from([*ids, "OK", "NO", "BAD"])) for o in OUTCOMES}}
            if not by_steps or draw(st.booleans()):
                goal["cost"] = {"energy_wh": draw(st.integers(0, 200)),
                                "duration_s": draw(st.integers(1, 3_000))}
            if by_steps and depth < 2 and draw(st.integers(0, 3)) == 0:
                goal["refines"] = refinement(gid, depth + 1)
            inner.append(goal)
        return {"start": ids[0], "goals": inner,
                "terminals": [{"id": "OK", "kind": "complete", "returns": "succeed"},
                              {"id": "NO", "kind": "abort", "returns": "fail"},
                              {"id": "BAD", "kind": "abort", "returns": "violate"}],
                "within": {"steps": draw(st.integers(1, 4))} if by_steps
                else {"duration_s": draw(st.integers(1, 6_000))},
                "on_timeout": draw(st.sampled_from(["fail", "violate"]))}

    for goal in base["goals"]:
        if draw(st.booleans()):
            goal["refines"] = refinement(goal["id"], 1)
    return Orders.model_validate(base)


def within_the_verifiers_figure(orders: Orders, pick: int, step_s: float) -> None:
    """Replay one path (chosen by `pick`) and hold each goal, and the path, to the verifier's
    figures on the form the verifier prices (a refined mission's flat automaton)."""
    flat, graph = checked_form(orders)
    counts = count_paths(graph)
    assert counts is not None
    path_index = 1 + pick % counts.total
    note(f"path {path_index} of {orders.model_dump_json(exclude_defaults=True)}")
    runs = rehearse(orders, path_index, step_s)
    costs = mission_costs(flat)
    goals = flat.goal_index()
    worst = worst_paths(flat, graph)
    assert worst is not None
    vehicle = flat.target_vehicle()
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


@settings(max_examples=100, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(missions(), st.integers(1, 10_000), st.sampled_from([1.0, 7.0, 30.0]))
def test_every_goal_rehearses_within_the_verifiers_figure(orders: Orders, pick: int,
                                                          step_s: float) -> None:
    within_the_verifiers_figure(orders, pick, step_s)


@settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(refined_missions(), st.integers(1, 10_000), st.sampled_from([1.0, 7.0, 30.0]))
def test_every_goal_inside_a_refinement_rehearses_within_its_figure(
        orders: Orders, pick: int, step_s: float) -> None:
    within_the_verifiers_figure(orders, pick, step_s)
