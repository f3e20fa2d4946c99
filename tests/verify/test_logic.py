"""Constraint logic with z3: CONTRADICTION, VACUOUS, NORM, EXPR, timeouts, caching and goal-set
consistency, each with planted defects in otherwise clean orders."""

from __future__ import annotations

import copy
import json
from collections.abc import Callable
from typing import Any

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st
from pydantic import ValidationError

from countersign.orders.examples import example_bytes, example_names, load_example
from countersign.orders.findings import Finding
from countersign.orders.model import Orders
from countersign.verify.logic import (
    LogicCache,
    UnknownIds,
    check_logic,
    core_satisfiable,
    explain_goal_set,
    format_goal_set,
)

EXEMPLAR: dict[str, Any] = json.loads(example_bytes("search-and-sample"))


def variant(change: Callable[[dict[str, Any]], None], base: dict[str, Any] = EXEMPLAR) -> Orders:
    data = copy.deepcopy(base)
    change(data)
    return Orders.model_validate(data)


def goal(data: dict[str, Any], goal_id: str) -> dict[str, Any]:
    return next(g for g in data["goals"] if g["id"] == goal_id)


def only(findings: list[Finding], code: str) -> list[Finding]:
    return [f for f in findings if f.code == code]


# The built-in examples stay clean ---------------------------------------------------------------


@pytest.mark.parametrize("name", example_names())
def test_examples_have_no_logic_findings(name: str) -> None:
    assert check_logic(load_example(name)) == []


def test_exemplar_c4_holds_for_every_goal_in_scope_only_through_either_branch() -> None:
    # Each goal of C4's scope can keep C4 by depth alone; with the depth branch closed the
    # lane branch must still be open, and it is: nothing bounds lane distance.
    def shallow(data: dict[str, Any]) -> None:
        for gid in ("G1", "G2", "G3", "G4"):
            goal(data, gid)["envelope"] = {"depth_m": [0, 5]}

    assert check_logic(variant(shallow)) == []


# CONTRADICTION ----------------------------------------------------------------------------------


def test_goal_envelope_against_a_constraint_in_scope() -> None:
    orders = variant(lambda d: goal(d, "G5").update(envelope={"depth_m": [0, 5]}))
    [finding] = check_logic(orders)
    assert finding.code == "CONTRADICTION" and finding.severity == "error"
    assert finding.subjects == ("G5", "C7")
    assert finding.message == (
        "G5 Return to Base is ordered at depth 0-5 m, but C7 requires depth >= 20 m. "
        "G5 cannot run as ordered without violating C7."
    )
    assert [p["key"] for p in finding.details["core"]] == ["env:G5:depth_m", "con:C7"]


def test_mission_constraint_against_the_vehicle() -> None:
    def weak_sonar(data: dict[str, Any]) -> None:
        data["vehicles"][0]["envelope"]["contact_detection_range_m"] = [0, 3000]

    [finding] = check_logic(variant(weak_sonar))
    assert finding.code == "CONTRADICTION"
    assert finding.subjects == ("C5", "remus-100")
    assert finding.message.startswith(
        "C5 requires surface contact detection range >= 5,000 m, but the vehicle REMUS 100 AUV "
        "is limited to surface contact detection range 0-3,000 m."
    )
    # Reported once for the mission, not once per goal.


def test_disjunctive_constraint_satisfiable_through_one_branch_only() -> None:
    # Figure 4, constraint 4: lane standoff OR depth. The depth branch is closed by the
    # envelope, the lane branch by another envelope bound: only then is C4 violated.
    def lane_only(data: dict[str, Any]) -> None:
        goal(data, "G1")["envelope"] = {"depth_m": [0, 5], "lane_distance_m": [1000, 3000]}

    def neither(data: dict[str, Any]) -> None:
        goal(data, "G1")["envelope"] = {"depth_m": [0, 5], "lane_distance_m": [0, 500]}

    assert check_logic(variant(lane_only)) == []
    [finding] = check_logic(variant(neither))
    assert finding.subjects == ("G1", "C4")
    assert finding.message.startswith(
        "G1 Search Area A is ordered at depth 0-5 m and distance to nearest shipping lane "
        "0-500 m, but C4 requires distance to nearest shipping lane >= 1,000 m or depth >= 20 m."
    )
    assert finding.details["minimal"] is True


