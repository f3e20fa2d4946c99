"""Exact outcome probabilities, checked against path enumeration, the vertices
of each goal's polytope (intervals) and Storm on the same Markov chain; the expected energy
and time charge the legs between goals as BUDGET does (one cost model)."""

from __future__ import annotations

import itertools
import json
import random
import sys
from fractions import Fraction
from pathlib import Path

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from pydantic import ValidationError

from countersign.orders.examples import example_bytes
from countersign.orders.model import BUDGET_QUANTITIES, Orders
from countersign.orders.reader import read_file
from countersign.verify import probability
from countersign.verify.budget import worst_paths
from countersign.verify.graph import build_graph
from countersign.verify.paths import count_paths, iter_path_lines, iter_paths
from countersign.verify.probability import (
    QUANTILES,
    fraction_boxes,
    goal_probabilities,
    outcome_probabilities,
    path_probability_bounds,
    quantile,
    summary_lines,
)

from .prob_oracles import (
    Dist,
    enumerate_figures,
    priced,
    random_orders,
    storm_figures,
    vertices,
    with_probabilities,
)


def _reference() -> Path | None:
    here = Path(__file__).resolve()
    for root in (*here.parents, Path("/work")):
        candidate = root / "shared" / "reference" / "nps-ethical-control" / "missions" / "avcl"
        if candidate.is_dir():
            return candidate
    return None


AVCL = _reference()


def exemplar() -> dict[str, object]:
    data: dict[str, object] = json.loads(example_bytes("search-and-sample"))
    return data


def point_dists(orders: Orders) -> list[Dist]:
    boxes = fraction_boxes(goal_probabilities(orders, build_graph(orders)))
    return [(b[0][0], b[1][0], b[2][0]) for b in boxes]


def assert_matches_enumeration(orders: Orders) -> None:
    """Every figure equals the sum over every path, each path charged its goals and its legs;
    BUDGET's worst path is the costliest of them and no quantile exceeds it."""
    graph = build_graph(orders)
    figures = outcome_probabilities(orders, graph)
    worst = worst_paths(orders, graph)
    assert figures is not None and figures.exact and worst is not None
    for quantity in BUDGET_QUANTITIES:
        oracle = enumerate_figures(graph, point_dists(orders), *priced(orders, quantity))
        # The report's doubles are the exact values' (the fixed-point pass decides them).
        for terminal, value in oracle["terminals"].items():
            assert figures.terminals[terminal].exact == float(value)
        assert figures.violation.exact == float(oracle["violation"])
        assert figures.expected[quantity].bound.exact == float(oracle["expected"])
        assert worst[quantity].total == float(oracle["worst"])
        quantiles = figures.expected[quantity].quantiles
        assert quantiles is not None
        for level in QUANTILES:
            assert quantiles[level] == float(quantile(oracle["distribution"], Fraction(level)))
            assert quantiles[level] <= worst[quantity].total


def assert_matches_storm(orders: Orders) -> None:
    graph = build_graph(orders)
    figures = outcome_probabilities(orders, graph)
    assert figures is not None
    storm = storm_figures(orders)
    for terminal, bound in figures.terminals.items():
        assert float(bound.low) == pytest.approx(storm[f"t_{terminal}"], abs=1e-9)
    assert float(figures.violation.low) == pytest.approx(storm["violated"], abs=1e-9)
    assert float(figures.expected["energy_wh"].bound.low) == pytest.approx(
        storm["energy"], rel=1e-9, abs=1e-9)
    assert float(figures.expected["duration_s"].bound.low) == pytest.approx(
        storm["time"], rel=1e-9, abs=1e-9)


def test_the_exemplar_matches_storm_and_enumeration() -> None:
    for seed in range(5):
        orders = with_probabilities(exemplar(), seed)
        assert_matches_storm(orders)
        assert_matches_enumeration(orders)


@pytest.mark.skipif(AVCL is None, reason="NPS reference missions (shared/reference/"
                    "nps-ethical-control/missions/avcl) are not present on this machine")
