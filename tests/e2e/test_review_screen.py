"""On a real screen (1024x768 and 1280x800): the supervisor's review shows every
step of every path (goal id and outcome letter), the terminal and the probability always in
view, costs with units, the cited rehearsal with its outcome, path and replay link, and the
campaign the operator attached from the Versions tab; the record renders the rehearsal as a
table inside the page's width and links the printable document. axe-core finds no serious or
critical violation on these pages. Screenshots go to the artefact folder.

Each page test signs in once and opens each page once per screen, in a window of that size (the
pages lay out as they render), then checks it there."""

from __future__ import annotations

import itertools
import json
import re
import secrets
import time
from typing import Any

import httpx
import pytest
from playwright.sync_api import Page, expect

from .conftest import SCREENS, Server, _api_import, expect_accessible
from .screens import box, font_px, inside, no_page_scroll_sideways, shot
from .test_roles import sign_in
from .test_vehicle_registry import approve, client, exemplar


def _no_sideways_scroll(page: Page, where: str) -> None:
    """no_page_scroll_sideways, its failure naming the screen."""
    try:
        no_page_scroll_sideways(page)
    except AssertionError as failed:
        raise AssertionError(f"{failed} {where}") from None


def wait_for(operator: httpx.Client, url: str, done: Any) -> dict[str, Any]:
    """Polls until `done(body)`; a generous bound for a loaded machine, not a timing claim."""
    deadline = time.monotonic() + 600
    while not done(body := operator.get(url).json()):
        assert time.monotonic() < deadline, body
        time.sleep(0.5)
    return body


@pytest.fixture(scope="module")
def submitted(server: Server) -> dict[str, Any]:
    """The exemplar as v1 with energy and probabilities (so the review has quantiles to print),
    a finished 3-simulation campaign, a replayed rehearsal record, submitted, the record
    attached by API; the campaign is left for the browser to attach."""
    data = exemplar()
    data["id"] = f"e2e-review-screen-{secrets.token_hex(3)}"
    for i, goal in enumerate(data["goals"]):
        goal["cost"] = {"energy_wh": 100.0 + 13.37 * i, "duration_s": 1800 + 61 * i}
        goal["p"] = {"succeed": 0.7, "fail": 0.2, "violate": 0.1}
    mission = _api_import(server, json.dumps(data).encode(), "application/json")
    with client(server, "operator") as operator:
        assert operator.post(f"/api/missions/{mission}/versions").status_code == 201
        started = operator.post(f"/api/missions/{mission}/versions/1/campaigns",
                                json={"simulations": 3})
        assert started.status_code == 201, started.text
        campaign = started.json()["id"]
        rehearsal = operator.post(f"/api/missions/{mission}/rehearsals",
                                  json={"source": "replay", "path_index": 2, "speed": 100000,
                                        "version": 1})
        assert rehearsal.status_code == 201, rehearsal.text
        live = rehearsal.json()["id"]
        wait_for(operator, f"/api/rehearsals/{live}",
                 lambda b: b["status"]["state"] in ("finished", "stopped"))
        stopped = operator.post(f"/api/rehearsals/{live}/stop")
        assert stopped.status_code == 200, stopped.text
        record = stopped.json()["digest"]
        wait_for(operator, f"/api/campaigns/{campaign}",
                 lambda b: b["state"] not in ("queued", "running"))
        submission = operator.post(f"/api/missions/{mission}/versions/1/submit")
        assert submission.status_code == 201, submission.text
        sid = submission.json()["id"]
        cited = operator.post(f"/api/submissions/{sid}/rehearsal", json={"rehearsal": record})
        assert cited.status_code in (200, 201), cited.text
    return {"mission": mission, "campaign": campaign, "submission": sid, "record": record}


def test_operator_attaches_the_campaign_from_the_versions_tab(page: Page,
                                                               submitted: dict[str, Any]) -> None:
    sign_in(page, "operator")
    page.goto(f"/missions/{submitted['mission']}?tab=versions")
    citation = page.get_by_test_id("campaign-citation")
    expect(citation.get_by_test_id("cited-campaigns")).to_contain_text("none attached")
    citation.get_by_role("button", name=f"Attach campaign {submitted['campaign']}").click()
    expect(citation.get_by_test_id("cited-campaigns")).to_contain_text(submitted["campaign"])
    expect(citation.get_by_role("button", name=re.compile("^Attach campaign"))).to_have_count(0)
    # Item 6: the results say which paths the campaign did not reach, and offer per-goal
    # probabilities only when its runs took more than one path.
    page.get_by_role("button", name="Results").first.click()
    covered = page.get_by_test_id("campaign-covered")
    found = re.search(r"Paths covered: (\d+) of 75", covered.inner_text())
    assert found, covered.inner_text()
    expect(page.get_by_test_id("campaign-not-reached")).to_contain_text("Not reached: #")
    offer = page.get_by_role("button", name="Offer per-goal probabilities")
    if int(found.group(1)) <= 1:
        expect(offer).to_have_count(0)
        expect(page.get_by_test_id("no-offer")).to_contain_text("every run took the same path")
    else:
        expect(offer).to_be_visible()
    expect_accessible(page, "the Versions tab with a submission")