def test_constraints_in_a_shared_scope_contradicting_each_other_are_reported_once() -> None:
    def clash(data: dict[str, Any]) -> None:
        data["constraints"].append(
            {"id": "C8", "applies_to": ["G1", "G2"], "expr": "nav_error_m >= 20"})

    [finding] = check_logic(variant(clash))
    assert finding.subjects == ("C1", "C8", "G1", "G2")
    assert finding.message == (
        "C1 requires navigation error <= 10 m, but C8 requires navigation error >= 20 m. "
        "Goals G1 and G2 cannot run as ordered."
    )


def test_self_contradictory_constraint_and_independent_cores_are_all_found() -> None:
    def two_problems(data: dict[str, Any]) -> None:
        data["constraints"].append(
            {"id": "C8", "applies_to": ["G3"], "expr": "depth_m > 50 and depth_m < 30"})
        goal(data, "G3")["envelope"] = {"depth_m": [25, 50], "altitude_m": [0, 2]}
        data["constraints"].append(
            {"id": "C9", "applies_to": ["G3"], "expr": "altitude_m >= 3"})

    findings = check_logic(variant(two_problems))
    messages = sorted(f.message for f in findings)
    assert len(findings) == 2
    assert any("C8 requires depth > 50 m and depth < 30 m, which can never hold" in m
               for m in messages)
    assert any("altitude above the seabed 0-2 m, but C9 requires" in m for m in messages)


def test_envelope_against_quantity_domain() -> None:
    orders = variant(lambda d: goal(d, "G4").update(envelope={"depth_m": [20, 40],
                                                              "nav_error_m": [-5, -1]}))
    [finding] = check_logic(orders)
    assert finding.subjects == ("G4", "nav_error_m")
    assert finding.message == (
        "G4 Rendezvous with vehicle 2 in Area C is ordered at navigation error -5 to -1 m, but "
        "navigation error is never below 0 m. G4 cannot run as ordered."
    )


# VACUOUS ----------------------------------------------------------------------------------------


def test_constraint_guaranteed_by_the_vehicle_is_vacuous() -> None:
    def typo(data: dict[str, Any]) -> None:
        data["constraints"].append(
            {"id": "C8", "applies_to": "mission", "expr": "depth_m <= 1000"})

    [finding] = check_logic(variant(typo))
    assert finding.code == "VACUOUS" and finding.severity == "warning"
    assert finding.subjects == ("C8", "remus-100")
    assert "the vehicle REMUS 100 AUV is limited to depth 0-100 m" in finding.message


def test_tautology_is_vacuous_and_a_monitor_within_the_goal_envelope_is_not() -> None:
    def tautology(data: dict[str, Any]) -> None:
        data["constraints"].append(
            {"id": "C8", "applies_to": ["G5"], "expr": "nav_error_m < 3 or nav_error_m >= 3"})

    [finding] = check_logic(variant(tautology))
    assert finding.code == "VACUOUS" and finding.subjects == ("C8",)
    assert "holds whatever the vehicle does" in finding.message
    # C7 (depth >= 20 on G5 ordered at 20-60 m) is implied by the orders, not by the vehicle:
    # it is a real monitor and must not be flagged.
    assert not only(check_logic(load_example("search-and-sample")), "VACUOUS")


# NORM (seed 002) --------------------------------------------------------------------------------


def protected(data: dict[str, Any]) -> None:
    next(a for a in data["areas"] if a["id"] == "A")["contexts"].append("marine_protected_area")


def test_sampling_is_refused_in_a_protected_area_and_accepted_elsewhere() -> None:
    assert check_logic(load_example("search-and-sample")) == []
    [finding] = check_logic(variant(protected))
    assert finding.code == "NORM" and finding.severity == "error"
    assert finding.subjects == ("G2", "N1", "marine_protected_area")
    assert finding.message == (
        "Refusal: G2 Take environmental sample from Area A cannot run as ordered without "
        "breaking N1 (No sampling inside a marine protected area). G2 Take environmental "
        "sample from Area A has behavior 'sample' and Area A is a marine protected area, but "
        "N1 forbids the behavior 'sample' in a marine protected area."
    )
    kinds = sorted(p["kind"] for p in finding.details["core"])
    assert kinds == ["behavior", "context", "norm"]
    # The same order in Area B (not protected) is accepted.
    def elsewhere(data: dict[str, Any]) -> None:
        protected(data)
        goal(data, "G2")["area"] = "B"

    assert check_logic(variant(elsewhere)) == []