def test_the_nps_missions_match_storm() -> None:
    assert AVCL is not None
    checked = 0
    for path in sorted(AVCL.glob("*.xml")):
        loaded = read_file(path)
        if loaded.orders is None:
            continue
        orders = with_probabilities(loaded.orders.model_dump(mode="json", by_alias=True), 3)
        if count_paths(build_graph(orders)) is None:
            continue
        assert_matches_storm(orders)
        checked += 1
    assert checked >= 5


def test_random_graphs_match_storm() -> None:
    rng = random.Random(20)
    for _ in range(25):
        assert_matches_storm(random_orders(rng, rng.randint(1, 30), terminals=rng.randint(1, 3)))


def test_random_graphs_with_legs_match_storm() -> None:
    rng = random.Random(21)
    for _ in range(10):
        orders = random_orders(rng, rng.randint(2, 12), terminals=rng.randint(1, 3), places=True)
        assert any(any(leg) for leg in priced(orders)[1])
        assert_matches_storm(orders)


def test_the_exemplars_expected_energy_charges_the_legs() -> None:
    """The exemplar with probabilities: its worst path is 1,137 Wh with legs, and its
    expectation and quantiles are figures of the same paths, not of the goals alone (660 Wh
    for every goal)."""
    orders = with_probabilities(exemplar(), 1)
    graph = build_graph(orders)
    figures = outcome_probabilities(orders, graph)
    worst = worst_paths(orders, graph)
    assert figures is not None and worst is not None
    assert round(worst["energy_wh"].total) == 1137
    energy = figures.expected["energy_wh"]
    assert energy.quantiles is not None
    assert max(energy.quantiles.values()) == worst["energy_wh"].total
    assert float(energy.bound.low) > 660
    assert_matches_enumeration(orders)


@settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(st.integers(0, 2**32), st.integers(1, 8))
def test_point_figures_equal_enumeration(seed: int, goals: int) -> None:
    assert_matches_enumeration(random_orders(random.Random(seed), goals,
                                             terminals=random.Random(seed).randint(1, 3)))


