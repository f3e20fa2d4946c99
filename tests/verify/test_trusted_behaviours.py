"""A vehicle's trusted behaviours as DESIGN.md defines them: its `behaviors` list when the profile
gives one, otherwise the behaviours its features fulfil. M7 (seed 000 III.D), the plain orders
and the contingency rules' do_safe check all read the same rule.

The DESIGN.md example is read from /work/shared/DESIGN.md when it is there; a verbatim copy in
tests/verify/data keeps the tests running without it, and a test keeps the two identical.
"""

from __future__ import annotations

import copy
import json
import re
from pathlib import Path
from typing import Any

import pytest

from countersign.orders.model import Orders, Vehicle
from countersign.orders.plain import plain_orders
from countersign.orders.profile import trusted_behaviors
from countersign.rules import theory_for
from countersign.rules.design import design_findings
from countersign.verify import validate

DESIGN = Path(__file__).resolve().parents[2].parent / "shared" / "DESIGN.md"
FIXTURE = Path(__file__).resolve().parent / "data" / "design-example-orders.json"
_BLOCK = re.compile(r"^## Orders format[^\n]*\n```json\n(.*?)^```", re.S | re.M)


def _from_design() -> dict[str, Any]:
    if not DESIGN.is_file():
        pytest.skip(f"{DESIGN} is absent: the DESIGN.md example is checked from the fixture copy")
    found = _BLOCK.search(DESIGN.read_text(encoding="utf-8"))
    assert found is not None, f"{DESIGN} has no JSON block under '## Orders format'"
    data: dict[str, Any] = json.loads(found.group(1))
    return data


def _from_fixture() -> dict[str, Any]:
    data: dict[str, Any] = json.loads(FIXTURE.read_text(encoding="utf-8"))
    return data


@pytest.fixture(params=["DESIGN.md", "fixture"])
def design_example(request: pytest.FixtureRequest) -> dict[str, Any]:
    return _from_design() if request.param == "DESIGN.md" else _from_fixture()


def _m7(data: dict[str, Any]) -> list[tuple[tuple[str, ...], tuple[str, ...], str]]:
    """Each M7 finding as (subjects, rules, message)."""
    return [(f.subjects, tuple(f.details.get("rules", ())), f.message)
            for f in validate(Orders.model_validate(data)).findings if f.code == "M7"]


def _behaviour_m7(data: dict[str, Any]) -> list[tuple[tuple[str, ...], str]]:
    return [(subjects, message) for subjects, rules, message in _m7(data) if "III.D" in rules]


def test_fixture_is_the_design_example_verbatim() -> None:
    assert _from_design() == _from_fixture()


def test_design_example_profile_without_behaviors_trusts_what_its_features_fulfil(
    design_example: dict[str, Any],
) -> None:
    (profile,) = design_example["vehicles"]
    assert "behaviors" not in profile
    assert trusted_behaviors(Vehicle.model_validate(profile)) == ["transit"]


def test_design_example_orders_get_m7_only_for_what_its_features_cannot_do(
    design_example: dict[str, Any],
) -> None:
    # DESIGN.md's example profile has one feature, fulfilling `transit`, while G1 is an
    # `area_search` that requires `area_search`. By DESIGN.md's own rules G1 is then M7 twice
    # (unmet requirement, V3/V5; behaviour not trusted, III.D); what the profile lacking a
    # `behaviors` list may no longer do is make the vehicle trust nothing.
    assert [(s, r) for s, r, _ in _m7(design_example)] == [
        (("G1", "remus-100"), ("M7", "V5")), (("G1", "remus-100"), ("M7", "III.D"))]
    ((_, message),) = _behaviour_m7(design_example)
    assert ("its behaviour 'area_search' is not among the vehicle's trusted behaviours "
            "(transit; the profile lists no behaviours, so those its features fulfil)") in message


def test_design_example_with_a_feature_fulfilling_its_goal_has_no_m7(
    design_example: dict[str, Any],
) -> None:
    # The profile the product owner described (features that fulfil area_search, sample, ...;
    # no `behaviors` list): nothing else in the example changed, and no M7 at all.
    data = copy.deepcopy(design_example)
    data["vehicles"][0]["features"][0]["fulfills"] = ["area_search", "sample", "transit"]
    assert "behaviors" not in data["vehicles"][0]
    assert _m7(data) == []
    report = validate(Orders.model_validate(data))
    assert "VEHICLE" not in {f.code for f in report.findings}


def test_explicit_behaviors_list_is_what_the_vehicle_trusts(
    design_example: dict[str, Any],
) -> None:
    # Features can fulfil area_search, but the profile's own list trusts only transit.
    data = copy.deepcopy(design_example)
    data["vehicles"][0]["features"][0]["fulfills"] = ["area_search", "transit"]
    data["vehicles"][0]["behaviors"] = ["transit"]
    ((subjects, message),) = _behaviour_m7(data)
    assert subjects == ("G1", "remus-100")
    assert "its behaviour 'area_search' is not among the vehicle's trusted behaviours (transit)" \
        in message
    data["goals"][0]["behavior"] = "transit"
    assert _behaviour_m7(data) == []


def test_profile_whose_features_fulfil_nothing_trusts_nothing(
    design_example: dict[str, Any],
) -> None:
    data = copy.deepcopy(design_example)
    data["goals"][0]["requires"] = []
    data["vehicles"][0]["features"][0]["fulfills"] = []
    ((subjects, message),) = _behaviour_m7(data)
    assert subjects == ("G1", "remus-100")
    assert ("is not among the vehicle's trusted behaviours (none; the profile lists no "
            "behaviours, so those its features fulfil)") in message


def test_plain_orders_name_the_trusted_behaviours_the_check_used(
    design_example: dict[str, Any],
) -> None:
    text = plain_orders(Orders.model_validate(design_example))
    assert "Trusted behaviours: transit (those its features fulfil)." in text
    data = copy.deepcopy(design_example)
    data["vehicles"][0]["behaviors"] = ["transit", "area_search"]
    text = plain_orders(Orders.model_validate(data))
    assert "Trusted behaviours: transit, area search." in text


def _with_rules(profile: dict[str, Any], action: str) -> Orders:
    data: dict[str, Any] = {
        "id": "m", "vehicle": "v", "start": "G1", "vehicles": [{"id": "v", **profile}],
        "goals": [{"id": "G1", "behavior": "transit",
                   "next": {"succeed": "COMPLETE", "fail": "ABORT", "violate": "ABORT"}}],
        "rules": {"observables": ["leak"], "strict": [
            {"id": "S1", "kind": "safety", "if": ["leak"], "then": f"do_safe({action})"}]},
    }
    return Orders.model_validate(data)


def _unknown_actions(orders: Orders) -> list[str]:
    theory = theory_for(orders)
    assert theory is not None
    return [f.message for f in design_findings(theory, orders)
            if "is not a behaviour the vehicle can carry out" in f.message]


def test_do_safe_actions_are_checked_against_the_same_trusted_behaviours() -> None:
    fulfils = {"features": [{"id": "f", "fulfills": ["transit", "surface"]}]}
    assert _unknown_actions(_with_rules(fulfils, "surface")) == []
    listed = {**fulfils, "behaviors": ["transit"]}
    assert _unknown_actions(_with_rules(listed, "surface")) == [
        "do_safe(surface) is not a behaviour the vehicle can carry out (not among the "
        "behaviours of vehicle v: transit)."]
