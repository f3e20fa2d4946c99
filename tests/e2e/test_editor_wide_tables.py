"""In the browser at 1024x768: the editor's Quantities table, wider than its card, scrolls
sideways inside it; neither it nor its visually hidden headers widen the page."""

from __future__ import annotations

import json

from playwright.sync_api import Browser, expect

from countersign.orders.examples import example_bytes

from .conftest import PATIENCE_MS, Server, _api_import
from .test_editor_build_exemplar import panel, saved
from .test_roles import sign_in


def test_the_quantities_table_scrolls_inside_its_card(browser: Browser, server: Server) -> None:
    context = browser.new_context(base_url=server.url, viewport={"width": 1024, "height": 768})
    context.set_default_timeout(PATIENCE_MS)
    page = context.new_page()
    try:
        data = json.loads(example_bytes("search-and-sample"))
        data["id"] = "wide-quantities"
        mission = _api_import(server, json.dumps(data).encode(), "application/json")
        sign_in(page, "operator")
        page.goto(f"/missions/{mission}?tab=editor")
        expect(page.get_by_test_id("editor-canvas")).to_have_attribute("data-ready", "true",
                                                                        timeout=60_000)
        saved(page)
        panel(page, "Quantities")
        wrap = page.locator(".table-wrap:has(table.quantities)").bounding_box()
        assert wrap is not None and wrap["x"] + wrap["width"] <= 1024, wrap
        assert page.evaluate("document.documentElement.scrollWidth") <= 1024
    finally:
        context.close()