def test_a_permission_is_an_exception_to_a_prohibition() -> None:
    def permitted(data: dict[str, Any]) -> None:
        protected(data)
        next(a for a in data["areas"] if a["id"] == "A")["contexts"].append("research_zone")
        data["norms"].append({"id": "N2", "context": "research_zone",
                              "permitted": "behavior == 'sample'", "text": "Research permit"})

    assert check_logic(variant(permitted)) == []


@pytest.mark.parametrize("permit_context", ["research_zone", "depth_m > 1000"])
def test_a_permission_excuses_nothing_where_its_own_context_does_not_hold(
    permit_context: str,
) -> None:
    """The permit holds in Area B (or at a depth no goal is ordered to): sampling in the
    protected Area A stays forbidden, so the permission's context must be part of the
    exception and not only its permitted behaviour."""
    def permitted_elsewhere(data: dict[str, Any]) -> None:
        protected(data)
        next(a for a in data["areas"] if a["id"] == "B")["contexts"].append("research_zone")
        data["norms"].append({"id": "N2", "context": permit_context,
                              "permitted": "behavior == 'sample'", "text": "Research permit"})

    [finding] = check_logic(variant(permitted_elsewhere))
    assert finding.code == "NORM" and finding.severity == "error"
    assert finding.subjects == ("G2", "N1", "marine_protected_area")
    assert "(unless N2 permits the behavior 'sample'" in finding.message


def test_a_refusal_names_the_prohibition_and_every_permission_that_could_excuse_it() -> None:
    def two_permits(data: dict[str, Any]) -> None:
        protected(data)
        next(a for a in data["areas"] if a["id"] == "B")["contexts"].append("research_zone")
        data["norms"] += [
            {"id": "N2", "context": "research_zone", "permitted": "behavior == 'sample'"},
            {"id": "N3", "context": "depth_m > 1000", "permitted": "area == 'A'"},
        ]

    [finding] = check_logic(variant(two_permits))
    assert finding.subjects == ("G2", "N1", "marine_protected_area")
    assert (
        "N1 forbids the behavior 'sample' in a marine protected area (unless N2 permits the "
        "behavior 'sample' in a research zone or N3 permits area is 'A' when depth > 1,000 m)"
    ) in finding.message


def test_an_edited_permission_is_rechecked_through_the_cache() -> None:
    """A permission is part of every prohibition it may excuse: the cached result of a goal
    must not outlive an edit of a permission's context (here one that reads the same
    quantity, so the goal's facts stay the same and only N1's exception differs)."""
    def permit(context: str) -> Callable[[dict[str, Any]], None]:
        def change(data: dict[str, Any]) -> None:
            protected(data)
            data["norms"].append({"id": "N2", "context": context,
                                  "permitted": "behavior == 'sample'"})
        return change

    cache = LogicCache()
    assert check_logic(variant(permit("depth_m >= 0")), cache) == []
    [finding] = check_logic(variant(permit("depth_m > 1000")), cache)
    assert finding.subjects == ("G2", "N1", "marine_protected_area")


def test_every_norm_is_judged_on_its_own_breach() -> None:
    """A refusal, two obligations whose breach depends on depth (each with its own witness)
    and a permission that concerns none of them: nothing of one norm leaks into another."""
    def many(data: dict[str, Any]) -> None:
        protected(data)
        next(a for a in data["areas"] if a["id"] == "C")["contexts"].append("shipping_lane")
        goal(data, "G4")["envelope"] = {"depth_m": [20, 40]}
        data["norms"] += [
            {"id": "N2", "context": "shipping_lane", "obligated": "depth_m >= 30"},
            {"id": "N3", "context": "shipping_lane", "obligated": "depth_m <= 35"},
            {"id": "N4", "context": "research_zone", "permitted": "behavior == 'sample'"},
        ]

    findings = {f.subjects[:2]: f for f in check_logic(variant(many))}
    assert sorted(findings) == [("G2", "N1"), ("G4", "N2"), ("G4", "N3")]
    assert findings[("G2", "N1")].severity == "error"
    low, high = findings[("G4", "N2")], findings[("G4", "N3")]
    assert low.severity == high.severity == "warning"
    assert float(low.details["witness"]["depth_m"]) < 30
    assert float(high.details["witness"]["depth_m"]) > 35
    # An obligation has no exception: a permission is no part of its wording.
    assert "unless" not in low.message and "unless" not in high.message


