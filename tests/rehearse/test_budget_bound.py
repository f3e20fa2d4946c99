"""The verifier's budget figures bound what a nominal rehearsal uses.

The simulation flies the verifier's legs and charges legs and goals from the verifier's cost
model, so a replayed rehearsal of any path of the exemplar, read back through the execution
checker, is that path with no deviation, and its measured energy and time are at most the
verifier's figures for that path (the goals' costs plus the legs of the outcome edges taken),
which are at most the worst case the BUDGET check proved within the budget."""

from __future__ import annotations

import pytest

from countersign.export.rehearsal_log import rehearsal_runs
from countersign.orders.examples import load_example
from countersign.orders.model import BUDGET_QUANTITIES, Orders
from countersign.rehearse.execution import Step, check_execution, read_log
from countersign.rehearse.manager import Rehearsal, RehearsalOptions
from countersign.verify.budget import worst_paths
from countersign.verify.costs import goal_cost, leg_cost
from countersign.verify.legs import leg_lengths
from countersign.verify.paths import MissionPath, iter_paths, paths_of

ORDERS = load_example("search-and-sample")


def verifier_figures(orders: Orders, path: MissionPath) -> dict[str, float]:
    """The verifier's energy and time for one path: each goal's cost and each leg taken."""
    vehicle, areas, goals = orders.target_vehicle(), orders.area_index(), orders.goal_index()
    lengths = leg_lengths(orders)
    figures: dict[str, float] = {}
    for quantity in BUDGET_QUANTITIES:
        total = 0.0
        for goal, outcome in zip(path.goals, path.outcomes, strict=True):
            cost, _ = goal_cost(goals[goal], quantity, vehicle, areas)
            total += (cost or 0.0) + leg_cost(lengths.get((goal, outcome)), quantity, vehicle)
        figures[quantity] = total
    return figures


def rehearsed_usage(orders: Orders, path: MissionPath, seed: int,
                    steps: list[Step] | None = None) -> dict[str, float]:
    """A headless replay of the path, through the execution checker: its measured use (and
    its log's steps, appended to `steps` when given)."""
    rehearsal = Rehearsal(orders, owner="test", headless=True,
                          options=RehearsalOptions(source="replay", path_index=path.index,
                                                   seed=seed))
    rehearsal.run_headless(max_wall_s=600)
    (run,) = rehearsal_runs(rehearsal.stop().to_json())
    log = read_log(run.ndjson)
    if steps is not None:
        steps.extend(log)
    verdict = check_execution(orders, log)
    assert (run.claimed_path, verdict.path, verdict.deviations) == (path.index, path.index, ())
    sources = {u.quantity: u.source for u in verdict.usage}
    assert sources == {"energy_wh": "readings", "duration_s": "timestamps"}, sources
    return {u.quantity: u.used for u in verdict.usage}


def test_every_path_of_the_exemplar_rehearses_within_the_verifiers_figures() -> None:
    graph, counts = paths_of(ORDERS)
    assert counts is not None and counts.total == 75
    worst = worst_paths(ORDERS, graph)
    assert worst is not None
    over: list[str] = []
    for path in iter_paths(graph, counts):
        figures = verifier_figures(ORDERS, path)
        used = rehearsed_usage(ORDERS, path, seed=path.index)
        for quantity, figure in figures.items():
            # The verifier's worst case is the largest path figure, and within the budget.
            assert figure <= worst[quantity].total + 1e-6
            assert worst[quantity].budget is not None
            assert worst[quantity].total <= worst[quantity].budget
            if used[quantity] > figure + 1e-6:
                over.append(f"path {path.index}: {quantity} {used[quantity]:.3f} > "
                            f"{figure:.3f}")
    assert not over, over


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_the_all_succeed_path_uses_what_the_verifier_charges_for_its_work_and_legs(
        seed: int) -> None:
    """Path 1 (every goal succeeds) runs every plan to its end: its energy is the verifier's
    figure less only the cost of goals with no work to charge it to (G5, a transit to a
    station, whose transit is the leg into it)."""
    graph, counts = paths_of(ORDERS)
    assert counts is not None
    path = next(iter_paths(graph, counts, limit=1))
    assert path.outcomes == ("succeed",) * 5
    g5 = ORDERS.goal_index()["G5"].cost
    assert g5 is not None and g5.energy_wh is not None
    steps: list[Step] = []
    used = rehearsed_usage(ORDERS, path, seed, steps)
    assert used["energy_wh"] == pytest.approx(
        verifier_figures(ORDERS, path)["energy_wh"] - g5.energy_wh, abs=0.01)
    # Each goal, with the leg into it, lasts at most its duration cost plus that leg's time:
    # G3's sweep of Area B at cruise speed would take longer than its 5,400 s, so it is paced
    # to its cost (a second per waypoint for the simulation's step).
    vehicle, goals = ORDERS.target_vehicle(), ORDERS.goal_index()
    lengths = leg_lengths(ORDERS)
    previous: tuple[str, str] | None = None
    for step in steps:
        cost, _ = goal_cost(goals[step.goal], "duration_s", vehicle, ORDERS.area_index())
        leg = leg_cost(lengths.get(previous) if previous else None, "duration_s", vehicle)
        assert step.start is not None and step.time is not None and cost is not None
        took = float(step.time) - float(step.start)
        assert took <= cost + leg + 40, (step.goal, took, cost, leg)
        previous = (step.goal, step.outcome)
