"""The approval history reads a fixed number of queries however many approvals a page shows
(no query per approval for its version, its people or its log entry), and each listed approval
is still checked against its own log entry."""

from __future__ import annotations

from typing import Any

from .approval_helpers import (
    approve,
    bypass_triggers,
    new_version,
    register_key,
    statements_run,
    submit,
)
from .conftest import World


def _history(world: World) -> tuple[list[dict[str, Any]], int]:
    client = world.client("auditor")
    client.get("/api/approvals")  # the token warm, as for any page
    with statements_run(world) as statements:
        response = client.get("/api/approvals")
    assert response.status_code == 200, response.text
    return response.json()["items"], len(statements)


def _decide(world: World, count: int) -> list[int]:
    supervisor = world.client("supervisor")
    signer = register_key(supervisor, name=f"key-{count}")
    made = []
    for i in range(count):
        decision = "approved" if i % 2 else "rejected"
        made.append(approve(world, supervisor, signer, submit(world, new_version(world)),
                            decision=decision, reason=f"reason {i}")["id"])
    return made


def test_the_approval_history_costs_the_same_for_one_or_many(world: World) -> None:
    first = _decide(world, 1)
    one, queries_for_one = _history(world)
    assert [a["id"] for a in one] == first
    made = first + _decide(world, 5)
    many, queries_for_many = _history(world)
    assert [a["id"] for a in many] == made[::-1]
    assert queries_for_many == queries_for_one, (queries_for_one, queries_for_many)
    assert all(a["operator"] == world.usernames["operator"] for a in many)
    assert all(a["supervisor"] == world.usernames["supervisor"] for a in many)
    assert [a["version"] for a in many] == list(range(6, 0, -1))
    assert [a["log_index"] for a in many] == sorted((a["log_index"] for a in many), reverse=True)
    assert all(a["integrity"] == [] for a in many)


def test_each_listed_approval_is_checked_against_its_own_log_entry(world: World) -> None:
    made = _decide(world, 3)
    bypass_triggers(world.database, "approvals",
                    "UPDATE approvals SET reason = 'forged' WHERE id = :id", id=made[1])
    listed = {a["id"]: a for a in _history(world)[0]}
    assert listed[made[1]]["integrity"] != []
    assert any("reason" in problem for problem in listed[made[1]]["integrity"])
    assert listed[made[0]]["integrity"] == [] and listed[made[2]]["integrity"] == []
    detail = world.client("auditor").get(f"/api/approvals/{made[1]}").json()
    assert detail["integrity"] == listed[made[1]]["integrity"]
