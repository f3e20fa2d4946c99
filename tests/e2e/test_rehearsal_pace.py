"""In the browser at 1024 and 1280 px: at the default pace a step-by-step
rehearsal of the exemplar asks its first question within a bounded number of frames; viser's
own panel does not cover the scene; one set of controls with the app's outcome names; a fault
pressed while waiting is queued with a visible message (pressed again, refused with one);
simulated time and energy are shown; the record is listed from the stop's answer, with no wait
for a reload.

One rehearsal: it starts at 1024 px, and while it waits for G1's outcome the window is resized
to each width to check the scene's coverage there (viser's canvas follows its frame's size)."""

from __future__ import annotations

import time
from typing import Any

from playwright.sync_api import Page, expect

from countersign.rehearse.manager import GOAL_FRAMES, SLOW_FRAMES

from .conftest import Server
from .test_rehearsal_screen import scene_fits_its_frame
from .test_roles import sign_in

# Points of a 19 x 19 grid over viser's canvas that hit the scene (the canvas, or the labels
# drawn over it inside its container) rather than a panel on top of it.
COVERAGE_JS = """() => {
  const canvas = document.querySelector("canvas");
  if (!canvas) return null;
  const r = canvas.getBoundingClientRect();
  const scene = canvas.parentElement;
  let hit = 0, total = 0;
  const covering = new Set();
  for (let i = 1; i < 20; i++) for (let j = 1; j < 20; j++) {
    const el = document.elementFromPoint(r.left + r.width * i / 20, r.top + r.height * j / 20);
    total++;
    if (el && (el === canvas || el.contains(canvas) || (scene && scene.contains(el)))) hit++;
    else if (el) covering.add(el.tagName + "." + String(el.className).slice(0, 40));
  }
  return {hit, total, width: r.width, height: r.height, viewport: innerWidth,
          covering: [...covering].slice(0, 5)};
}"""


def _status(page: Page, rehearsal_id: str) -> dict[str, Any]:
    answer = page.request.get(f"/api/rehearsals/{rehearsal_id}")
    assert answer.ok, answer.text()
    status: dict[str, Any] = answer.json()["status"]
    return status


WIDTHS = [1024, 1280]
HEIGHT = 800


def test_a_step_by_step_rehearsal_in_the_browser(page: Page, server: Server,
                                                 own_exemplar: str) -> None:
    # A mission of its own: other tests rehearse and edit the shared exemplar, and this test
    # counts the records it lists.
    del server
    seeded_mission = own_exemplar
    page.set_viewport_size({"width": WIDTHS[0], "height": HEIGHT})
    sign_in(page, "operator")
    page.goto(f"/missions/{seeded_mission}?tab=rehearse")
    expect(page.get_by_test_id("rehearsal-speed")).to_have_value("")  # the auto pace
    begin = time.perf_counter()
    page.get_by_test_id("start-rehearsal").click()
    frame = page.get_by_test_id("viser-frame")
    expect(frame).to_be_visible(timeout=60_000)
    rehearsal_id = (frame.get_attribute("src") or "").strip("/").split("/")[-1]
    viewer = page.frame_locator('[data-testid="viser-frame"]')
    expect(viewer.locator("canvas").first).to_be_visible(timeout=60_000)

    expect(page.get_by_test_id("rehearsal-state")).to_have_text("Waiting for the outcome",
                                                                 timeout=120_000)
    status = _status(page, rehearsal_id)
    print(f"first question after {status['first_question_frame']} frames, "
          f"{time.perf_counter() - begin:.1f} s wall from the click")
    assert status["first_question_frame"] <= GOAL_FRAMES + 4 * SLOW_FRAMES
    expect(page.get_by_test_id("rehearsal-question")).to_contain_text("Did goal Succeed (s)")

    # One set of controls, named as everywhere else in the app; none in viser's panel.
    labels = [page.get_by_test_id(f"outcome-{o}").inner_text()
              for o in ("succeed", "fail", "violate")]
    # Each button also shows the key that answers the prompt (s/f/c).
    assert labels == ["Succeed s", "Fail f", "Violate (constraint) c"]
    expect(viewer.get_by_role("button", name="Succeed")).to_have_count(0)
    expect(viewer.get_by_role("button", name="Leak")).to_have_count(0)

    # The scene is not covered by viser's panel, at each width.
    handle = frame.element_handle()
    content = handle.content_frame() if handle else None
    assert content is not None
    # viser minimises its panel when the server's message arrives and animates it; there is
    # no state of the page to wait for instead.
    page.wait_for_timeout(1000)  # let viser lay out its (minimised) panel
    # viser's toast about software WebGL (headless Chromium has no GPU) is closed as a user
    # would; it is not the panel and does not appear on a machine with a GPU.
    toasts = viewer.locator(".mantine-Notification-root button")
    for _ in range(toasts.count()):
        toasts.first.click()
    expect(toasts).to_have_count(0)
    for width in WIDTHS:
        if page.viewport_size != {"width": width, "height": HEIGHT}:
            page.set_viewport_size({"width": width, "height": HEIGHT})
            scene_fits_its_frame(page)
        coverage = content.evaluate(COVERAGE_JS)
        print(f"{width} px: scene coverage {coverage}")
        assert coverage is not None, f"no canvas at {width} px"
        assert coverage["width"] >= 0.9 * coverage["viewport"], (f"at {width} px", coverage)
        assert coverage["hit"] >= 0.95 * coverage["total"], (f"at {width} px", coverage)

    # Time and energy of G1's whole plan, shown.
    expect(page.get_by_test_id("rehearsal-time")).to_contain_text(" h ")
    expect(page.get_by_test_id("rehearsal-energy")).to_contain_text("Wh left of")

    # A fault pressed while the goal waits: queued, and said so.
    page.get_by_test_id("fault-leak").click()
    expect(page.get_by_test_id("fault-notice")).to_contain_text("Fault queued: leak")
    expect(page.get_by_test_id("rehearsal-faults")).to_contain_text("queued for the next goal")
    # The same fault pressed again is refused, and the page says why.
    page.get_by_test_id("fault-leak").click()
    expect(page.get_by_role("alert")).to_contain_text("already queued")
    expect(page.get_by_test_id("rehearsal-faults")).to_contain_text("queued for the next goal")
    page.get_by_test_id("outcome-succeed").click()
    expect(page.get_by_test_id("rehearsal-step")).to_have_text("1")
    expect(page.get_by_test_id("rehearsal-faults")).to_contain_text("Leak")

    # The record is listed from the stop's answer: no reload of the list is needed.
    records = page.get_by_test_id("rehearsal-records")
    before = records.get_by_role("link", name="Replay").count() if records.count() else 0
    listed: list[str] = []
    page.on("request", lambda r: listed.append(r.url) if "rehearsal-records" in r.url else None)
    with page.expect_response(lambda r: r.url.endswith(f"/rehearsals/{rehearsal_id}/stop")) as stop:
        page.get_by_test_id("stop-rehearsal").click()
    assert stop.value.ok
    stopped_at = time.perf_counter()
    expect(records.get_by_role("link", name="Replay")).to_have_count(before + 1)
    print(f"record listed {time.perf_counter() - stopped_at:.2f} s after the stop answered")
    assert listed == [], listed
