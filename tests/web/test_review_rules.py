"""Contingency rules in plain language where the supervisor reads orders:
the review route, the approval record and the plain-orders export."""

from __future__ import annotations

import json
from typing import Any

from fastapi.testclient import TestClient

from countersign.orders.examples import example_bytes, load_example
from countersign.rules.plain_orders import SECTION, rules_sentences

from .approval_helpers import MISSION, approve, register_key
from .conftest import World

RULES_MISSION = "search-and-sample-rules"


def _create(client: TestClient, orders: dict[str, Any]) -> int:
    created = client.post("/api/missions", json=orders)
    assert created.status_code == 201, created.text
    version = client.post(f"/api/missions/{orders['id']}/versions")
    assert version.status_code == 201, version.text
    return int(version.json()["number"])


def _review(client: TestClient, mission: str, number: int) -> dict[str, Any]:
    response = client.get(f"/api/missions/{mission}/versions/{number}/review")
    assert response.status_code == 200, response.text
    data: dict[str, Any] = response.json()
    return data


def test_review_shows_the_rules_in_plain_language(world: World) -> None:
    operator = world.client("operator")
    number = _create(operator, json.loads(example_bytes(RULES_MISSION)))
    review = _review(world.client("supervisor"), RULES_MISSION, number)
    expected = rules_sentences(load_example(RULES_MISSION))
    assert review["rules"] == expected and len(expected) == 12
    assert any(s.startswith("S_leak_surface (safety rule): If 'safety sensor failure (leak)' "
                            "is true, then surface now.") for s in review["rules"])
    assert SECTION not in review["plain"]  # the plain orders stay as signed; rules beside them

    plain = operator.get(f"/api/missions/{RULES_MISSION}/export", params={"format": "plain"})
    assert plain.status_code == 200
    assert f"\n\n{SECTION}\n\n" in plain.text and expected[-1] + "\n" in plain.text


def test_review_without_rules_has_an_empty_list(world: World) -> None:
    operator = world.client("operator")
    number = int(operator.post(f"/api/missions/{MISSION}/versions").json()["number"])
    assert _review(operator, MISSION, number)["rules"] == []
    plain = operator.get(f"/api/missions/{MISSION}/export", params={"format": "plain"})
    assert SECTION not in plain.text


def test_unreadable_rules_give_an_empty_list_and_a_finding(world: World) -> None:
    operator = world.client("operator")
    orders = json.loads(example_bytes(MISSION))
    orders["id"] = "unreadable-rules"
    orders["rules"] = {"defaults": [{"id": "D1", "kind": "goal", "then": "not a literal("}]}
    number = _create(operator, orders)
    review = _review(operator, "unreadable-rules", number)
    assert review["rules"] == []
    assert any(f["code"] == "RULES" and "cannot be read" in f["message"]
               for f in review["findings"])


def test_the_approval_record_carries_the_rules(world: World) -> None:
    operator = world.client("operator")
    supervisor = world.client("supervisor")
    number = _create(operator, json.loads(example_bytes(RULES_MISSION)))
    submitted = operator.post(f"/api/missions/{RULES_MISSION}/versions/{number}/submit")
    assert submitted.status_code == 201, submitted.text
    approval = approve(world, supervisor, register_key(supervisor), submitted.json()["id"])["id"]
    record = world.client("auditor").get(f"/api/approvals/{approval}")
    assert record.status_code == 200, record.text
    assert record.json()["rules"] == _review(supervisor, RULES_MISSION, number)["rules"] != []