def test_obligation_forced_by_the_envelope_is_refused_and_one_merely_allowed_is_a_warning() -> None:
    def lane(data: dict[str, Any], low: int) -> None:
        next(a for a in data["areas"] if a["id"] == "C")["contexts"].append("shipping_lane")
        goal(data, "G4")["envelope"] = {"depth_m": [low, 40]}
        data["norms"].append({"id": "N2", "context": "shipping_lane",
                              "obligated": "depth_m >= 30", "text": "Stay deep in the lane"})

    def shallow(data: dict[str, Any]) -> None:
        lane(data, 20)
        goal(data, "G4")["envelope"] = {"depth_m": [20, 25]}

    [refusal] = check_logic(variant(shallow))
    assert refusal.code == "NORM" and refusal.severity == "error"
    assert refusal.subjects == ("G4", "N2", "shipping_lane")
    assert "ordered at depth 20-25 m" in refusal.message
    assert "N2 requires depth >= 30 m in a shipping lane" in refusal.message

    [risk] = check_logic(variant(lambda d: lane(d, 20)))
    assert risk.code == "NORM" and risk.severity == "warning"
    assert risk.subjects == ("G4", "N2", "shipping_lane")
    assert float(risk.details["witness"]["depth_m"]) < 30

    # A constraint that keeps the goal deep enough rules the breach out.
    def monitored(data: dict[str, Any]) -> None:
        lane(data, 20)
        data["constraints"].append({"id": "C8", "applies_to": ["G4"], "expr": "depth_m >= 30"})

    assert check_logic(variant(monitored)) == []


def test_norm_with_an_expression_context() -> None:
    def surfacing(data: dict[str, Any]) -> None:
        data["norms"].append({"id": "N2", "context": "depth_m < 2 and context('coastal')",
                              "forbidden": "behavior == 'area_search'",
                              "text": "No searching at the surface near the coast"})
        goal(data, "G3")["envelope"] = {"depth_m": [0, 1]}
        data["constraints"] = [c for c in data["constraints"] if c["id"] != "C4"]

    [finding] = check_logic(variant(surfacing))
    assert finding.code == "NORM" and finding.subjects[:2] == ("G3", "N2")
    assert "coastal" in finding.subjects


def test_conflicting_norms_are_reported_together() -> None:
    def conflict(data: dict[str, Any]) -> None:
        protected(data)
        data["norms"].append({"id": "N2", "context": "marine_protected_area",
                              "obligated": "behavior == 'sample'"})

    findings = check_logic(variant(conflict))
    refusals = [f for f in findings if f.code == "NORM" and f.severity == "error"]
    assert {f.subjects[0] for f in refusals} == {"G1", "G2"}


# EXPR ------------------------------------------------------------------------------------------


def test_expression_errors_are_findings_with_positions() -> None:
    def broken(data: dict[str, Any]) -> None:
        data["constraints"][3]["expr"] = "lane_distance_m >= 1000 or depth_m >="
        data["constraints"][0]["expr"] = "nav_eror_m <= 10"
        data["norms"][0]["forbidden"] = "behavior = 'sample'"

    findings = check_logic(variant(broken))
    assert [f.message for f in only(findings, "EXPR")] == [
        "C1, column 1: unknown quantity 'nav_eror_m' (did you mean 'nav_error_m'?)",
        "C4, column 38: expected a value after '>='",
        "N1 forbidden, column 10: '=' is not an operator here; use ==",
    ]
    assert all(f.severity == "error" for f in findings)
    assert only(findings, "EXPR")[1].details["column"] == 38


# Solver hygiene and bad input -----------------------------------------------------------------


