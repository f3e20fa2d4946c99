"""An edit reads and copies what it needs once: the draft is never decoded to answer a stored
report, nor by a save that follows a save of the same process (the editing burst's list of
changes compares with the draft it wrote); reused reports are not deep copies. What is stored
and answered stays exactly what it was."""

from __future__ import annotations

from collections.abc import Iterator
from contextlib import contextmanager
from typing import Any

import pytest
from sqlalchemy import event, text

from countersign.errors import Conflict
from countersign.orders.canonical import digest, digest_of_json, orders_to_json
from countersign.orders.examples import load_example
from countersign.store import missions as store
from countersign.verify.reuse import ReportReuse

from .conftest import World

EXAMPLE = "search-and-sample"


@contextmanager
def draft_reads(world: World, column: str = "missions.draft") -> Iterator[list[str]]:
    """The SELECT statements that read a mission's draft column (or `column`), while inside."""
    seen: list[str] = []

    def before(conn: Any, cursor: Any, statement: str, *args: Any) -> None:
        words = statement.lower().replace(",", " ").split()
        if words[:1] == ["select"] and column in words:
            seen.append(statement)

    event.listen(world.database.engine, "before_cursor_execute", before)
    try:
        yield seen
    finally:
        event.remove(world.database.engine, "before_cursor_execute", before)


def _edit(world: World, mission: str, draft_decoded: int = 0
          ) -> tuple[dict[str, Any], dict[str, Any]]:
    client = world.client("operator")
    current = client.get(f"/api/missions/{mission}")
    orders = current.json()["orders"]
    orders["goals"][0]["title"] = orders["goals"][0]["title"] + " (edited)"
    with draft_reads(world) as reads:
        saved = client.put(f"/api/missions/{mission}/draft", json={"orders": orders},
                           headers={"If-Match": current.headers["etag"]})
        assert saved.status_code == 200, saved.text
        saves = len(reads)
        report = client.get(f"/api/missions/{mission}/report")
        assert report.status_code == 200, report.text
    assert (saves, len(reads) - saves) == (draft_decoded, 0), reads
    return saved.json(), report.json()


def test_a_save_decodes_no_draft_after_a_save_here_and_its_report_not_at_all(
        world: World) -> None:
    _forget(EXAMPLE)
    _edit(world, EXAMPLE, draft_decoded=1)
    detail, report = _edit(world, EXAMPLE)
    # What the save answered is what the database holds (it was not read back).
    again = world.client("auditor").get(f"/api/missions/{EXAMPLE}")
    assert again.headers["etag"] == f'"{detail["revision"]}"'
    assert {k: v for k, v in again.json().items() if k != "versions"} == {
        k: v for k, v in detail.items() if k != "versions"}
    assert report["digest"] == detail["draft_digest"]
    assert detail["draft_digest"] == digest_of_json(detail["orders"])


def _forget(mission: str) -> None:
    """Forget the draft this process wrote last for the mission: as if another process had."""
    with store._last_drafts_lock:
        store._last_drafts.pop(mission, None)


def test_a_draft_another_process_wrote_is_read_for_the_burst(world: World) -> None:
    _forget(EXAMPLE)
    _edit(world, EXAMPLE, draft_decoded=1)
    # What this process wrote before another process saved the draft again.
    with store._last_drafts_lock:
        store._last_drafts[EXAMPLE] = ("sha256:" + "0" * 64, {"goals": []})
    _edit(world, EXAMPLE, draft_decoded=1)
    client = world.client("operator")
    client.post(f"/api/missions/{EXAMPLE}/versions")  # logs the burst
    events = world.client("auditor").get("/api/events", params={"mission": EXAMPLE}).json()
    [burst] = [e for e in events if e["kind"] == "draft.updated"]
    first = client.get(f"/api/missions/{EXAMPLE}").json()["orders"]["goals"][0]["id"]
    assert burst["detail"]["changed"] == [f"goal {first}"]
    assert burst["detail"]["saves"] == 2


def test_the_report_of_a_save_here_is_answered_without_decoding_its_stored_copy(
        world: World) -> None:
    client = world.client("operator")
    current = client.get(f"/api/missions/{EXAMPLE}")
    orders = current.json()["orders"]
    orders["goals"][1]["title"] = "Renamed for the report"
    saved = client.put(f"/api/missions/{EXAMPLE}/draft", json={"orders": orders},
                       headers={"If-Match": current.headers["etag"]})
    assert saved.status_code == 200, saved.text
    with draft_reads(world, "validation_reports.report") as reads:
        answered = client.get(f"/api/missions/{EXAMPLE}/report")
    assert answered.status_code == 200 and reads == []
    # Byte for byte what the stored copy gives (another process answers from it).
    world.database.reports.clear()
    with draft_reads(world, "validation_reports.report") as reads:
        stored = client.get(f"/api/missions/{EXAMPLE}/report")
    assert len(reads) == 1 and stored.content == answered.content


def test_the_draft_read_for_a_report_must_be_of_the_digest_read_before(world: World) -> None:
    with world.database.session(write=False) as db:
        value = store.draft_digest(db, EXAMPLE)
        assert store.draft_of(db, EXAMPLE, value)["id"] == EXAMPLE
        # A draft saved between the two reads (PostgreSQL's read committed): not its report.
        with pytest.raises(Conflict):
            store.draft_of(db, EXAMPLE, "sha256:" + "0" * 64)


def test_a_reused_report_is_the_kept_one_with_its_digest_replaced() -> None:
    orders = load_example(EXAMPLE)
    reuse = ReportReuse()
    made: dict[str, Any] = {"digest": "sha256:first", "findings": [{"code": "X"}]}
    assert reuse.report(orders, "sha256:first", lambda o: made, checked="k") is made
    reused = reuse.report(orders, "sha256:second", lambda o: {}, checked="k")
    assert reused["digest"] == "sha256:second" and made["digest"] == "sha256:first"
    # Shared, not copied: reports are never mutated.
    assert reused["findings"] is made["findings"]


def test_the_digest_of_json_data_is_the_digest_of_the_orders() -> None:
    orders = load_example(EXAMPLE)
    assert digest_of_json(orders_to_json(orders)) == digest(orders)


def test_a_detail_shows_the_summary_columns_without_decoding_the_report(world: World) -> None:
    _forget(EXAMPLE)
    detail, _ = _edit(world, EXAMPLE, draft_decoded=1)
    # Every stored report made unusable: a detail that decoded one would fail (a 500).
    with world.database.engine.begin() as connection:
        connection.execute(text("UPDATE validation_reports SET report = '{\"corrupted\": true}'"))
    again = world.client("auditor").get(f"/api/missions/{EXAMPLE}")
    assert again.status_code == 200, again.text
    assert [again.json()[k] for k in ("ok", "errors", "warnings")] == [
        detail[k] for k in ("ok", "errors", "warnings")]
    assert detail["errors"] is not None
