"""The editor's autosaves are coalesced in the event log, one `draft.updated`
entry per editing burst of one author, saying which items changed; every save still bumps the
revision (the ETag of compare-and-set)."""

from __future__ import annotations

import copy
from datetime import timedelta
from typing import Any

from fastapi.testclient import TestClient
from sqlalchemy import update

from countersign.store.accounts import create_token, create_user
from countersign.store.draft_bursts import BURST, changed_items
from countersign.store.tables import Mission, utcnow

from .conftest import PASSWORD, World, count_rows

DRAFT_EVENTS = "SELECT count(*) FROM events WHERE kind = 'draft.updated' AND mission_id = '{}'"


def _copy(world: World, mission: str) -> dict[str, Any]:
    orders = copy.deepcopy(world.client("operator").get(
        "/api/missions/search-and-sample").json()["orders"])
    orders["id"] = mission
    return orders


def _save(client: Any, mission: str, orders: dict[str, Any]) -> int:
    revision = client.get(f"/api/missions/{mission}").headers["etag"]
    answer = client.put(f"/api/missions/{mission}/draft", json={"orders": orders},
                        headers={"If-Match": revision})
    assert answer.status_code == 200, answer.text
    return int(answer.json()["revision"])


def _drafts(world: World, mission: str) -> list[dict[str, Any]]:
    events = world.client("auditor").get("/api/events", params={"mission": mission}).json()
    return [e for e in events if e["kind"] == "draft.updated"]


def test_one_burst_of_saves_is_one_log_entry_naming_what_changed(world: World) -> None:
    client = world.client("operator")
    mission = "burst-one"
    orders = _copy(world, mission)
    created = client.post("/api/missions", json=orders).json()
    for n in range(10):
        orders["goals"][n % 3]["title"] = f"Title {n}"
        revision = _save(client, mission, orders)
    orders["norms"].append({"id": "N9", "context": "harbour", "permitted": "true"})
    revision = _save(client, mission, orders)
    assert revision == 12  # every save is still a revision: the ETag of compare-and-set
    assert count_rows(world.database, DRAFT_EVENTS.format(mission)) == 0  # the burst is open
    client.post(f"/api/missions/{mission}/versions")  # a version logs the edits before it
    [entry] = _drafts(world, mission)
    assert entry["before_digest"] == created["draft_digest"]
    assert entry["after_digest"] == client.get(f"/api/missions/{mission}").json()["draft_digest"]
    assert entry["detail"]["saves"] == 11
    assert entry["detail"]["from_revision"] == 2 and entry["detail"]["revision"] == 12
    assert entry["detail"]["changed"] == ["goal G1", "goal G2", "goal G3", "norm N9 added"]


def test_another_author_or_a_quiet_pause_ends_the_burst(world: World) -> None:
    with world.database.session() as db:
        other = create_user(db, username="operator2", role="operator", password=PASSWORD,
                            signer=world.database.log_signer)
        token = create_token(db, user=other, name="tests", signer=world.database.log_signer)[1]
    first = world.client("operator")
    second = TestClient(world.app, headers={"Authorization": f"Bearer {token}"})
    mission = "burst-two"
    orders = _copy(world, mission)
    first.post("/api/missions", json=orders)
    orders["title"] = "First's"
    _save(first, mission, orders)
    _save(first, mission, orders | {"title": "First's again"})
    orders["title"] = "Second's"
    _save(second, mission, orders)  # the first author's burst ends here
    assert count_rows(world.database, DRAFT_EVENTS.format(mission)) == 1
    # Two minutes of quiet end the second's burst: the event list shows it.
    with world.database.session() as db:
        db.execute(update(Mission).where(Mission.id == mission)
                   .values(burst_at=utcnow() - BURST - timedelta(seconds=1)))
    drafts = _drafts(world, mission)
    assert [d["actor"] for d in drafts] == ["operator1", "operator2"]
    assert [d["detail"]["saves"] for d in drafts] == [2, 1]
    assert drafts[0]["detail"]["changed"] == ["title"]


def test_changed_items_in_words() -> None:
    before = {"title": "A", "goals": [{"id": "G1", "title": "x"}, {"id": "G2"}],
              "norms": [{"id": "N1"}]}
    after = {"title": "B", "goals": [{"id": "G1", "title": "y"}, {"id": "G3"}],
             "norms": [{"id": "N1"}]}
    assert changed_items(before, after) == ["goal G1", "goal G3 added", "goal G2 removed",
                                            "title"]
