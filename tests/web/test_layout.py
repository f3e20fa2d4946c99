"""Node positions are editor data, not orders: saving them creates no
revision, no "Updated by" and no event."""

from __future__ import annotations

from countersign.store.tables import Mission
from countersign.web.routes.schemas import Layout

from .conftest import World, count_rows
from .described import assert_described

EXAMPLE = "search-and-sample"


def test_saving_the_layout_leaves_revision_author_and_events(world: World) -> None:
    client = world.client("operator")
    before = client.get(f"/api/missions/{EXAMPLE}").json()
    events = count_rows(world.database, "SELECT count(*) FROM events")
    layout = {"G1": {"x": 10, "y": 20.5}, "COMPLETE": {"x": 300, "y": 0}}
    saved = client.put(f"/api/missions/{EXAMPLE}/layout", json={"layout": layout})
    assert saved.status_code == 200, saved.text
    after = client.get(f"/api/missions/{EXAMPLE}").json()
    assert after["layout"] == layout
    _assert_stored_layout(world, saved.json()["layout"], after["layout"])
    for field in ("revision", "updated_by", "updated_at", "draft_digest"):
        assert after[field] == before[field], field
    assert count_rows(world.database, "SELECT count(*) FROM events") == events


def _assert_stored_layout(world: World, *answers: object) -> None:
    """Every answer is the stored layout, and the Layout model describes it exactly."""
    with world.database.session() as db:
        stored = db.get(Mission, EXAMPLE).layout  # type: ignore[union-attr]
    assert stored and all(answer == stored for answer in answers)
    assert_described(Layout, stored)


def test_a_layout_saved_with_the_draft_is_answered_as_stored(world: World) -> None:
    client = world.client("operator")
    orders = client.get(f"/api/missions/{EXAMPLE}").json()["orders"]
    layout = {"G1": {"x": 1, "y": -2.25}, "ABORT": {"x": 0.5, "y": 40}}
    saved = client.put(f"/api/missions/{EXAMPLE}/draft", json={"orders": orders, "layout": layout},
                       headers={"If-Match": '"1"'})
    assert saved.status_code == 200, saved.text
    # Compared as text too: the draft route keeps the numbers it was sent (an int stays one).
    assert saved.json()["layout"] == layout and '"x":1,' in saved.text
    _assert_stored_layout(world, saved.json()["layout"],
                          client.get(f"/api/missions/{EXAMPLE}").json()["layout"])


def test_a_bad_layout_is_refused_with_where(world: World) -> None:
    client = world.client("operator")
    bad = client.put(f"/api/missions/{EXAMPLE}/layout", json={"layout": {"G1": {"x": "left"}}})
    assert bad.status_code == 422
    assert "G1" in bad.text
    missing = client.put("/api/missions/no-such/layout", json={"layout": {}})
    assert missing.status_code == 404
    assert world.client("auditor").put(f"/api/missions/{EXAMPLE}/layout",
                                       json={"layout": {}}).status_code == 403
