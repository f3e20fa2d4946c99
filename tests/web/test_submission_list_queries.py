"""The submission list reads a fixed number of queries however many submissions it shows (no
query per submission for its version, its people or its log entries), and each submission
still shows the state its log entries give it."""

from __future__ import annotations

from typing import Any

from sqlalchemy import text

from .approval_helpers import new_version, statements_run, submit
from .conftest import World


def _list(world: World) -> tuple[list[dict[str, Any]], int]:
    client = world.client("auditor")
    client.get("/api/submissions")  # the token and the report cache warm, as for any page
    with statements_run(world) as statements:
        response = client.get("/api/submissions")
    assert response.status_code == 200, response.text
    return response.json(), len(statements)


def _withdraw(world: World, submission: int) -> None:
    response = world.client("operator").post(f"/api/submissions/{submission}/withdraw")
    assert response.status_code == 200, response.text


def test_the_submission_list_costs_the_same_for_one_or_many(world: World) -> None:
    first = submit(world, new_version(world))
    one, queries_for_one = _list(world)
    assert [s["id"] for s in one] == [first]
    _withdraw(world, first)
    made = [first]
    for _ in range(4):
        made.append(submit(world, new_version(world)))
        _withdraw(world, made[-1])
    made.append(submit(world, new_version(world)))
    many, queries_for_many = _list(world)
    assert [s["id"] for s in many] == made[::-1]
    assert queries_for_many == queries_for_one, (queries_for_one, queries_for_many)
    assert [s["state"] for s in many] == ["submitted"] + ["withdrawn"] * 5
    assert all(s["submitted_by"] == world.usernames["operator"] for s in many)
    assert [s["version"] for s in many] == list(range(6, 0, -1))


def test_each_listed_submission_shows_its_own_log_state(world: World) -> None:
    """Read in one query, the log entries are still told apart per submission: a row changed
    behind the app's back is named on its own submission only (ids 1 and 10 included, whose
    entries contain `"submission":1` as a prefix of each other's)."""
    made = []
    for _ in range(10):
        made.append(submit(world, new_version(world)))
        _withdraw(world, made[-1])
    with world.database.engine.begin() as connection:
        connection.execute(text("UPDATE submissions SET state = 'approved' WHERE id = :id"),
                           {"id": made[0]})
    listed = {s["id"]: s for s in _list(world)[0]}
    assert listed[made[0]]["state"] == "withdrawn"
    assert listed[made[0]]["integrity"] == [
        f"submission {made[0]}: the table says approved, the log says withdrawn"]
    assert all(listed[i]["integrity"] == [] and listed[i]["state"] == "withdrawn"
               for i in made[1:])