def test_extreme_numbers_and_long_expressions_never_crash() -> None:
    def extreme(data: dict[str, Any]) -> None:
        goal(data, "G1")["envelope"] = {"depth_m": [25, 1e308], "nav_error_m": [-1e308, 0]}
        # Non-finite bounds are refused by the model itself (see below).
        goal(data, "G2")["envelope"] = {"depth_m": [-1.7e308, 1.7e308]}
        goal(data, "G3")["envelope"] = {"depth_m": [5e-324, 40]}
        data["constraints"].append({
            "id": "C8", "applies_to": ["G4"],
            "expr": " + ".join(["depth_m"] * 900) + " >= 1e30"})
        data["constraints"].append({
            "id": "C9", "applies_to": ["G5"], "expr": "depth_m * depth_m * depth_m > 1e30"})

    # The solver's own budget bounds this; the time taken is in tests/bench/bench_fail_fast.py.
    findings = check_logic(variant(extreme), timeout_ms=500, total_timeout_s=10)
    by_subject = {f.subjects[0]: f for f in findings}
    # 900 depths add up to at most 36,000 m in G4's envelope: not 10^30.
    assert by_subject["G4"].code == "CONTRADICTION"
    assert "C8" in by_subject["G4"].subjects
    assert "G5" in by_subject and "C9" in by_subject["G5"].subjects


@pytest.mark.parametrize("bound", [float("inf"), float("-inf"), float("nan")])
def test_non_finite_envelope_bounds_are_refused_by_the_model(bound: float) -> None:
    def infinite(data: dict[str, Any]) -> None:
        goal(data, "G2")["envelope"] = {"depth_m": [0, bound]}

    with pytest.raises(ValidationError, match="finite"):
        variant(infinite)




def test_a_hard_constraint_times_out_as_a_finding() -> None:
    def hard(data: dict[str, Any]) -> None:
        data["quantities"].update({n: {"type": "integer", "min": 2} for n in ("xa", "xb", "xc")})
        data["constraints"].append({
            "id": "C8", "applies_to": ["G1"],
            "expr": "xa * xa * xa * xa + xb * xb * xb * xb == xc * xc * xc * xc",
        })

    # The solver's own budget bounds this; the time taken is in tests/bench/bench_fail_fast.py.
    findings = check_logic(variant(hard), timeout_ms=200, total_timeout_s=5)
    undecided = [f for f in findings if f.details.get("undecided")]
    assert undecided and all(f.severity == "warning" for f in undecided)
    assert any("G1" in f.subjects for f in undecided)


def test_total_time_budget_bounds_a_run() -> None:
    orders = variant(lambda d: goal(d, "G5").update(envelope={"depth_m": [0, 5]}))
    findings = check_logic(orders, total_timeout_s=0)
    assert findings and all(f.severity == "warning" for f in findings)
    assert any("ran out of time" in f.message or "could not decide" in f.message
               for f in findings)


def test_cache_rechecks_only_what_an_edit_touches() -> None:
    cache = LogicCache()
    first = check_logic(load_example("search-and-sample"), cache)
    assert first == []
    solved = cache.misses
    assert solved == 1 + 5 + 7  # mission, five goals, seven constraints (VACUOUS)
    check_logic(load_example("search-and-sample"), cache)
    assert cache.misses == solved  # nothing changed: nothing solved
    edited = variant(lambda d: goal(d, "G2").update(envelope={"depth_m": [26, 50]}))
    check_logic(edited, cache)
    assert cache.misses == solved + 1  # only G2
    shallow = variant(lambda d: goal(d, "G5").update(envelope={"depth_m": [0, 5]}))
    assert len(check_logic(shallow, cache)) == 1
    assert len(check_logic(shallow, cache)) == 1  # the cached result reads the same


# Goal sets (seed 001, 5.4.2) --------------------------------------------------------------------


def test_goal_set_reports_a_minimal_incompatible_subset() -> None:
    orders = variant(lambda d: goal(d, "G5").update(envelope={"depth_m": [0, 5]}))
    result = explain_goal_set(orders, ["G1", "G5"])
    assert result.consistent is False
    assert result.core_goals == ("G5",) and result.core_constraints == ("C7",)
    assert result.explanation == "G5 Return to Base is ordered at depth 0-5 m, but C7 requires " \
        "depth >= 20 m."
    assert "Minimal incompatible subset: G5, C7" in format_goal_set(result)
    assert result.to_json()["core"] == {"goals": ["G5"], "constraints": ["C7"],
                                         "background": []}
    # Without C7, the same goals are consistent, with a witness state per goal.
    fine = explain_goal_set(orders, ["G1", "G5"], ["C1", "C4"])
    assert fine.consistent is True
    assert float(fine.witness["G5"]["depth_m"]) <= 5


