"""In the browser: the activity log shows a role change as whose role, from
what to what; newest first; filtered by kind, actor, target and time on the server; each row
numbered by its entry's index in the transparency log."""

from __future__ import annotations

import json

from playwright.sync_api import Page, expect

from .conftest import PASSWORD, Server
from .test_roles import sign_in
from .test_vehicle_registry import client


def _log_indexes(server: Server) -> dict[int, int]:
    with client(server, "auditor") as auditor:
        entries = auditor.get("/api/log/entries", params={"limit": 5000}).json()
    return {json.loads(e["entry"])["event"]["id"]: e["index"] for e in entries}


def test_the_log_names_a_role_change_newest_first_filtered_and_numbered_as_the_log(
        page: Page, server: Server) -> None:
    with client(server, "admin") as admin:
        made = admin.post("/api/users", json={"username": "e2e-log-heidi", "role": "operator",
                                              "password": "Qz8-another-long-pass"})
        assert made.status_code == 201, made.text
        changed = admin.patch(f"/api/users/{made.json()['id']}",
                              json={"role": "supervisor", "admin_password": PASSWORD["admin"]})
        assert changed.status_code == 200, changed.text
        # Another test's editing burst may be logged when it goes quiet, after this change:
        # the change is the newest user.updated event, not necessarily the newest event.
        recent = admin.get("/api/events", params={"order": "newest", "limit": 50}).json()
        newest = next(e for e in recent if e["kind"] == "user.updated")

    sign_in(page, "auditor")
    page.get_by_role("link", name="Activity", exact=True).click()
    rows = page.get_by_test_id("event-row")
    expect(rows.first).to_be_visible()
    indexes = _log_indexes(server)
    change = page.locator(f'[data-testid="event-row"][data-index="{indexes[newest["id"]]}"]')
    expect(change.get_by_test_id("event-target")).to_have_text("user e2e-log-heidi")
    expect(change.get_by_test_id("event-change")).to_have_text(
        "role from operator to supervisor")
    # Newest first: rows in falling log order, the role change on the first page (the
    # browser tests before this one on the same server may log after it: editing bursts end
    # when they go quiet).
    numbers = [int(n) for n in rows.evaluate_all("rs => rs.map(r => r.dataset.index)")]
    assert numbers == sorted(numbers, reverse=True), numbers
    assert indexes[newest["id"]] in numbers, numbers
    shown = rows.evaluate_all("rs => rs.map(r => r.cells[0].textContent)")
    assert [int(n) for n in shown] == numbers  # the # column is the log index
    assert set(numbers) <= set(indexes.values())

    page.get_by_label("Kind").select_option("user.updated")
    page.get_by_label("Target").fill("e2e-log-heidi")
    page.get_by_role("button", name="Filter", exact=True).click()
    expect(rows).to_have_count(1)
    expect(rows.first.get_by_test_id("event-change")).to_have_text(
        "role from operator to supervisor")
    expect(rows.first).to_have_attribute("data-index", str(indexes[newest["id"]]))

    page.get_by_label("Who").fill("supervisor")  # the admin made the change, not a supervisor
    page.get_by_role("button", name="Filter", exact=True).click()
    expect(page.get_by_text("No events match these filters.")).to_be_visible()
    page.get_by_label("Who").fill("admin")
    page.get_by_label("From").fill("2099-01-01T00:00")
    page.get_by_role("button", name="Filter", exact=True).click()
    expect(page.get_by_text("No events match these filters.")).to_be_visible()
    page.get_by_label("From").fill("2020-01-01T00:00")
    page.get_by_role("button", name="Filter", exact=True).click()
    expect(rows).to_have_count(1)
    page.get_by_role("button", name="Clear filters").click()
    expect(rows.nth(1)).to_be_visible()  # the unfiltered log again, not the one match
    expect(change.get_by_test_id("event-target")).to_have_text("user e2e-log-heidi")
