"""In the editor, at 1024x768 and 1280x800: a refined goal opens on its own canvas
(sub-goals, terminals that return the parent's outcomes) with breadcrumbs back up and the
findings of the refinement (REFINE); a refinement is added to a goal and edited, and every
edit round-trips through the draft's save (`refines` in the orders). A team's orders show one
canvas per vehicle (a member switcher), the meeting id on rendezvous goals and the TEAM
findings. Each screen: parts inside the window and the card, nodes readable and apart,
axe-core clean; screenshots in the artifacts folder.

Each test signs in once. A draft without positions is laid out for the window it first opens
in (the positions are then saved) and a canvas is fitted to the window as it is shown, not again
when the window changes: so a mission is made for each screen and first opened in a window of
that size, as before; the edits are made once, on the 1024x768 one, and what they add is then
opened afresh at each screen (the editor reloaded in a window of that size)."""

from __future__ import annotations

import json
import re
from typing import Any

import pytest
from playwright.sync_api import Page, expect

from countersign.orders.examples import example_bytes

from .conftest import SCREENS, expect_accessible
from .screens import shot
from .test_editor import select_node
from .test_editor_build_exemplar import saved
from .test_editor_screen import GEOMETRY, _create, check_screen, open_editor
from .test_roles import sign_in


def _shape(page: Page) -> dict[str, Any]:
    expect(page.get_by_test_id("editor-canvas")).to_have_attribute("data-ready", "true")
    shape: dict[str, Any] = page.evaluate(GEOMETRY)
    return shape


def _scope_bar_fits(page: Page, what: str) -> None:
    bar = page.get_by_test_id("editor-scope").bounding_box()
    card = page.locator(".tabpanel").first.bounding_box()
    canvas = page.get_by_test_id("editor-canvas").bounding_box()
    size = page.viewport_size
    assert bar and card and canvas and size, what
    right = bar["x"] + bar["width"]
    assert bar["x"] >= card["x"] - 1 and right <= card["x"] + card["width"] + 1, what
    assert right <= size["width"] and bar["y"] >= 0, what
    assert bar["y"] + bar["height"] <= canvas["y"] + 1, (what, "scope bar over the canvas")


def _draft(page: Page, mission: str) -> dict[str, Any]:
    answer = page.request.get(f"/api/missions/{mission}")
    assert answer.ok, answer.text()
    orders: dict[str, Any] = answer.json()["orders"]
    return orders


def _goal(orders: dict[str, Any], goal: str) -> dict[str, Any]:
    found: dict[str, Any] = next(g for g in orders["goals"] if g["id"] == goal)
    return found


def test_editor_opens_edits_and_adds_refinements(
        page: Page, tmp_path_factory: pytest.TempPathFactory) -> None:
    sign_in(page, "operator")
    # The mission, then G1's refinement, each first opened at each screen; 1024x768 last, the
    # mission whose edits follow.
    for width, height in reversed(SCREENS):
        where = f"at {width}x{height}"
        page.set_viewport_size({"width": width, "height": height})
        orders = json.loads(example_bytes("search-and-sample-refined"))
        orders["id"] = f"refined-editor-{width}"
        # One terminal of G1's refinement returns nothing: REFINE, shown inside the refinement.
        del _goal(orders, "G1")["refines"]["terminals"][0]["returns"]
        mission = _create(page, orders)
        shape = open_editor(page, mission)
        check_screen(shape, f"refined mission {where}")
        expect(page.get_by_test_id("refined-G1")).to_have_text("refined ▸")
        # The error inside the refinement marks the refined goal as an error.
        expect(page.get_by_test_id("markers-G1")).to_have_text("✖ REFINE")
        shot(page, tmp_path_factory, f"refine-mission-{width}x{height}")

        # Open G1's refinement (double-click): its own canvas, breadcrumbs back to the mission.
        page.get_by_test_id("node-G1").locator(".node-title").dblclick()
        expect(page.get_by_test_id("crumb-current")).to_have_text("G1 Search Area A")
        expect(page.get_by_test_id("crumb-0")).to_have_text("Mission")
        shape = _shape(page)
        assert shape["nodes"] == 6, (where, shape["nodes"])
        check_screen(shape, f"G1's refinement {where}")
        _scope_bar_fits(page, f"breadcrumbs {where}")
        expect(page.get_by_test_id("returns-HALT")).to_have_text("returns violate")
        expect(page.get_by_test_id("returns-FOUND")).to_have_text("returns nothing")
        findings = page.get_by_test_id("editor-findings-panel")
        expect(findings).to_contain_text("REFINE")
        expect(page.get_by_test_id("markers-FOUND")).to_contain_text("REFINE")
        expect_accessible(page, f"G1's refinement {where}")
        shot(page, tmp_path_factory, f"refine-open-{width}x{height}")

    # The terminal returns succeed again: saved inside `refines`, REFINE gone.
    select_node(page, "FOUND")
    returns = page.get_by_label("Returns (the outcome of G1)")
    returns.select_option("succeed")
    returns.blur()
    saved(page)
    expect(page.get_by_test_id("returns-FOUND")).to_have_text("returns succeed")
    expect(page.get_by_test_id("markers-FOUND")).to_have_count(0)
    terminal = _goal(_draft(page, mission), "G1")["refines"]["terminals"][0]
    assert terminal == {**terminal, "id": "FOUND", "returns": "succeed"}, terminal

    # A goal added inside the refinement is saved inside it, not among the mission's goals.
    page.get_by_role("button", name="Add goal", exact=True).click()
    saved(page)
    draft = _draft(page, mission)
    inner = [g["id"] for g in _goal(draft, "G1")["refines"]["goals"]]
    assert len(inner) == 4, inner
    assert len(draft["goals"]) == len(orders["goals"]), [g["id"] for g in draft["goals"]]

    # Back up by the breadcrumbs; add a refinement to G2 and open it.
    page.get_by_test_id("crumb-0").click()
    expect(page.get_by_test_id("breadcrumbs")).to_have_count(0)
    _shape(page)
    select_node(page, "G2")
    page.get_by_test_id("add-refinement").click()
    saved(page)
    refines = _goal(_draft(page, mission), "G2")["refines"]
    assert refines["start"] == "G2.1", refines
    assert [t["returns"] for t in refines["terminals"]] == ["succeed", "fail", "violate"], refines
    expect(page.get_by_test_id("refined-G2")).to_be_visible()
    for n, (width, height) in enumerate(SCREENS):
        where = f"at {width}x{height}"
        if n > 0:
            # Shown afresh at this size: the editor reloaded, G2's refinement opened again (its
            # positions are not saved: they are laid out as it opens).
            page.set_viewport_size({"width": width, "height": height})
            open_editor(page, mission)
            select_node(page, "G2")
        page.get_by_test_id("open-refinement").click()
        expect(page.get_by_test_id("crumb-current")).to_contain_text("G2 ")
        shape = _shape(page)
        assert shape["nodes"] == 4, (where, shape["nodes"])
        # The mission's error is in G1's refinement (the goal added there leads nowhere): the
        # verdict says so rather than "Not valid: 0 errors".
        expect(page.get_by_test_id("editor-verdict")).to_contain_text(
            re.compile(r"^Not valid: 0 errors here \([1-9]\d* elsewhere in the mission\), "))
        check_screen(shape, f"G2's new refinement {where}")
        expect_accessible(page, f"G2's new refinement {where}")
        shot(page, tmp_path_factory, f"refine-added-{width}x{height}")

    # U goes back up from the keyboard; O opens the selected goal's refinement again.
    page.get_by_test_id("node-G2.1").click()
    page.keyboard.press("u")
    expect(page.get_by_test_id("breadcrumbs")).to_have_count(0)
    _shape(page)
    select_node(page, "G1")
    page.keyboard.press("o")
    expect(page.get_by_test_id("crumb-current")).to_have_text("G1 Search Area A")


