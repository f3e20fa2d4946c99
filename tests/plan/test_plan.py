"""Survey planning (seed 001): the exact solver against brute force, infeasibility
with a minimal conflict, draft orders that validate, bad input and the command line."""

from __future__ import annotations

import argparse
import json
import math
from pathlib import Path
from typing import Any

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from countersign import cli
from countersign.cli.plan import add_commands
from countersign.plan import (
    PlanProblem,
    PlanReadError,
    PlanTimeout,
    PlanTooLarge,
    orders_from_plan,
    problem_from_data,
    solve,
)
from countersign.plan.check import check_plan
from countersign.plan.examples import example_problem
from countersign.verify.report import validate

# ---------------------------------------------------------------------------------------------
# Brute force: every sequence of distinct areas, every pass of each, no pruning at all.


def _energy_by_set(problem: PlanProblem) -> dict[frozenset[str], float]:
    """The least energy of a plan surveying exactly each set of areas, by enumerating every
    order and pass choice (depth first, each partial sequence extended by every unused area)."""
    rate = problem.vehicle.transit_wh_per_m
    areas = problem.areas
    options = [
        area.passes[:1] if problem.level == 1 else area.passes for area in areas
    ]
    best: dict[frozenset[str], float] = {}

    def visit(used: frozenset[str], position: tuple[float, float], spent: float) -> None:
        total = spent + rate * math.hypot(
            problem.recovery[0] - position[0], problem.recovery[1] - position[1]
        )
        if total < best.get(used, math.inf):
            best[used] = total
        for area, passes in zip(areas, options, strict=True):
            if area.id in used:
                continue
            for pass_ in passes:
                leg = rate * math.hypot(pass_.entry[0] - position[0], pass_.entry[1] - position[1])
                visit(used | {area.id}, pass_.exit, spent + leg + pass_.survey_wh)

    visit(frozenset(), problem.start, 0.0)
    return best


def _oracle(problem: PlanProblem) -> tuple[float, float] | None:
    """(value, energy) of the best feasible plan, or None; the value is the reward unless the
    problem converts energy to the common currency."""
    rewards = {a.id: a.reward for a in problem.areas}
    mandatory = {a.id for a in problem.areas if a.mandatory}
    limit = problem.vehicle.battery_wh - problem.vehicle.reserve_wh
    candidates = [
        (problem.objective(sum(rewards[a] for a in chosen), energy), -energy)
        for chosen, energy in _energy_by_set(problem).items()
        if energy <= limit and mandatory <= chosen
    ]
    if not candidates:
        return None
    value, negative = max(candidates)
    return value, -negative


def _servable(by_set: dict[frozenset[str], float], required: set[str], limit: float) -> bool:
    return any(energy <= limit and required <= chosen for chosen, energy in by_set.items())


def _independent_energy(problem: PlanProblem, order: list[str], passes: dict[str, int]) -> float:
    areas = {a.id: a for a in problem.areas}
    rate = problem.vehicle.transit_wh_per_m
    position, total = problem.start, 0.0
    for area_id in order:
        pass_ = areas[area_id].passes[passes[area_id]]
        total += rate * math.dist(position, pass_.entry) + pass_.survey_wh
        position = pass_.exit
    return total + rate * math.dist(position, problem.recovery)


# ---------------------------------------------------------------------------------------------
# Random problems: small integer grids make ties in reward and energy common.


@st.composite
def problems(
    draw: st.DrawFn, max_areas: int = 5, max_passes: int = 3, level: int | None = None
) -> PlanProblem:
    coordinate = st.tuples(st.integers(0, 100), st.integers(0, 100))
    n = draw(st.integers(0, max_areas))
    areas = []
    for index in range(n):
        passes = [
            {"entry": draw(coordinate), "exit": draw(coordinate),
             "survey_wh": draw(st.integers(0, 60))}
            for _ in range(draw(st.integers(1, max_passes)))
        ]
        areas.append({
            "id": f"A{index}",
            "reward": draw(st.integers(0, 20)),
            "mandatory": draw(st.integers(0, 2)) == 0,
            "passes": passes,
        })
    battery = draw(st.integers(0, 900))
    conversion = draw(st.sampled_from([
        {}, {}, {"energy_wh": {"kind": "linear", "rate": 0.05}},
        {"energy_wh": {"kind": "exponential", "rate": 0.01, "scale": 0.5}},
    ]))
    return problem_from_data({
        "conversion": conversion,
        "format": "countersign.plan/1",
        "level": draw(st.sampled_from([1, 2])) if level is None else level,
        "start": draw(coordinate),
        "recovery": draw(coordinate),
        "vehicle": {"transit_wh_per_m": draw(st.sampled_from([0.5, 1, 2])),
                    "battery_wh": battery, "reserve_wh": draw(st.integers(0, 30))},
        "areas": areas,
    })