def test_goal_set_with_the_vehicle_in_the_explanation() -> None:
    def weak_sonar(data: dict[str, Any]) -> None:
        data["vehicles"][0]["envelope"]["contact_detection_range_m"] = [0, 3000]

    result = explain_goal_set(variant(weak_sonar), ["G2"])
    assert result.consistent is False
    assert result.core_goals == () and result.core_constraints == ("C5",)
    assert result.background == (
        "the vehicle REMUS 100 AUV is limited to surface contact detection range 0-3,000 m",)


def test_goal_set_rejects_unknown_ids_and_notes_inapplicable_constraints() -> None:
    orders = load_example("search-and-sample")
    with pytest.raises(UnknownIds, match="G9, C99"):
        explain_goal_set(orders, ["G1", "G9"], ["C99"])
    result = explain_goal_set(orders, ["G5"], ["C7", "C3"])
    assert result.consistent is True and result.not_applicable == ("C3",)
    broken = variant(lambda d: d["constraints"][6].update(expr="depth_m >= "))
    result = explain_goal_set(broken, ["G5"])
    assert result.consistent is True and "C7" not in result.constraints
    assert [f.message for f in result.findings] == ["C7, column 12: expected a value after '>='"]


# Minimality (property test) ----------------------------------------------------------------------

QUANTITY_NAMES = ["depth_m", "altitude_m", "nav_error_m"]


@st.composite
def small_orders(draw: st.DrawFn) -> Orders:
    def interval() -> list[int]:
        low = draw(st.integers(0, 60))
        return [low, low + draw(st.integers(0, 40))]

    def atom() -> str:
        name = draw(st.sampled_from(QUANTITY_NAMES))
        op = draw(st.sampled_from([">=", "<=", ">", "<"]))
        if draw(st.booleans()):
            other = draw(st.sampled_from(QUANTITY_NAMES))
            return f"{name} + {other} {op} {draw(st.integers(0, 120))}"
        return f"{name} {op} {draw(st.integers(0, 100))}"

    goals = []
    for index in range(draw(st.integers(1, 3))):
        names = draw(st.lists(st.sampled_from(QUANTITY_NAMES), min_size=1, max_size=3,
                              unique=True))
        goals.append({"id": f"G{index}", "envelope": {n: interval() for n in names},
                      "next": {"succeed": "COMPLETE", "fail": "ABORT", "violate": "ABORT"}})
    constraints = []
    for index in range(draw(st.integers(1, 6))):
        expr = atom()
        if draw(st.booleans()):
            expr = f"{expr} {draw(st.sampled_from(['and', 'or']))} {atom()}"
        scope: str | list[str] = "mission" if draw(st.booleans()) else sorted(
            draw(st.sets(st.sampled_from([g["id"] for g in goals]), min_size=1)))
        constraints.append({"id": f"C{index}", "applies_to": scope, "expr": expr})
    return Orders.model_validate({
        "id": "random", "start": "G0", "goals": goals, "constraints": constraints,
        "vehicle": "v", "vehicles": [{"id": "v", "envelope": {"depth_m": [0, 80]}}],
    })


@settings(max_examples=60, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(small_orders())
def test_every_reported_core_is_minimal(orders: Orders) -> None:
    for finding in check_logic(orders):
        if finding.code not in {"CONTRADICTION", "VACUOUS"}:
            continue
        keys = [part["key"] for part in finding.details["core"]]
        assert core_satisfiable(orders, keys) is False, finding.message
        for index in range(len(keys)):
            rest = keys[:index] + keys[index + 1:]
            assert core_satisfiable(orders, rest) is True, (finding.message, keys[index])


@settings(max_examples=40, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(small_orders())
def test_every_incompatible_goal_set_is_minimal(orders: Orders) -> None:
    result = explain_goal_set(orders)
    # A core without goals (constraints against the vehicle) is covered above.
    if result.consistent is not False or not result.core_goals:
        return
    goals = list(result.core_goals)
    constraints = list(result.core_constraints)
    # Asking about exactly the reported subset: incompatible; without any one element: not.
    assert explain_goal_set(orders, goals, constraints).consistent is False
    for index in range(len(constraints)):
        rest = constraints[:index] + constraints[index + 1:]
        assert explain_goal_set(orders, goals, rest).consistent is True
    for index in range(len(goals)):
        rest_goals = goals[:index] + goals[index + 1:]
        assert explain_goal_set(orders, rest_goals, constraints).consistent is True
