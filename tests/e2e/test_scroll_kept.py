"""A change of the query string only (a list's filter, a mission's tab) keeps the page where
the reader scrolled it; going to another page still starts at its top."""

from __future__ import annotations

import json
import re

from playwright.sync_api import Page, expect

from countersign.orders.examples import example_bytes

from .conftest import Server
from .test_editor_import import _create_empty
from .test_roles import sign_in

PREFIX = "scroll-kept"
SCROLLED = 120  # px: the filters and the tabs are still in the window


def _missions(page: Page, count: int) -> None:
    token = _create_empty(page, f"{PREFIX}-00")
    for n in range(1, count):
        created = page.request.post("/api/missions", headers={"X-CSRF-Token": token}, data={
            "format": "countersign.orders/1", "id": f"{PREFIX}-{n:02}",
            "title": f"Scroll {n}", "goals": []})
        assert created.status == 201, created.text()


def _scroll_to(page: Page, y: int) -> None:
    page.evaluate("(y) => window.scrollTo(0, y)", y)
    page.wait_for_function("(y) => window.scrollY === y", arg=y)


def test_a_filter_change_keeps_the_scroll_position(page: Page, server: Server) -> None:
    del server
    sign_in(page, "operator")
    _missions(page, 30)  # more than a page of the list: the page is taller than the window
    page.goto(f"/missions?q={PREFIX}")
    rows = page.locator("table.missions tbody tr")
    expect(rows).to_have_count(25)
    _scroll_to(page, SCROLLED)
    status = page.get_by_label("Status")
    assert status.bounding_box()["y"] > 0  # type: ignore[index]  # visible: no scroll to it
    status.select_option("draft")
    expect(page).to_have_url(re.compile(r"[?&]status=draft"))
    expect(page.locator(".table-wrap[aria-busy='true']")).to_have_count(0)
    expect(rows).to_have_count(25)
    assert page.evaluate("() => window.scrollY") == SCROLLED

    # Another page starts at its top.
    page.locator(f"table.missions a[href='/missions/{PREFIX}-01']").first.click()
    expect(page).to_have_url(re.compile(rf"/missions/{PREFIX}-01"))
    page.wait_for_function("() => window.scrollY === 0")


def test_a_tab_change_keeps_the_scroll_position(page: Page, server: Server) -> None:
    del server
    sign_in(page, "operator")
    token = page.evaluate("() => fetch('/api/auth/me').then(r => r.json())"
                          ".then(j => j.csrf_token)")
    orders = json.loads(example_bytes("search-and-sample"))
    orders["id"] = f"{PREFIX}-tabs"
    created = page.request.post("/api/missions", headers={"X-CSRF-Token": token}, data=orders)
    assert created.status == 201, created.text()
    page.set_viewport_size({"width": 1024, "height": 600})
    page.goto(f"/missions/{PREFIX}-tabs?tab=orders")
    tabs = page.get_by_role("tablist")
    expect(page.get_by_test_id("plain-orders")).to_contain_text("Return to Base")
    _scroll_to(page, SCROLLED)
    # The JSON editor of the orders is as tall as the plain orders: nothing to clamp to.
    tabs.get_by_role("tab", name="Edit orders").click()
    expect(page).to_have_url(re.compile(r"[?&]tab=edit"))
    expect(page.get_by_label("Orders JSON")).to_be_visible()
    assert page.evaluate("() => document.documentElement.scrollHeight - innerHeight") > SCROLLED
    assert page.evaluate("() => window.scrollY") == SCROLLED