def _agrees_with_brute_force(problem: PlanProblem) -> None:
    plan = solve(problem)
    expected = _oracle(problem)
    limit = problem.vehicle.limit_wh
    if expected is None:
        assert not plan.feasible
        by_set = _energy_by_set(problem)
        conflict = set(plan.conflict)
        mandatory = {a.id for a in problem.areas if a.mandatory}
        assert conflict <= mandatory
        assert not _servable(by_set, conflict, limit)
        for member in conflict:  # minimal: without any one member the rest can be served
            assert _servable(by_set, conflict - {member}, limit)
        assert plan.message
        return
    assert plan.feasible, plan.message
    value, energy = expected
    if problem.conversion:
        assert math.isclose(plan.value, value, rel_tol=1e-9, abs_tol=1e-9)
    else:
        assert plan.reward == value == plan.value
    assert math.isclose(plan.energy_wh, energy, rel_tol=1e-9, abs_tol=1e-9)
    # The plan it prints is the plan it costed, by an independent computation.
    assert math.isclose(
        _independent_energy(problem, plan.order, plan.passes), plan.energy_wh,
        rel_tol=1e-9, abs_tol=1e-9,
    )
    assert plan.energy_wh <= limit
    assert {a.id for a in problem.areas if a.mandatory} <= set(plan.order)
    if problem.level == 1:
        assert set(plan.passes.values()) <= {0}
    assert check_plan(problem, plan.order, plan.passes).ok


