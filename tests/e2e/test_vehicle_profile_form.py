"""In the browser (1024x768): an admin enters a vehicle profile as a form, not
JSON (behaviours, speed, budget, an envelope limit, a feature), changes one nested value, and the
version diff names that nested field (envelope.depth_m), not the whole envelope. The form fits
the window; axe-core finds no serious or critical violation on the page."""

from __future__ import annotations

import secrets

from playwright.sync_api import Browser, expect

from .conftest import PATIENCE_MS, Server, expect_accessible
from .screens import box, no_page_scroll_sideways
from .test_roles import sign_in


def test_admin_edits_a_profile_as_a_form_and_reads_a_field_level_diff(
        browser: Browser, server: Server) -> None:
    context = browser.new_context(base_url=server.url, viewport={"width": 1024, "height": 768})
    context.set_default_timeout(PATIENCE_MS)
    page = context.new_page()
    try:
        vehicle = f"form-auv-{secrets.token_hex(3)}"
        sign_in(page, "admin")
        page.get_by_role("link", name="Vehicles", exact=True).click()
        page.get_by_role("button", name="New vehicle").click()
        form = page.get_by_test_id("profile-form")
        form.get_by_label("Vehicle id").fill(vehicle)
        form.get_by_label("Title").fill("Form AUV")
        form.get_by_label("Trusted behaviours (comma-separated)").fill("transit, area_search")
        form.get_by_label("Speed (m/s)").fill("1.5")
        form.get_by_label("Energy budget (Wh)").fill("1200")
        limit = form.get_by_label("New limit (quantity name)")
        limit.fill("depth_m")
        limit.press("Enter")
        form.get_by_label("depth_m max").fill("100")
        form.get_by_role("button", name="Add feature").click()
        form.get_by_label("Feature 1 id").fill("nav")
        form.get_by_label("nav measures").fill("depth_m, nav_error_m")
        width = page.viewport_size["width"] if page.viewport_size else 0
        assert box(form)["x"] >= 0 and box(form)["x"] + box(form)["width"] <= width
        no_page_scroll_sideways(page)
        expect_accessible(page, "the vehicle profile form")
        page.get_by_role("button", name="Save vehicle").click()
        expect(page.get_by_role("status").filter(has_text=f"Vehicle {vehicle} saved.")
               ).to_be_visible()

        page.get_by_role("button", name=f"Edit {vehicle}").click()
        form = page.get_by_test_id("profile-form")
        expect(form.get_by_label("depth_m max")).to_have_value("100")
        expect(form.get_by_label("Vehicle id")).to_have_attribute("readonly", "")
        form.get_by_label("depth_m max").fill("60")
        page.get_by_role("button", name="Save vehicle").click()
        versions = page.get_by_test_id("vehicle-versions").get_by_role("listitem")
        expect(versions).to_have_count(2)
        expect(page.get_by_test_id("vehicle-diff")).to_have_text(
            "envelope.depth_m: [0,100] → [0,60]")
        expect_accessible(page, "the vehicle registry with a version diff")
    finally:
        context.close()
