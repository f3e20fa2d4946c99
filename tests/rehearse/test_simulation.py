"""The simulation, outcome sources and records, headless (no viser server)."""

from __future__ import annotations

from pathlib import Path

import pytest

from countersign.orders.examples import load_example
from countersign.orders.model import Orders
from countersign.orders.reader import read_file
from countersign.rehearse.manager import Rehearsal, RehearsalOptions
from countersign.rehearse.sim import FaultSpec, Limits, Simulation
from countersign.rehearse.sources import make_source
from countersign.verify.paths import iter_paths, paths_of

DATA = Path(__file__).parent / "data"


def headless(orders: Orders, **options: object) -> Rehearsal:
    rehearsal = Rehearsal(orders, owner="test", options=RehearsalOptions(**options),  # type: ignore[arg-type]
                          headless=True)
    rehearsal.run_headless(max_wall_s=60)
    return rehearsal


def simulate(orders: Orders, seed: int = 0, faults: tuple[str, ...] = ()) -> Simulation:
    sim = Simulation(orders, seed=seed, source=make_source("simulate", orders), faults=faults)
    sim.advance(10_000_000)
    assert sim.state == "finished"
    return sim


def test_seed_004_localisation_lost_during_the_second_transect() -> None:
    orders = load_example("transect-survey")
    nominal = simulate(orders)
    assert nominal.run.goals == ["G1", "G2", "G3", "G4", "G5"]
    assert nominal.run.outcomes == ["succeed"] * 5

    # Navigation drifts once the second transect starts: localisation is lost, the rules
    # abandon the transect and the vehicle goes home.
    sim = simulate(orders, faults=("nav_drift@G4",))
    run = sim.run
    assert run.goals == ["G1", "G2", "G3", "G4", "G5"]
    assert run.outcomes[:3] == ["succeed", "succeed", "succeed"]
    assert run.outcomes[3] != "succeed"  # transect 2 abandoned
    assert run.outcomes[4] == "succeed" and run.terminal == "COMPLETE"  # home
    ended = next(e for e in sim.events if e.kind == "decision" and e.goal == "G4")
    assert ended.data["planned"] == "transect_t2"
    for rule in ("X_precision", "X_t2_lost"):
        assert sim.rule_firings.get(rule), rule
    # Transect 2 was cut short: the vehicle left before the end of the line.
    g4 = next(e for e in sim.events if e.goal == "G4" and e.kind == "outcome")
    g4_nominal = next(e for e in nominal.events if e.goal == "G4" and e.kind == "outcome")
    assert g4.t < g4_nominal.t


def test_seed_004_leak_means_surface_and_abort() -> None:
    sim = simulate(load_example("transect-survey"), faults=("leak@G2",))
    decision = next(e for e in sim.events if e.kind == "decision" and e.goal == "G2")
    assert decision.data["action"] == "surface"
    assert "X_leak_surface" in decision.data["rules"]
    assert sim.run.outcomes[1] == "violate"
    assert sim.vehicle.depth == 0.0
    assert sim.run.terminal == "ABORT"


def test_seed_001_strong_current_forces_giving_up_a_goal() -> None:
    orders = read_file(DATA / "three-surveys.json").orders
    assert orders is not None
    with_current = without_current = None
    for seed in range(40):
        sim = simulate(orders, seed)
        strong = [e for e in sim.events if e.kind == "current" and e.data["strong"]]
        if not strong and without_current is None:
            without_current = sim
        if strong and strong[0].goal == "G1" and with_current is None:
            with_current = sim
        if with_current is not None and without_current is not None:
            break
    assert with_current is not None and without_current is not None
    # Normal currents: every survey is done.
    assert without_current.run.outcomes == ["succeed"] * 5
    # A strong opposing current in the first survey doubles consumption there; the learnt
    # consumption then cannot cover every survey and the way home, so a survey is given up
    # (fail, seed 001) and the vehicle still gets home.
    run = with_current.run
    given_up = [e for e in with_current.events
                if e.kind == "decision" and e.text.startswith("energy:")]
    assert given_up, run.outcomes
    assert given_up[0].data["consumption_factor"] > 1.0
    assert "fail" in run.outcomes[1:3]
    assert run.terminal == "COMPLETE"
    assert with_current.energy_remaining_wh > 0


def test_same_seed_same_record_digest() -> None:
    orders = load_example("search-and-sample")
    first = headless(orders, source="simulate", seed=7, faults=("contact_close@G3",))
    second = headless(orders, source="simulate", seed=7, faults=("contact_close@G3",))
    third = headless(orders, source="simulate", seed=8, faults=("contact_close@G3",))
    assert first.record().digest == second.record().digest
    assert first.record().digest != third.record().digest
    data = first.record().to_json()
    assert data["format"] == "countersign.rehearsal/1"
    assert data["orders"]["digest"].startswith("sha256:")
    with pytest.raises(LookupError):
        first.record().replay_html()  # headless: no scene was recorded


