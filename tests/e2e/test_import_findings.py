"""An imported AVCL mission keeps the reader's findings (the SINK warnings of the
handlers NPS defaults) in its stored report, and the browser shows them."""

from __future__ import annotations

from pathlib import Path

import pytest
from playwright.sync_api import Page, expect

from .conftest import Server
from .test_editor_import import _create_empty, _import
from .test_roles import sign_in

PIRATES = Path("/work/shared/reference/nps-ethical-control/missions/avcl/"
               "PiratesSeizingMerchantDefense.xml")


@pytest.mark.skipif(not PIRATES.exists(), reason="the NPS reference missions are not here")
def test_pirates_imported_in_the_browser_shows_its_sink_warnings(page: Page,
                                                                 server: Server) -> None:
    del server
    sign_in(page, "operator")
    mission = "pirates-import"
    _create_empty(page, mission)
    page.goto(f"/missions/{mission}?tab=editor")
    expect(page.get_by_test_id("node-COMPLETE")).to_be_visible()
    _import(page, PIRATES)
    # "Saved" holds before the import too (the file is read first): wait for the import to
    # reach the draft, then for its save.
    expect(page.get_by_test_id("editor-notice")).to_contain_text(
        "Imported PiratesSeizingMerchantDefense.xml")
    expect(page.get_by_test_id("save-state")).to_have_text("Saved")
    expect(page.get_by_test_id("editor-verdict")).to_contain_text("19 warnings")
    # The stored report keeps them: a fresh load of the page shows them too.
    report = page.request.get(f"/api/missions/{mission}/report").json()
    sinks = [f for f in report["findings"] if f["code"] == "SINK" and f["severity"] == "warning"]
    assert len(sinks) == 19, report["findings"]
    page.reload()
    expect(page.get_by_test_id("editor-verdict")).to_contain_text("19 warnings")
    expect(page.get_by_test_id("editor-findings")).to_contain_text("NPS convention")
