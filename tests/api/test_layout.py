"""Node positions are editor data, not orders (issue 18 item 2): saving them creates no
revision, no "Updated by" and no event."""

from __future__ import annotations

from .conftest import World, count_rows

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
    for field in ("revision", "updated_by", "updated_at", "draft_digest"):
        assert after[field] == before[field], field
    assert count_rows(world.database, "SELECT count(*) FROM events") == events


def test_a_bad_layout_is_refused_with_where(world: World) -> None:
    client = world.client("operator")
    bad = client.put(f"/api/missions/{EXAMPLE}/layout", json={"layout": {"G1": {"x": "left"}}})
    assert bad.status_code == 422
    assert "G1" in bad.text
    missing = client.put("/api/missions/no-such/layout", json={"layout": {}})
    assert missing.status_code == 404
    assert world.client("auditor").put(f"/api/missions/{EXAMPLE}/layout",
                                       json={"layout": {}}).status_code == 403
