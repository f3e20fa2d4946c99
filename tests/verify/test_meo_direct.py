"""The report's direct route to C1, C2, M6 and M7 (verify.meo.direct) gives the very findings
the MEO route gives for those codes: on every example, every planted violation, and generated
orders full of defects (duplicate ids, scopes naming terminals and the mission, starts that are
not goals, features listing tests, vehicles not targeted)."""

from __future__ import annotations

import copy
from pathlib import Path
from typing import Any

import pytest
from hypothesis import HealthCheck, given, settings
from hypothesis import strategies as st

from countersign.orders.examples import example_names, load_example
from countersign.orders.model import Orders
from countersign.verify.meo.direct import CODES, RULES, meo_only_findings

from ..oracles.meo_route import meo_check
from ..oracles.shape_info import shape_info
from .test_meo import PLANTED, defective_orders, exemplar_data


def assert_same(orders: Orders) -> None:
    expected = [f.to_json() for f in meo_check(orders).findings if f.code in CODES]
    assert [f.to_json() for f in meo_only_findings(orders)] == expected


@pytest.mark.parametrize("name", example_names())
def test_examples(name: str) -> None:
    assert_same(load_example(name))


@pytest.mark.parametrize("index", range(len(PLANTED)))
def test_planted_violations(index: int) -> None:
    data = exemplar_data()
    PLANTED[index][2](data)
    assert_same(Orders.model_validate(data))


@st.composite
def tangled_orders(draw: st.DrawFn) -> Orders:
    """defective_orders, then constraints scoped to the mission with terminals and unknown
    names beside it, features that list the constraints they test, duplicate constraints,
    goals and features, and more than one vehicle."""
    data: dict[str, Any] = draw(defective_orders()).model_dump(mode="json", exclude_unset=True)
    ids = [g["id"] for g in data["goals"]]
    names = [*ids, "COMPLETE", "ABORT", "NOWHERE", "X", data["id"]]
    extra = [{"id": draw(st.sampled_from(["C0", "C1", "K"])),
              "applies_to": draw(st.lists(st.sampled_from(names), max_size=3)),
              "expr": draw(st.sampled_from([None, "depth_m > 2", "ok", "speed < 1"]))}
             for _ in range(draw(st.integers(0, 3)))]
    data["constraints"] = data.get("constraints", []) + extra
    if data["goals"] and draw(st.booleans()):
        data["goals"].append(copy.deepcopy(draw(st.sampled_from(data["goals"]))))
    if data.get("vehicles"):
        features = data["vehicles"][0]["features"]
        for feature in features:
            feature["tests"] = draw(st.lists(st.sampled_from(["C0", "C1", "K", "Z"]), max_size=2))
        if features and draw(st.booleans()):
            features.append(copy.deepcopy(features[0]))
        if draw(st.booleans()):
            data["vehicles"].append({"id": draw(st.sampled_from(["v", "w"])), "features": [
                {"id": "all", "fulfills": ["a", "b", "c"], "measures": ["depth_m", "ok"]}]})
        data["vehicle"] = draw(st.sampled_from(["v", "w", None]))
    for goal in data["goals"]:
        if draw(st.booleans()):
            goal["title"] = draw(st.sampled_from(["", "Survey", goal["id"]]))
    return Orders.model_validate(data)


@settings(max_examples=300, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(tangled_orders())
def test_generated_orders(orders: Orders) -> None:
    assert_same(orders)


@pytest.mark.parametrize("scope", [["COMPLETE"], ["ABORT", "NOWHERE"], ["G1", "COMPLETE"]])
def test_terminals_beside_the_mission_scope(scope: list[str]) -> None:
    """A terminal the mission reaches is in the mission (G10), so a constraint on the mission
    and that terminal breaks no C1; one it does not reach does."""
    data = exemplar_data()
    data["constraints"][6]["applies_to"] = [data["id"], *scope]
    data["goals"][0]["next"]["violate"] = "COMPLETE"
    assert_same(Orders.model_validate(data))
    data["start"] = "COMPLETE"
    assert_same(Orders.model_validate(data))


def test_the_product_has_one_route_to_these_findings() -> None:
    """The shapes route lives under tests/oracles; the product checks C1, C2, M6 and M7 only in
    verify/meo/direct.py (and never runs pySHACL)."""
    import countersign
    import countersign.verify.meo.reasoned as meo

    assert not {"meo_check", "findings_from"} & set(dir(meo))
    backend_meo = Path(meo.__file__).parent
    assert not (backend_meo / "shapes.py").exists()  # the shapes' reading is the tests' (oracles)
    backend = Path(countersign.__file__).parent
    assert [p.name for p in backend.rglob("*.py") if "pyshacl" in p.read_text()] == []


def test_the_rules_cited_are_those_shapes_ttl_names() -> None:
    """direct.py's table of the rules each code cites (kept there so that a validation does not
    parse shapes.ttl with rdflib) is what ontology/shapes.ttl says."""
    assert {code: shape_info()[code].rules for code in CODES} == RULES