@pytest.mark.parametrize("index", [1, 2, 5, 26, 38, 75])
def test_replay_gives_the_outcomes_of_path_n(index: int) -> None:
    orders = load_example("search-and-sample")
    graph, counts = paths_of(orders)
    assert counts is not None
    path = next(iter_paths(graph, counts, offset=index - 1, limit=1))
    record = headless(orders, source="replay", path_index=index).record().to_json()
    assert record["outcomes"] == list(path.outcomes)
    assert record["goals"] == list(path.goals)
    assert record["terminal"] == path.terminal


def test_tour_visits_every_path_in_order_bounded() -> None:
    orders = load_example("transect-survey")
    graph, counts = paths_of(orders)
    assert counts is not None
    limits = Limits(max_tour_paths=12)
    sim = Simulation(orders, seed=0, source=make_source("tour", orders, max_tour_paths=12),
                     limits=limits)
    sim.advance(100_000_000)
    assert sim.state == "finished"
    expected = list(iter_paths(graph, counts, limit=12))
    assert [r.path_index for r in sim.runs] == [p.index for p in expected]
    assert [r.outcomes for r in sim.runs] == [list(p.outcomes) for p in expected]


@pytest.mark.parametrize(("fault", "constraint"), [
    ("leak", "C2"), ("nav_drift", "C1"), ("contact_close", "C6"),
])
def test_faults_end_the_goal_with_the_constraint_they_break(fault: str, constraint: str) -> None:
    sim = simulate(load_example("search-and-sample"), faults=(f"{fault}@G3",))
    decision = next(e for e in sim.events if e.kind == "decision" and e.goal == "G3")
    assert decision.data.get("constraint") == constraint
    assert sim.run.outcomes[sim.run.goals.index("G3")] == "violate"


def test_low_energy_gives_up_the_goal() -> None:
    sim = simulate(load_example("search-and-sample"), faults=("low_energy@G1",))
    assert sim.run.outcomes[0] == "fail"
    assert sim.events[[e.kind for e in sim.events].index("decision")].text.startswith("energy:")


def test_gps_loss_keeps_the_nominal_mission_without_a_surfacing() -> None:
    # GPS only matters at the surface; the exemplar stays submerged until the terminal.
    sim = simulate(load_example("search-and-sample"), faults=("gps_loss",))
    assert sim.run.terminal == "COMPLETE"
    assert "gps_loss" in sim.active_faults


def test_live_inputs_are_recorded_and_reproduce_the_run() -> None:
    orders = load_example("search-and-sample")
    live = Simulation(orders, seed=3, source=make_source("simulate", orders))
    live.advance(9_000)
    live.inject("leak")
    live.advance(10_000_000)
    again = simulate(orders, seed=3, faults=tuple(live.fault_log))
    assert again.run.to_json() == live.run.to_json()
    assert [e.to_json() for e in again.events] == [e.to_json() for e in live.events]


def test_manual_choices_and_their_errors() -> None:
    orders = load_example("search-and-sample")
    sim = Simulation(orders, seed=0, source=make_source("manual", orders))
    with pytest.raises(ValueError, match="no goal is waiting"):
        sim.choose("succeed")
    sim.advance(10_000_000)
    assert sim.state == "waiting_for_outcome" and sim.current_goal == "G1"
    with pytest.raises(ValueError, match="outcome must be one of"):
        sim.choose("maybe")
    for outcome in ("violate", "succeed"):  # G1 c -> G4, G4 s -> G5
        sim.choose(outcome)
        sim.advance(10_000_000)
    sim.choose("succeed")
    assert sim.state == "finished"
    assert sim.run.goals == ["G1", "G4", "G5"] and sim.run.terminal == "COMPLETE"


def test_options_and_faults_are_validated() -> None:
    orders = load_example("search-and-sample")
    for bad in ({"source": "dream"}, {"seed": -1}, {"path_index": 0}, {"speed": 0},
                {"faults": ("meteor",)}, {"faults": ("leak@-5",)}):
        with pytest.raises(ValueError):
            Rehearsal(orders, owner="t", options=RehearsalOptions(**bad), headless=True)  # type: ignore[arg-type]
    with pytest.raises(ValueError, match="between 1 and 75"):
        Rehearsal(orders, owner="t", options=RehearsalOptions(source="replay", path_index=76),
                  headless=True)
    assert str(FaultSpec.parse("leak@G2")) == "leak@G2"
    assert FaultSpec.parse("nav_drift@120").at_s == 120


def test_orders_with_a_loop_are_bounded() -> None:
    data = load_example("search-and-sample").model_dump(mode="json", exclude_unset=True)
    data["goals"][4]["next"] = {"succeed": "G1", "fail": "G1", "violate": "G1"}
    orders = Orders.model_validate(data)
    sim = Simulation(orders, seed=0, source=make_source("simulate", orders),
                     limits=Limits(max_goal_visits=12))
    sim.advance(100_000_000)
    assert sim.state == "finished"
    assert len(sim.run.goals) == 12
    assert any(e.kind == "error" and "G7" in e.text for e in sim.events)
