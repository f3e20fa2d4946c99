"""The "Plan survey" dialog of the mission editor.

The operator opens the exemplar in the editor, opens "Plan survey", leaves out the shipping
lane and the recovery area, sets rewards, a mandatory area and the battery, solves on the
server, sees the chosen order drawn on the plan view, and creates a new draft from the plan's
orders, which the server then holds and validates.
"""

from __future__ import annotations

import re

import pytest
from playwright.sync_api import Page, expect

from .screens import tables_fit_each_screen
from .test_roles import sign_in


def test_plan_survey_dialog_solves_and_creates_a_draft(
        page: Page, seeded_mission: str, tmp_path_factory: pytest.TempPathFactory) -> None:
    sign_in(page, "operator")
    page.goto(f"/missions/{seeded_mission}?tab=editor")
    expect(page.get_by_test_id("node-G5")).to_be_visible()
    page.locator(".editor-toolbar summary", has_text="More").click()
    page.get_by_role("button", name="Plan survey…").click()
    dialog = page.get_by_role("dialog", name="Plan survey")
    expect(dialog).to_be_visible()
    # Defaults: start and recovery at the recovery area, battery from the vehicle's budget.
    expect(dialog.get_by_label("Battery (Wh)")).to_have_value("1500")
    expect(dialog.get_by_label("Include BASE", exact=True)).not_to_be_checked()
    tables_fit_each_screen(page, tmp_path_factory, "plan-areas",
                           [(dialog.get_by_role("table", name="Areas to consider"), dialog)],
                           include=".plan-dialog")
    dialog.get_by_label("Include LANE", exact=True).uncheck()
    dialog.get_by_label("Battery (Wh)").fill("20000")
    dialog.get_by_label("Reserve (Wh)").fill("500")
    dialog.get_by_label("Level").select_option("2")
    for area, reward in (("A", "30"), ("B", "20"), ("C", "10")):
        dialog.get_by_label(f"Reward of {area}", exact=True).fill(reward)
    dialog.get_by_label("A is mandatory", exact=True).check()
    dialog.get_by_role("button", name="Solve").click()
    result = dialog.get_by_test_id("plan-result")
    expect(result).to_contain_text("Best plan:")
    text = result.inner_text()
    print(f"plan survey: {text.strip()}")
    assert re.search(r"\bA\b", text), text
    expect(dialog.get_by_test_id("plan-route")).to_be_visible()
    expect(dialog.get_by_test_id("plan-area-A")).to_have_class(re.compile("chosen"))
    expect(dialog.get_by_test_id("plan-area-LANE")).not_to_have_class(re.compile("chosen"))

    # An infeasible variant explains itself (battery too small for the mandatory area).
    dialog.get_by_label("Battery (Wh)").fill("600")
    dialog.get_by_role("button", name="Solve").click()
    expect(result).to_contain_text("No feasible plan")
    expect(result).to_contain_text("A")
    dialog.get_by_label("Battery (Wh)").fill("20000")
    dialog.get_by_role("button", name="Solve").click()
    expect(result).to_contain_text("Best plan:")

    dialog.get_by_label("New mission id").fill("survey-plan-e2e")
    dialog.get_by_role("button", name="Create draft from plan").click()
    expect(page).to_have_url(re.compile(r"/missions/survey-plan-e2e"))
    expect(page.get_by_role("heading", level=1)).to_contain_text("Survey plan")
    expect(page.get_by_test_id("editor-canvas")).to_have_attribute("data-ready", "true")
    detail = page.request.get("/api/missions/survey-plan-e2e").json()
    goals = detail["orders"]["goals"]
    assert any(g.get("params", {}).get("plan_area") == "A" for g in goals), goals
    report = page.request.get("/api/missions/survey-plan-e2e/report").json()
    assert not [f for f in report["findings"] if f["code"] == "BUDGET" and f["severity"] == "error"]
    assert report["paths"]["count"] > 0
