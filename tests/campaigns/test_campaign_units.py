"""Campaign pieces: the Wilson interval against Newcombe's published table,
path numbers against enumeration, the sweep, the bounds, and one stored result per index."""

from __future__ import annotations

from pathlib import Path

import pytest
from sqlalchemy import func, select

from countersign.campaigns.simulate import Mission, simulate
from countersign.campaigns.spec import MAX_SIMULATIONS, MAX_SWEEP_CELLS, CampaignSpec
from countersign.campaigns.stats import goal_probabilities, summarize, wilson
from countersign.cli import campaign as cli_campaign
from countersign.errors import Unprocessable
from countersign.orders.canonical import digest, orders_to_json
from countersign.orders.examples import load_example
from countersign.orders.model import OutcomeProbabilities
from countersign.rehearse.sim import FAULTS
from countersign.store import campaigns as store
from countersign.store.db import Database
from countersign.store.tables import CampaignRun
from countersign.verify.paths import count_paths, iter_paths
from countersign.verify.refine import checked_form

# Newcombe (1998), Statistics in Medicine 17:857, Table I, method 3 (Wilson score, no
# continuity correction): an independent computation of the same interval.
NEWCOMBE = [((81, 263), (0.2553, 0.3662)), ((15, 148), (0.0624, 0.1605)),
            ((0, 20), (0.0, 0.1611)), ((1, 29), (0.0061, 0.1718))]


@pytest.mark.parametrize(("case", "expected"), NEWCOMBE)
def test_wilson_interval_equals_newcombes_table(case: tuple[int, int],
                                                 expected: tuple[float, float]) -> None:
    low, high = wilson(*case)
    assert (round(low, 4), round(high, 4)) == expected


def test_every_path_number_equals_the_enumerations() -> None:
    mission = Mission(load_example("search-and-sample"))
    assert mission.counts is not None
    paths = list(iter_paths(mission.graph, mission.counts))
    assert len(paths) == mission.total_paths == 75
    for path in paths:
        assert mission.path_index(path.goals, path.outcomes) == path.index
    assert mission.path_index(["G1"], ["succeed"]) is None  # not a whole path
    assert mission.path_index(["G2", "G3"], ["succeed", "succeed"]) is None


def test_a_refined_missions_campaign_flies_and_counts_its_flat_paths() -> None:
    """A campaign of the refined exemplar flies the goals inside G1 and numbers what it
    covers as `countersign paths` does (867 flat paths); the per-goal estimates name the
    goals of the orders (G1/G1.2), not their unrolled copies; a fault may wait for a goal
    inside."""
    orders = load_example("search-and-sample-refined")
    mission = Mission(orders)
    assert mission.total_paths == 867
    _, graph = checked_form(orders)
    counts = count_paths(graph)
    assert counts is not None
    flat = list(iter_paths(graph, counts))
    spec = CampaignSpec.build(simulations=6, faults=["none", "leak"],
                              goals=["start", "G1/G1.2"], orders=orders)
    assert spec.cells == ((), ("leak",), ("leak@G1/G1.2",))
    runs = [simulate(mission, i, *spec.simulation(i)) for i in range(6)]
    for run in runs:
        assert run["goals"][0].startswith("G1/G1.1#"), run["goals"]
        path = flat[run["path"] - 1]
        assert (list(path.goals), list(path.outcomes)) == (run["goals"], run["outcomes"])
    summary = summarize(runs, total_paths=mission.total_paths,
                        terminals=[(t.id, t.kind) for t in orders.effective_terminals],
                        goals=[g.id for g in orders.goals])
    assert summary["coverage"]["total_paths"] == 867
    assert "G1/G1.1" in summary["goals"] and not any("#" in g for g in summary["goals"])


def test_the_sweep_pairs_seeds_across_cells_and_is_bounded() -> None:
    orders = load_example("search-and-sample")
    spec = CampaignSpec.build(simulations=12, faults=["none", "leak"], goals=["start", "G3"],
                              seed=7, orders=orders)
    assert spec.cells == ((), ("leak",), ("leak@G3",))
    assert [spec.simulation(i) for i in range(4)] == [
        (7, ()), (7, ("leak",)), (7, ("leak@G3",)), (8, ())]
    assert spec.chunks()[-1] == (10, 12)
    for bad, field in [({"simulations": MAX_SIMULATIONS + 1}, "simulations"),
                       ({"simulations": 0}, "simulations"),
                       ({"simulations": 5, "faults": ["boom"]}, "faults"),
                       ({"simulations": 5, "faults": ["leak"], "goals": ["G99"]}, "goals")]:
        with pytest.raises(Unprocessable, match=field):
            CampaignSpec.build(orders=orders, **bad)  # type: ignore[arg-type]
    many_goals = [f"G{i}" for i in range(1, 6)] + ["start"]
    with pytest.raises(Unprocessable, match=f"at most {MAX_SWEEP_CELLS}"):
        CampaignSpec.build(simulations=5, faults=list(FAULTS), goals=many_goals * 1
                           + [f"X{i}" for i in range(20)])
    assert cli_campaign.FAULTS == FAULTS and cli_campaign.MAX_SIMULATIONS == MAX_SIMULATIONS


def test_estimates_and_offered_probabilities_fit_the_orders_form() -> None:
    orders = load_example("search-and-sample")
    mission = Mission(orders)
    runs = [simulate(mission, i, i, f) for i, f in enumerate([(), ("nav_drift",), ()])]
    summary = summarize(runs, total_paths=75,
                        terminals=[(t.id, t.kind) for t in orders.effective_terminals],
                        goals=[g.id for g in orders.goals])
    assert summary["simulations"] == 3
    assert sum(t["count"] for t in summary["terminals"].values()) == 3
    assert sum(summary["energy_wh"]["histogram"]["counts"]) == 3
    assert all(1 <= p["path"] <= 75 for p in summary["coverage"]["paths"])
    for offered in goal_probabilities(summary).values():
        OutcomeProbabilities.model_validate(offered["point"])
        OutcomeProbabilities.model_validate(
            {k: tuple(v) for k, v in offered["interval"].items()})


def test_a_result_is_stored_once_per_campaign_and_index(tmp_path: Path) -> None:
    database = Database(f"sqlite:///{tmp_path / 'c.db'}")
    database.migrate()
    orders = load_example("search-and-sample")
    with database.session() as db:
        row = store.create(db, orders=orders_to_json(orders), orders_digest=digest(orders),
                           spec={"simulations": 2}, simulations=2, owner=None,
                           signer=database.log_signer)
    with database.session() as db:
        assert store.store_result(db, row.id, 0, {"index": 0}) is True
    with database.session() as db:
        assert store.store_result(db, row.id, 0, {"index": 0, "again": True}) is False
    with database.session(write=False) as db:
        assert db.scalar(select(func.count()).select_from(CampaignRun)) == 1
