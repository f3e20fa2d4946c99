"""On the review page, at 1024x768 and 1280x800: a refined mission's review draws each
refinement under the mission's graph (its ends say which outcome they return) and its paths
show the nested steps (`G1/G1.1`) readable, apart and inside the list; a team's review draws
every member's graph, the meetings that link them and the TEAM findings. axe-core clean;
screenshots in the artifacts folder.

Each test signs in once and opens the review once per screen, in a window of that size (a
graph is scaled to its frame as the page renders it, not again when the window changes)."""

from __future__ import annotations

import itertools
import json
import re
from typing import Any

import pytest
from playwright.sync_api import Page, expect

from countersign.orders.examples import example_bytes

from .conftest import Server, _api_import, expect_accessible
from .screens import SCREENS, box, font_px, inside, no_page_scroll_sideways, shot
from .test_roles import sign_in
from .test_vehicle_registry import client


def _version(server: Server, name: str, mission: str) -> str:
    data = json.loads(example_bytes(name))
    data["id"] = mission
    created = _api_import(server, json.dumps(data).encode(), "application/json")
    with client(server, "operator") as operator:
        answer = operator.post(f"/api/missions/{created}/versions")
        assert answer.status_code in (201, 409), answer.text
    return created


def _no_sideways_scroll(page: Page, where: str) -> None:
    """no_page_scroll_sideways, its failure naming the screen."""
    try:
        no_page_scroll_sideways(page)
    except AssertionError as failed:
        raise AssertionError(f"{failed} {where}") from None


@pytest.fixture(scope="module")
def missions(server: Server) -> dict[str, str]:
    return {"refined": _version(server, "search-and-sample-refined", "review-refined"),
            "team": _version(server, "search-and-sample-team", "review-team")}


def _graph_fits(page: Page, section: Any, what: str) -> None:
    card = box(page.locator("main"))
    frame = box(section.locator(".orders-graph-canvas"))
    inside(frame, card, f"{what}: graph frame inside the card")
    size = page.viewport_size
    assert size and frame["x"] + frame["width"] <= size["width"], what


def test_review_of_a_refined_mission_shows_nested_steps(
        page: Page, missions: dict[str, str], tmp_path_factory: pytest.TempPathFactory) -> None:
    sign_in(page, "supervisor")
    for width, height in SCREENS:
        where = f"at {width}x{height}"
        page.set_viewport_size({"width": width, "height": height})
        page.goto(f"/missions/{missions['refined']}/versions/1/review")
        refinement = page.get_by_test_id("review-refinement-G1")
        expect(refinement.get_by_role("heading")).to_have_text("Refinement of G1: Search Area A")
        expect(refinement).to_contain_text("at most 6 steps, then fail")
        expect(refinement.get_by_test_id("orders-graph")).to_be_visible()
        expect(refinement.locator("text").filter(has_text="returns succeed")).to_have_count(1)
        refinement.scroll_into_view_if_needed()
        _graph_fits(page, refinement, f"refinement {where}")
        shot(page, tmp_path_factory, f"review-refinement-{width}x{height}")

        paths = page.get_by_test_id("review-paths")
        rows = paths.get_by_test_id("review-path-row")
        expect(rows.first).to_be_visible()
        paths.scroll_into_view_if_needed()
        listing = box(paths)
        inside(listing, box(page.locator("main")), f"path list inside the card {where}")
        nested = 0
        for i in range(min(rows.count(), 6)):
            row = rows.nth(i)
            if box(row)["y"] + box(row)["height"] > listing["y"] + listing["height"]:
                break
            steps = row.get_by_test_id("review-path-step")
            cells = [box(row.get_by_test_id("review-path-terminal"))]
            for k in range(steps.count()):
                step = steps.nth(k)
                text = step.inner_text()
                assert re.fullmatch(r"G\d+(/G[\d.]+([#@][^/\s]*)?)*\s*[sfc]", text), (where, text)
                nested += "/" in text
                goal = step.locator(".rp-goal")
                # The whole id shows: its text is not cut by the cell.
                clipped = goal.evaluate("e => e.scrollWidth > e.clientWidth + 1")
                assert not clipped, ("step id cut off", where, text)
                cells.append(box(step.locator(".outcome-letter")))
                assert font_px(goal) >= 12, (where, text)
            for a, b in itertools.pairwise(cells):
                assert a["x"] + a["width"] <= b["x"] + 0.5, ("cells overlap", where, a, b)
            sentence = row.get_attribute("aria-label") or ""
            # The row's sentence names nested steps by their titles.
            assert "/" not in row.inner_text() or "unvisited cell" in sentence, (where, sentence)
        assert nested > 0, f"no nested step among the first paths {where}"
        _no_sideways_scroll(page, where)
        shot(page, tmp_path_factory, f"review-refined-paths-{width}x{height}")
        expect_accessible(page, f"the review of a refined mission {where}")


def test_review_of_a_team_shows_every_member_and_the_meetings(
        page: Page, missions: dict[str, str], tmp_path_factory: pytest.TempPathFactory) -> None:
    sign_in(page, "supervisor")
    orders = json.loads(example_bytes("search-and-sample-team"))
    for width, height in SCREENS:
        where = f"at {width}x{height}"
        page.set_viewport_size({"width": width, "height": height})
        page.goto(f"/missions/{missions['team']}/versions/1/review")
        meetings = page.get_by_test_id("review-meetings")
        expect(meetings).to_contain_text("Meeting R1")
        for member in orders["team"]:
            goal = next(g for g in member["orders"]["goals"] if g.get("meet") == "R1")
            expect(meetings).to_contain_text(f"{member['vehicle']} at {goal['id']}")
        expect(page.get_by_test_id("review-team-findings")).to_contain_text("TEAM error")
        meetings.scroll_into_view_if_needed()
        inside(box(meetings), box(page.locator("main")), f"meetings inside the card {where}")
        shot(page, tmp_path_factory, f"review-team-{width}x{height}")
        for member in orders["team"]:
            section = page.get_by_test_id(f"review-member-{member['vehicle']}")
            expect(section.get_by_role("heading").first).to_contain_text(
                f"Vehicle {member['vehicle']}")
            graph = section.get_by_test_id("orders-graph")
            nodes = len(member["orders"]["goals"]) + len(member["orders"]["terminals"])
            expect(graph).to_have_attribute("aria-label",
                                            re.compile(rf"{nodes} goals and terminals"))
            goal = next(g for g in member["orders"]["goals"] if g.get("meet") == "R1")
            expect(section.get_by_test_id(f"orders-meet-{goal['id']}")).to_have_text("meet R1")
            section.scroll_into_view_if_needed()
            _graph_fits(page, section, f"{member['vehicle']} {where}")
        shot(page, tmp_path_factory, f"review-team-member-{width}x{height}")
        _no_sideways_scroll(page, where)
        expect_accessible(page, f"the review of a team {where}")