@settings(max_examples=30, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(st.integers(0, 2**32), st.integers(1, 7))
def test_point_figures_with_legs_equal_enumeration(seed: int, goals: int) -> None:
    assert_matches_enumeration(random_orders(random.Random(seed), goals, places=True,
                                             terminals=random.Random(seed).randint(1, 3)))


def _extremes_by_vertices(orders: Orders) -> dict[str, tuple[Fraction, Fraction]]:
    graph = build_graph(orders)
    boxes = fraction_boxes(goal_probabilities(orders, graph))
    costs, legs = priced(orders)
    best: dict[str, tuple[Fraction, Fraction]] = {}
    for choice in itertools.product(*(vertices(b) for b in boxes)):
        oracle = enumerate_figures(graph, list(choice), costs, legs)
        values = {**{f"t_{t}": v for t, v in oracle["terminals"].items()},
                  "violated": oracle["violation"], "energy": oracle["expected"]}
        for name, value in values.items():
            low, high = best.get(name, (value, value))
            best[name] = (min(low, value), max(high, value))
    return best


@settings(max_examples=40, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(st.integers(0, 2**32), st.integers(1, 4))
def test_interval_bounds_equal_brute_force_over_vertices(seed: int, goals: int) -> None:
    rng = random.Random(seed)
    orders = random_orders(rng, goals, kinds=("point", "interval", "none"),
                           places=rng.random() < 0.5)
    figures = outcome_probabilities(orders, build_graph(orders))
    assert figures is not None
    brute = _extremes_by_vertices(orders)
    def doubles(pair: tuple[Fraction, Fraction]) -> tuple[float, float]:
        return float(pair[0]), float(pair[1])

    for terminal, bound in figures.terminals.items():
        assert doubles((bound.low, bound.high)) == doubles(brute[f"t_{terminal}"])
    assert doubles((figures.violation.low, figures.violation.high)) == doubles(brute["violated"])
    energy = figures.expected["energy_wh"].bound
    assert doubles((energy.low, energy.high)) == doubles(brute["energy"])


def test_missing_probabilities_give_bounds_and_names() -> None:
    data = exemplar()
    orders = with_probabilities(data, 1)
    goals = orders.model_dump(mode="json", by_alias=True)
    goals["goals"][4].pop("p")  # G5 Return to Base: unknown
    orders = Orders.model_validate(goals)
    figures = outcome_probabilities(orders, build_graph(orders))
    assert figures is not None and not figures.exact
    assert figures.unknown == ("G5",)
    # Every path passes G5, which may complete or abort with any probability.
    assert (figures.terminals["COMPLETE"].low, figures.terminals["COMPLETE"].high) == (0, 1)
    assert figures.expected["energy_wh"].quantiles is None


def test_vehicle_profile_gives_probabilities_per_behaviour() -> None:
    data = json.loads(json.dumps(exemplar()))
    vehicle = data["vehicles"][0]  # type: ignore[index]
    vehicle["p"] = {"area_search": {"succeed": 0.9, "fail": 0.1, "violate": 0}}
    orders = Orders.model_validate(data)
    graph = build_graph(orders)
    given_p = goal_probabilities(orders, graph)
    searching = [g.id for g, p in zip(graph.goals, given_p, strict=True) if p is not None]
    assert searching == [g.id for g in graph.goals if g.behavior == "area_search"]
    assert searching


@pytest.mark.parametrize("p", [
    {"succeed": 0.5, "fail": 0.2, "violate": 0.2},
    {"succeed": 0.5, "fail": 0.6, "violate": 0.0},
    {"succeed": [0.6, 0.5], "fail": 0.2, "violate": 0.2},
    {"succeed": [0.0, 0.2], "fail": [0, 0.2], "violate": [0, 0.2]},
    {"succeed": 1.5, "fail": -0.5, "violate": 0},
    {"succeed": 1.0, "fail": 0.0},
])
def test_bad_probabilities_are_rejected(p: dict[str, object]) -> None:
    with pytest.raises(ValidationError):
        Orders.model_validate({"id": "x", "start": "G1", "goals": [
            {"id": "G1", "p": p, "next": {"succeed": "COMPLETE", "fail": "ABORT",
                                          "violate": "ABORT"}}]})


def test_decimal_probabilities_sum_exactly() -> None:
    Orders.model_validate({"id": "x", "goals": [
        {"id": "G1", "p": {"succeed": 0.1, "fail": 0.2, "violate": 0.7}}]})


def test_each_path_carries_its_probability() -> None:
    orders = with_probabilities(exemplar(), 2)
    graph = build_graph(orders)
    counts = count_paths(graph)
    assert counts is not None
    bounds = path_probability_bounds(orders, graph)
    dists = point_dists(orders)
    total = 0.0
    lines = list(iter_path_lines(graph, counts, probabilities=bounds))
    paths = list(iter_paths(graph, counts, probabilities=bounds))
    assert len(lines) == len(paths) == 75
    for line, path in zip(lines, paths, strict=True):
        data = json.loads(line)
        assert data == path.to_json()
        exact = Fraction(1)
        for goal, outcome in zip(path.goals, path.outcomes, strict=True):
            node = graph.goal_ids.index(goal)
            exact *= dists[node][("succeed", "fail", "violate").index(outcome)]
        assert data["probability"] == pytest.approx(float(exact), rel=1e-12)
        total += data["probability"]
    assert total == pytest.approx(1.0)


def test_paths_without_probabilities_are_unchanged() -> None:
    orders = Orders.model_validate(exemplar())
    graph = build_graph(orders)
    counts = count_paths(graph)
    assert counts is not None
    assert "probability" not in next(iter_path_lines(graph, counts))


def test_interval_paths_carry_bounds() -> None:
    data = with_probabilities(exemplar(), 2).model_dump(mode="json", by_alias=True)
    data["goals"][0]["p"] = {"succeed": [0.5, 0.7], "fail": [0.1, 0.3], "violate": [0.1, 0.3]}
    orders = Orders.model_validate(data)
    graph = build_graph(orders)
    counts = count_paths(graph)
    assert counts is not None
    first = json.loads(next(iter_path_lines(graph, counts,
                                            probabilities=path_probability_bounds(orders, graph))))
    low, high = first["probability"]
    assert 0 < low < high


def test_unknown_start_gives_no_figures() -> None:
    orders = Orders.model_validate({"id": "x", "goals": [
        {"id": "G1", "p": {"succeed": 1, "fail": 0, "violate": 0}}]})
    assert outcome_probabilities(orders, build_graph(orders)) is None


def test_path_bounds_are_attainable() -> None:
    # succeed can only be 0.8 or more, since fail and violate together give at most 0.2.
    orders = Orders.model_validate({"id": "x", "start": "G1", "goals": [
        {"id": "G1", "p": {"succeed": [0.5, 1], "fail": [0, 0.1], "violate": [0, 0.1]},
         "next": {"succeed": "COMPLETE", "fail": "ABORT", "violate": "ABORT"}}]})
    bounds = path_probability_bounds(orders, build_graph(orders))
    assert bounds[0] == ((0.8, 1.0), (0.0, 0.1), (0.0, 0.1))


def test_report_and_command_line_show_the_probabilities(tmp_path: Path) -> None:
    from countersign.verify.report import validate

    from ..cli.test_bad_input import run_cli

    orders = with_probabilities(exemplar(), 1)
    report = validate(orders).to_json()
    assert report["probabilities"]["terminals"]["COMPLETE"] == {"min": 0.61, "max": 0.61}
    assert "probabilities" not in validate(Orders.model_validate(exemplar())).to_json()
    path = tmp_path / "orders.json"
    path.write_text(json.dumps(orders.model_dump(mode="json", by_alias=True, exclude_none=True)))
    text = run_cli("validate", str(path))
    assert "P(COMPLETE) = 0.61" in text.stdout, text.stdout + text.stderr
    lines = run_cli("paths", str(path), "--limit", "1").stdout.splitlines()
    assert json.loads(lines[0])["probability"] == pytest.approx(0.0227259648)


def test_expectations_past_the_largest_double_read_as_the_largest_double() -> None:
    """Two goals of 1e308 Wh: every figure is finite in JSON (which has no infinity)."""
    sure = {"succeed": 1, "fail": 0, "violate": 0}
    orders = Orders.model_validate({"id": "huge", "start": "G0", "goals": [
        {"id": "G0", "p": sure, "cost": {"energy_wh": 1e308},
         "next": dict.fromkeys(("succeed", "fail", "violate"), "G1")},
        {"id": "G1", "p": sure, "cost": {"energy_wh": 1e308},
         "next": {"succeed": "COMPLETE", "fail": "ABORT", "violate": "ABORT"}}]})
    figures = outcome_probabilities(orders, build_graph(orders))
    assert figures is not None
    energy = figures.to_json()["expected"]["energy_wh"]  # type: ignore[index]
    assert energy["min"] == energy["max"] == sys.float_info.max
    assert set(energy["quantiles"].values()) == {sys.float_info.max}
    assert any("1.79769e+308" in line for line in summary_lines(figures))


@settings(max_examples=40, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(st.integers(0, 2**32), st.integers(1, 60), st.sampled_from([160, 40, 4]))
def test_the_fixed_point_pass_reports_what_the_exact_pass_reports(
        seed: int, goals: int, bits: int) -> None:
    """Figures from the linear fixed-point pass are the exact pass's, double for
    double, on random DAGs with point, interval and missing probabilities and legs. At 40 and
    4 bits the enclosure rarely (4: never) decides the double, so the exact fallback must."""
    rng = random.Random(seed)
    orders = random_orders(rng, goals, kinds=("point", "point", "interval", "none"),
                           places=rng.random() < 0.5, terminals=rng.randint(1, 3))
    graph = build_graph(orders)
    exact = outcome_probabilities(orders, graph, fast=False)
    with pytest.MonkeyPatch.context() as patch:
        patch.setattr(probability, "FIXED_BITS", bits)
        fast = outcome_probabilities(orders, graph)
    assert exact is not None and fast is not None
    assert fast.to_json() == exact.to_json()