def test_review_shows_every_step_terminal_and_probability(
        page: Page, submitted: dict[str, Any], tmp_path_factory: pytest.TempPathFactory) -> None:
    sign_in(page, "supervisor")
    for width, height in SCREENS:
        where = f"at {width}x{height}"
        page.set_viewport_size({"width": width, "height": height})
        page.goto(f"/missions/{submitted['mission']}/versions/1/review")
        paths = page.get_by_test_id("review-paths")
        rows = paths.get_by_test_id("review-path-row")
        expect(rows.first).to_be_visible()
        paths.scroll_into_view_if_needed()
        card = box(page.locator("main"))
        listing = box(paths)
        inside(listing, card, f"the path list inside the page's card {where}")
        # Every row in view: number, terminal and probability inside the visible list, each step
        # an id and a letter, no two cells overlapping, text of a readable size.
        shown = rows.count()
        assert shown >= 5, (where, shown)
        for i in range(min(shown, 8)):
            row = rows.nth(i)
            if box(row)["y"] + box(row)["height"] > listing["y"] + listing["height"]:
                break
            terminal, chance = row.get_by_test_id("review-path-terminal"), row.get_by_test_id(
                "review-path-chance")
            expect(terminal).to_have_text(re.compile(r"^(COMPLETE|ABORT)$"))
            expect(chance).to_have_text(re.compile(r"^0\.\d+$"))
            inside(box(terminal), listing, f"terminal cell in the visible list {where}")
            inside(box(chance), listing, f"probability cell in the visible list {where}")
            steps = row.get_by_test_id("review-path-step")
            assert steps.count() >= 2, (where, i, steps.count())
            cells = [box(terminal), box(chance)]
            for k in range(steps.count()):
                expect(steps.nth(k)).to_have_text(re.compile(r"^G\d[sfc]$"))
                cells.append(box(steps.nth(k).locator(".outcome-letter")))
            for a, b in itertools.pairwise(cells):
                assert a["x"] + a["width"] <= b["x"] + 0.5, ("cells overlap", where, a, b)
            assert font_px(steps.first) >= 12 and font_px(terminal) >= 12, (
                f"text under 12 px in row {i + 1} {where}")
        # Rows differ where the paths differ (issue: rows #1-#6 looked identical).
        texts = [rows.nth(i).inner_text() for i in range(5)]
        assert len(set(texts)) == 5, (where, texts)

        figures = page.get_by_test_id("review-probabilities")
        expect(figures).to_contain_text("Wh")
        assert not re.search(r"\d\.\d{4,}", figures.inner_text().replace(" to ", " ")
                             .split("Any constraint")[1]), (where, figures.inner_text())

        rehearsal = page.get_by_test_id("review-rehearsal")
        expect(rehearsal.get_by_test_id("rehearsal-outcome")).to_have_text(
            re.compile(r"Ended at"))
        expect(rehearsal.get_by_test_id("rehearsal-steps")).to_contain_text("G1")
        expect(rehearsal.get_by_test_id("rehearsal-replay")).to_have_attribute(
            "href", re.compile(r"/replay\.html$"))
        inside(box(rehearsal), card, f"cited rehearsal inside the card {where}")
        _no_sideways_scroll(page, where)

        paths.scroll_into_view_if_needed()
        shot(page, tmp_path_factory, f"review-paths-{width}")
        rehearsal.scroll_into_view_if_needed()
        shot(page, tmp_path_factory, f"review-rehearsal-{width}")
        expect_accessible(page, f"the review at {width} px")
        page.goto("/reviews")
        expect(page.get_by_role("heading", level=1)).to_be_visible()
        expect_accessible(page, f"the list of reviews at {width} px")


def test_record_shows_the_rehearsal_as_a_table_and_links_the_document(
        page: Page, server: Server, submitted: dict[str, Any],
        tmp_path_factory: pytest.TempPathFactory) -> None:
    if "approval" not in submitted:
        submitted["approval"] = approve(server, submitted["submission"])
    sign_in(page, "auditor")
    for width, height in SCREENS:
        where = f"at {width}x{height}"
        page.set_viewport_size({"width": width, "height": height})
        page.goto(f"/audit/{submitted['approval']}")
        section = page.get_by_test_id("rehearsal")
        table = section.get_by_test_id("rehearsal-summary")
        expect(table).to_be_visible()
        expect(table.get_by_test_id("rehearsal-outcome")).to_have_text(re.compile(r"Ended at"))
        expect(table.get_by_role("link", name="Replay in 3D")).to_be_visible()
        assert "{" not in section.inner_text(), f"the rehearsal is printed as JSON {where}"
        inside(box(table), box(page.locator("main")), f"rehearsal table inside the card {where}")
        _no_sideways_scroll(page, where)
        document = page.get_by_role("link", name="Printable approval document")
        expect(document).to_have_attribute("href", re.compile(r"/document$|/document\b"))
        table.scroll_into_view_if_needed()
        shot(page, tmp_path_factory, f"record-rehearsal-{width}")
        expect_accessible(page, f"the record at {width} px")
        document.click()
        expect(page.get_by_role("heading", level=1)).to_be_visible()
        _no_sideways_scroll(page, f"on the printable approval document {where}")
        expect_accessible(page, f"the printable approval document at {width} px")
        page.goto("/audit")
        expect(page.get_by_role("heading", level=1)).to_be_visible()
        expect_accessible(page, f"the audit history at {width} px")