def test_editor_shows_each_team_member_and_the_meetings(
        page: Page, tmp_path_factory: pytest.TempPathFactory) -> None:
    sign_in(page, "operator")
    orders = json.loads(example_bytes("search-and-sample-team"))
    members = [m["vehicle"] for m in orders["team"]]
    meeting = next(g for g in orders["team"][0]["orders"]["goals"] if g.get("meet"))
    partner = next(g for g in orders["team"][1]["orders"]["goals"] if g.get("meet"))

    # Member 1's canvas, then member 2's, each first opened at each screen; 1024x768 last, the
    # mission whose edit follows.
    for width, height in reversed(SCREENS):
        where = f"at {width}x{height}"
        page.set_viewport_size({"width": width, "height": height})
        orders["id"] = f"team-editor-{width}"
        mission = _create(page, orders)
        shape = open_editor(page, mission)
        check_screen(shape, f"team member 1 {where}")
        _scope_bar_fits(page, f"member switcher {where}")
        first, second = (page.get_by_test_id(f"member-{m}") for m in members)
        expect(first).to_have_attribute("aria-pressed", "true")
        expect(page.get_by_test_id(f"meet-{meeting['id']}")).to_have_text(
            f"meet {meeting['meet']}")
        expect(page.get_by_test_id("editor-findings-panel")).to_contain_text("TEAM")
        expect_accessible(page, f"team member 1 {where}")
        shot(page, tmp_path_factory, f"team-member1-{width}x{height}")

        second.click()
        expect(second).to_have_attribute("aria-pressed", "true")
        shape = _shape(page)
        assert shape["nodes"] == len(orders["team"][1]["orders"]["goals"]) + len(
            orders["team"][1]["orders"]["terminals"]), (where, shape["nodes"])
        check_screen(shape, f"team member 2 {where}")
        expect(page.get_by_test_id(f"meet-{partner['id']}")).to_have_text(
            f"meet {partner['meet']}")
        expect(page.get_by_test_id("editor-findings-panel")).to_contain_text("TEAM")
        expect_accessible(page, f"team member 2 {where}")
        shot(page, tmp_path_factory, f"team-member2-{width}x{height}")

    # An edit on member 2's canvas is saved in member 2's orders.
    select_node(page, partner["id"])
    expect(page.get_by_test_id("goal-meet")).to_have_value(partner["meet"])
    expect(page.get_by_test_id("meet-partners")).to_have_text(
        f"Meets {members[0]} at {meeting['id']} ({meeting['title']}).")
    page.get_by_label("Title", exact=True).fill("Meet vehicle 1 in Area C")
    saved(page)
    draft = _draft(page, mission)
    saved_goal = _goal(draft["team"][1]["orders"], partner["id"])
    assert saved_goal["title"] == "Meet vehicle 1 in Area C", saved_goal
    assert saved_goal["meet"] == partner["meet"], saved_goal