@settings(max_examples=300, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(problems(max_areas=5, max_passes=3))
def test_solver_matches_brute_force_up_to_5_areas_3_passes(problem: PlanProblem) -> None:
    _agrees_with_brute_force(problem)


@settings(max_examples=40, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(problems(max_areas=7, max_passes=1, level=1))
def test_solver_matches_brute_force_level_1_up_to_7_areas(problem: PlanProblem) -> None:
    _agrees_with_brute_force(problem)


@settings(max_examples=3, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(problems(max_areas=7, max_passes=2, level=2).filter(lambda p: len(p.areas) >= 6))
def test_solver_matches_brute_force_7_areas_2_passes(problem: PlanProblem) -> None:
    _agrees_with_brute_force(problem)


@settings(max_examples=40, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(problems(max_areas=4, max_passes=2))
def test_draft_orders_validate_without_budget_finding(problem: PlanProblem) -> None:
    plan = solve(problem)
    if not plan.feasible:
        with pytest.raises(ValueError):
            orders_from_plan(problem, plan)
        return
    orders = orders_from_plan(problem, plan)
    report = validate(orders)
    assert report.ok, [f.message for f in report.findings]
    assert not [f for f in report.findings if f.code == "BUDGET"]
    assert report.costs is not None
    worst = report.costs["energy_wh"]
    assert math.isclose(worst.total, plan.energy_wh, rel_tol=1e-9, abs_tol=1e-9)
    assert worst.budget == pytest.approx(plan.limit_wh)
    # one goal per chosen area, in order, then the recovery goal
    goals = orders.goals
    assert [g.params["plan_area"] for g in goals[:-1]] == plan.order
    recovery = goals[-1].id
    for index, goal in enumerate(goals[:-1]):
        following = goals[index + 1].id
        assert goal.next == {"succeed": following, "fail": following, "violate": recovery}
    assert goals[-1].next == {"succeed": "COMPLETE", "fail": "ABORT", "violate": "ABORT"}


# ---------------------------------------------------------------------------------------------
# The GRAVITAS scenario (seed 001 section 8)


def test_gravitas_surveys_all_three_areas() -> None:
    problem = example_problem("gravitas")
    plan = solve(problem)
    assert plan.feasible
    assert sorted(plan.order) == ["LL", "LR", "UR"]
    assert plan.reward == 22807 + 51918 + 31313
    assert plan.energy_wh <= 60000 - 2000
    assert _oracle(problem) == (plan.reward, pytest.approx(plan.energy_wh))


def test_gravitas_replan_after_62_percent_rise_keeps_only_lr() -> None:
    problem = example_problem("gravitas-replan")
    plan = solve(problem)
    assert plan.order == ["LR"]  # UR is more rewarding but out of reach
    assert plan.reward == 31313
    assert plan.energy_wh == pytest.approx(27216)  # the paper's anticipated energy for LR
    ur_alone = check_plan(problem, ["UR"], {"UR": 0})
    assert not ur_alone.ok and "more than" in ur_alone.message


def test_common_currency_drops_an_area_not_worth_its_energy() -> None:
    problem = example_problem("gravitas-currency")
    plan = solve(problem)
    assert plan.order == ["UR", "LR"]  # LL's 22807 is worth less than twice its extra Wh
    assert plan.value == pytest.approx(plan.reward - 2 * plan.energy_wh)
    assert _oracle(problem) == (pytest.approx(plan.value), pytest.approx(plan.energy_wh))


def test_exponential_conversion_overflow_is_infinite_cost() -> None:
    data = {"format": "countersign.plan/1", "start": [0, 0], "recovery": [0, 0],
            "vehicle": {"transit_wh_per_m": 1, "battery_wh": 1e6},
            "conversion": {"energy_wh": {"kind": "exponential", "rate": 10}},
            "areas": [_area("A", 1000, mandatory=False, reward=5)]}
    plan = solve(problem_from_data(data))
    assert plan.order == [] and plan.value == 0


def test_level_1_uses_first_pass_only() -> None:
    plan = solve(example_problem("gravitas-level1"))
    assert set(plan.passes.values()) == {0}
    assert plan.energy_wh >= solve(example_problem("gravitas")).energy_wh


# ---------------------------------------------------------------------------------------------
# Infeasible problems


def _problem(areas: list[dict[str, Any]], battery: float, **extra: Any) -> PlanProblem:
    data = {"format": "countersign.plan/1", "level": 2, "start": [0, 0], "recovery": [0, 0],
            "vehicle": {"transit_wh_per_m": 1, "battery_wh": battery}, "areas": areas}
    data.update(extra)
    return problem_from_data(data)


def _area(area_id: str, x: float, mandatory: bool = True, reward: float = 1) -> dict[str, Any]:
    return {"id": area_id, "reward": reward, "mandatory": mandatory,
            "passes": [{"entry": [x, 0], "exit": [x, 0], "survey_wh": 0}]}


def test_infeasible_names_minimal_conflict() -> None:
    # A and B lie on opposite sides 100 m out: each alone costs 200, both together 400.
    problem = _problem(
        [_area("A", 100), _area("B", -100), _area("C", 10), _area("D", 5, mandatory=False)], 300
    )
    plan = solve(problem)
    assert not plan.feasible
    assert plan.conflict == ("A", "B")
    assert "A, B" in plan.message


def test_single_unreachable_mandatory_area() -> None:
    plan = solve(_problem([_area("FAR", 1000), _area("NEAR", 1)], 100))
    assert plan.conflict == ("FAR",)


def test_recovery_out_of_reach_without_any_area() -> None:
    problem = _problem([], 10, recovery=[100, 0])
    plan = solve(problem)
    assert not plan.feasible and plan.conflict == ()
    assert "straight from the start to recovery" in plan.message


def test_empty_plan_when_nothing_fits() -> None:
    plan = solve(_problem([_area("FAR", 1000, mandatory=False)], 100))
    assert plan.feasible and plan.order == [] and plan.reward == 0
    report = validate(orders_from_plan(_problem([], 100), plan))
    assert report.ok


# ---------------------------------------------------------------------------------------------
# Bounds and bad input


def test_too_many_areas_for_the_exact_solver() -> None:
    areas = [
        {"id": f"A{i}", "reward": 1,
         "passes": [{"entry": [i, 0], "exit": [i, 1], "survey_wh": 1}] * 3}
        for i in range(20)
    ]
    with pytest.raises(PlanTooLarge, match="20 areas"):
        solve(_problem(areas, 100))


def test_timeout() -> None:
    areas = [
        {"id": f"A{i}", "reward": 1,
         "passes": [{"entry": [i, 0], "exit": [i, 1], "survey_wh": 1}] * 3}
        for i in range(14)
    ]
    with pytest.raises(PlanTimeout, match="raise the timeout"):
        solve(_problem(areas, 100), timeout_s=0.01)


@pytest.mark.parametrize(
    ("change", "path", "message"),
    [
        ({"format": "countersign.orders/1"}, "$.format", "countersign.plan/1"),
        ({"level": 3}, "$.level", "level must be 1"),
        ({"start": [0]}, "$.start", "a point is two numbers"),
        ({"areas": [{"id": "A", "reward": 1, "passes": [{"entry": [1, 2, 3], "exit": [0, 0],
                                                         "survey_wh": 1}]}]},
         "$.areas[0].passes[0].entry", "a point is two numbers"),
        ({"vehicle": {"transit_wh_per_m": -1, "battery_wh": 1}}, "$.vehicle.transit_wh_per_m",
         "greater than or equal to 0"),
        ({"vehicle": {"transit_wh_per_m": float("nan"), "battery_wh": 1}},
         "$.vehicle.transit_wh_per_m", ""),
        ({"areas": [{"id": "A", "reward": 1, "passes": []}]}, "$.areas[0].passes", ""),
        ({"areas": [{"id": "bad id", "reward": 1, "passes": []}]}, "$.areas[0].id",
         "not a valid id"),
        ({"areas": [_area("A", 1), _area("A", 2)]}, "$", "two areas have the id 'A'"),
        ({"areas": [{**_area("A", 1), "colour": "red"}]}, "$.areas[0].colour", "unknown field"),
        ({"areas": [_area(f"A{i}", i) for i in range(65)]}, "$.areas", "at most 64"),
        ({"recovery": [1e12, 0]}, "$.recovery", "finite metres"),
    ],
)
def test_bad_problems_name_the_json_path(change: dict[str, Any], path: str, message: str) -> None:
    data = {"format": "countersign.plan/1", "level": 2, "start": [0, 0], "recovery": [0, 0],
            "vehicle": {"transit_wh_per_m": 1, "battery_wh": 10}, "areas": []}
    data.update(change)
    with pytest.raises(PlanReadError) as caught:
        problem_from_data(data)
    assert any(p.path == path and message in p.message for p in caught.value.problems), (
        caught.value.summary()
    )


def test_problem_must_be_an_object() -> None:
    with pytest.raises(PlanReadError, match="JSON object, not an array"):
        problem_from_data([])


def test_check_explains_first_violation() -> None:
    problem = example_problem("gravitas")
    assert "not an area" in check_plan(problem, ["XX"], {}).message
    assert "twice" in check_plan(problem, ["LL", "LL"], {}).message
    assert "no pass 5" in check_plan(problem, ["LL"], {"LL": 5}).message
    level1 = example_problem("gravitas-level1")
    assert "level 1" in check_plan(level1, ["LL"], {"LL": 1}).message
    assert check_plan(problem, ["LL", "LR"], {"LL": 0, "LR": 1}).ok


# ---------------------------------------------------------------------------------------------
# The command line (registered through cli_plan.add_commands, as cli.py will)


@pytest.fixture
def run_cli(monkeypatch: pytest.MonkeyPatch) -> Any:
    original = cli.build_parser

    def build_parser(group: str | None = None) -> argparse.ArgumentParser:
        parser = original(group)
        for action in parser._actions:
            if isinstance(action, argparse._SubParsersAction) and "plan" not in action.choices:
                add_commands(action)
        return parser

    monkeypatch.setattr(cli, "build_parser", build_parser)
    return cli.main


def _write(tmp_path: Path, name: str, data: Any) -> str:
    path = tmp_path / name
    path.write_text(json.dumps(data) if not isinstance(data, str) else data)
    return str(path)


def test_cli_plan_json_and_draft_validates(
    run_cli: Any, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    draft = tmp_path / "draft.json"
    assert run_cli(["plan", "example:gravitas-replan", "--format", "json",
                    "--orders-out", str(draft)]) == 0
    output = json.loads(capsys.readouterr().out)
    assert output["order"] == ["LR"] and output["passes"] == {"LR": 0}
    assert output["reward"] == 31313 and output["energy_wh"] == pytest.approx(27216)
    assert output["orders"]["format"] == "countersign.orders/1"
    assert json.loads(draft.read_text()) == output["orders"]
    assert run_cli(["validate", str(draft), "--format", "json"]) == 0
    report = json.loads(capsys.readouterr().out)
    assert report["ok"] and not [f for f in report["findings"] if f["code"] == "BUDGET"]


def test_cli_plan_text(run_cli: Any, capsys: pytest.CaptureFixture[str]) -> None:
    assert run_cli(["plan", "example:gravitas"]) == 0
    out = capsys.readouterr().out
    assert "reward 106038" in out and "then recovery" in out
    assert run_cli(["plan", "example:gravitas-currency"]) == 0
    out = capsys.readouterr().out
    assert "Not surveyed: LL" in out and "common currency" in out


def test_cli_infeasible_exits_1(
    run_cli: Any, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    data = {"format": "countersign.plan/1", "start": [0, 0], "recovery": [0, 0],
            "vehicle": {"transit_wh_per_m": 1, "battery_wh": 300},
            "areas": [_area("A", 100), _area("B", -100)]}
    assert run_cli(["plan", _write(tmp_path, "p.json", data), "--format", "json"]) == 1
    output = json.loads(capsys.readouterr().out)
    assert output["feasible"] is False and output["conflict"] == ["A", "B"]
    assert run_cli(["plan", _write(tmp_path, "p.json", data)]) == 1
    assert "Minimal conflicting mandatory areas: A, B" in capsys.readouterr().out


def test_cli_unreadable_exits_2(
    run_cli: Any, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    assert run_cli(["plan", _write(tmp_path, "p.json", "{not json")]) == 2
    assert "invalid JSON at line 1" in capsys.readouterr().err
    assert run_cli(["plan", _write(tmp_path, "p.json", {"level": 1})]) == 2
    assert "$.start" in capsys.readouterr().err
    assert run_cli(["plan", str(tmp_path / "missing.json")]) == 2
    assert run_cli(["plan", "example:nope"]) == 2
    assert "gravitas" in capsys.readouterr().err


def test_cli_check(run_cli: Any, tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    good = _write(tmp_path, "good.json", {"order": ["LR"], "passes": {"LR": 0}})
    bad = _write(tmp_path, "bad.json", {"order": ["UR"], "passes": {"UR": 0}})
    assert run_cli(["plan", "example:gravitas-replan", "--check", good]) == 0
    assert capsys.readouterr().out.startswith("OK: feasible")
    assert run_cli(["plan", "example:gravitas-replan", "--check", bad]) == 1
    assert "NOT OK" in capsys.readouterr().out
    broken = _write(tmp_path, "broken.json", {"order": "UR"})
    assert run_cli(["plan", "example:gravitas-replan", "--check", broken]) == 2
    assert "$.order" in capsys.readouterr().err


def test_cli_help_explains_the_format(run_cli: Any, capsys: pytest.CaptureFixture[str]) -> None:
    with pytest.raises(SystemExit):
        run_cli(["plan", "--help"])
    text = capsys.readouterr().out
    assert "countersign.plan/1" in text and "mandatory" in text and "exit codes" in text


# ---------------------------------------------------------------------------------------------
# A problem built from the orders' areas and vehicle profile


def test_problem_from_orders_areas_and_vehicle() -> None:
    from countersign.orders.examples import example_bytes
    from countersign.orders.reader import read_bytes
    from countersign.plan.from_orders import CannotBuildProblem, problem_from_orders

    orders = read_bytes(example_bytes("search-and-sample")).orders
    base = orders.area_index()["BASE"].polygon[0]
    problem = problem_from_orders(
        orders, start=base, recovery=base, areas=["A", "B"], rewards={"A": 5, "B": 3},
        mandatory=["A"], swath_m=100, battery_wh=3000,
    )
    assert [a.id for a in problem.areas] == ["A", "B"]
    assert problem.vehicle.transit_wh_per_m == pytest.approx(110 / 1.5 / 3600)
    assert problem.vehicle.battery_wh == 3000
    assert problem.areas[0].mandatory and not problem.areas[1].mandatory
    assert len(problem.areas[0].passes) == 4
    plan = solve(problem)
    assert plan.feasible and "A" in plan.order
    assert _oracle(problem) == (plan.reward, pytest.approx(plan.energy_wh))
    assert validate(orders_from_plan(problem, plan)).ok
    assert problem_from_orders(orders, start=base, recovery=base).vehicle.battery_wh == 1500
    with pytest.raises(CannotBuildProblem, match="no polygon"):
        problem_from_orders(orders, start=base, recovery=base, areas=["NOPE"])


# ---------------------------------------------------------------------------------------------
# An independent cross-check with z3 Optimize on small instances


def _z3_best(problem: PlanProblem) -> tuple[float, float] | None:
    import z3

    areas = problem.areas
    n = len(areas)
    rate = problem.vehicle.transit_wh_per_m
    nodes = [(a, p, pass_) for a, area in enumerate(areas)
             for p, pass_ in enumerate(problem.passes_of(area))]
    opt = z3.Optimize()
    opt.set("timeout", 20_000)
    # slot k holds node index slot[k], or -1 once the plan has ended
    slot = [z3.Int(f"slot{k}") for k in range(n)]
    for k in range(n):
        opt.add(slot[k] >= -1, slot[k] < len(nodes))
        if k:
            opt.add(z3.Implies(slot[k - 1] == -1, slot[k] == -1))
    area_of = {i: node[0] for i, node in enumerate(nodes)}
    for j in range(n):
        for k in range(j + 1, n):
            for u in range(len(nodes)):
                for v in range(len(nodes)):
                    if area_of[u] == area_of[v]:
                        opt.add(z3.Not(z3.And(slot[j] == u, slot[k] == v)))

    def real(value: float) -> z3.ArithRef:
        return z3.RealVal(repr(value))

    def choose(k: int, table: dict[int, float], default: float) -> z3.ArithRef:
        expr: z3.ArithRef = real(default)
        for index, value in table.items():
            expr = z3.If(slot[k] == index, real(value), expr)
        return expr

    home = rate * math.dist(problem.start, problem.recovery)
    if n == 0:
        return (0.0, home) if home <= problem.vehicle.limit_wh else None
    energy: z3.ArithRef = z3.If(slot[0] == -1, real(home), choose(
        0, {i: rate * math.dist(problem.start, p.entry) + p.survey_wh for i, (_, _, p)
            in enumerate(nodes)}, 0.0))
    for k in range(n):
        ends = slot[k + 1] == -1 if k + 1 < n else z3.BoolVal(True)
        back = choose(k, {i: rate * math.dist(p.exit, problem.recovery)
                          for i, (_, _, p) in enumerate(nodes)}, 0.0)
        energy = energy + z3.If(z3.And(slot[k] != -1, ends), back, real(0.0))
        if k + 1 < n:
            legs: z3.ArithRef = real(0.0)
            for u, (_, _, pu) in enumerate(nodes):
                for v, (_, _, pv) in enumerate(nodes):
                    cost = rate * math.dist(pu.exit, pv.entry) + pv.survey_wh
                    legs = z3.If(z3.And(slot[k] == u, slot[k + 1] == v), real(cost), legs)
            energy = energy + legs
    reward: z3.ArithRef = real(0.0)
    for a, area in enumerate(areas):
        chosen = z3.Or([slot[k] == i for k in range(n) for i in range(len(nodes))
                        if area_of[i] == a])
        if area.mandatory:
            opt.add(chosen)
        reward = reward + z3.If(chosen, real(area.reward), real(0.0))
    opt.add(energy <= real(problem.vehicle.limit_wh))
    opt.maximize(reward)
    opt.minimize(energy)
    result = opt.check()
    if result == z3.unsat:
        return None
    assert result == z3.sat
    model = opt.model()

    def number(expr: z3.ArithRef) -> float:
        value = model.eval(expr, model_completion=True)
        return float(value.as_fraction())

    return number(reward), number(energy)


@settings(max_examples=15, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(problems(max_areas=4, max_passes=2).filter(lambda p: not p.conversion))
def test_solver_matches_z3_optimize(problem: PlanProblem) -> None:
    plan = solve(problem)
    expected = _z3_best(problem)
    if expected is None:
        assert not plan.feasible
        return
    assert plan.feasible
    assert plan.reward == pytest.approx(expected[0])
    assert plan.energy_wh == pytest.approx(expected[1], rel=1e-9, abs=1e-9)


@pytest.mark.parametrize("name", ["gravitas", "gravitas-replan", "gravitas-level1"])
def test_gravitas_matches_z3_optimize(name: str) -> None:
    problem = example_problem(name)
    plan = solve(problem)
    assert _z3_best(problem) == (plan.reward, pytest.approx(plan.energy_wh, rel=1e-9))


def test_cli_too_large_exits_2_and_timeout_exits_1(
    run_cli: Any, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    def data(count: int) -> dict[str, Any]:
        return {"format": "countersign.plan/1", "start": [0, 0], "recovery": [0, 0],
                "vehicle": {"transit_wh_per_m": 1, "battery_wh": 100},
                "areas": [{"id": f"A{i}", "reward": 1,
                           "passes": [{"entry": [i, 0], "exit": [i, 1], "survey_wh": 1}] * 3}
                          for i in range(count)]}

    assert run_cli(["plan", _write(tmp_path, "big.json", data(20))]) == 2
    assert "more than the exact planner's limit" in capsys.readouterr().err
    assert run_cli(["plan", _write(tmp_path, "slow.json", data(14)), "--timeout", "0.01"]) == 1
    assert "raise the timeout" in capsys.readouterr().err
