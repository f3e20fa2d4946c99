"""The rehearsal view in a real browser: an operator starts a rehearsal, viser's scene loads
through the app's proxy (the iframe at /rehearsal/{id}/, its websocket checked and relayed),
shows something (a screenshot that is not blank), an outcome click advances the rehearsal, and
stopping it lists the record with its replay."""

from __future__ import annotations

import re
from pathlib import Path
from statistics import pvariance

import pytest
from playwright.sync_api import Page, expect

from .conftest import Server
from .test_roles import sign_in


def scene_variance(shot: Path) -> float:
    """How much the 3D view varies in grey: near 0 for a blank or washed-out scene."""
    from PIL import Image

    with Image.open(shot) as image:
        # The 3D view only: left of viser's GUI panel, below its notifications.
        width, height = image.size
        scene = image.convert("L").crop((0, int(height * 0.35), int(width * 0.55),
                                         int(height * 0.95))).resize((120, 80))
        return float(pvariance([scene.getpixel((x, y)) for y in range(80) for x in range(120)]))


def test_operator_rehearses_in_the_browser(page: Page, server: Server, own_exemplar: str,
                                           tmp_path_factory: pytest.TempPathFactory) -> None:
    del server
    sign_in(page, "operator")
    page.goto(f"/missions/{own_exemplar}?tab=rehearse")
    expect(page.get_by_role("tab", name="Rehearse")).to_have_attribute("aria-selected", "true")
    page.get_by_test_id("rehearsal-speed").fill("5000")
    page.get_by_test_id("start-rehearsal").click()

    frame = page.get_by_test_id("viser-frame")
    # Generous timeouts: starting a viser server and the simulation on a loaded machine.
    expect(frame).to_be_visible(timeout=60_000)
    expect(frame).to_have_attribute("src", re.compile(r"^/rehearsal/[A-Za-z0-9_-]+/$"))
    viewer = page.frame_locator('[data-testid="viser-frame"]')
    expect(viewer.locator("canvas").first).to_be_visible()
    # The page holds the controls: viser's panel has none.
    expect(viewer.get_by_role("button", name="Succeed")).to_have_count(0)

    expect(page.get_by_test_id("rehearsal-state")).to_have_text("Waiting for the outcome",
                                                                 timeout=60_000)
    # The first goal of the exemplar is current, in the status line and in the graph.
    expect(page.get_by_test_id("current-goal")).to_have_text(re.compile("Search Area A"))
    expect(page.get_by_test_id("graph-current")).to_contain_text("G1")

    shots = tmp_path_factory.getbasetemp() / "artifacts"
    shots.mkdir(exist_ok=True)
    shot = shots / "rehearsal-scene.png"
    messages: list[str] = []
    page.on("console", lambda m: messages.append(f"{m.type}: {m.text}"))
    # The scene fades in as software WebGL draws its first frames, slowly on a busy machine:
    # look again until it shows something, for up to a minute.
    variance = 0.0
    for _ in range(30):
        page.wait_for_timeout(2000)
        frame.screenshot(path=str(shot), timeout=90_000)
        variance = scene_variance(shot)
        if variance > 50:
            break
    print(f"rehearsal screenshot: {shot} (variance {variance:.1f})")
    assert variance > 50, f"the scene looks blank (variance {variance:.1f})"

    page.get_by_test_id("outcome-succeed").click()
    expect(page.get_by_test_id("rehearsal-step")).to_have_text("1")
    expect(page.get_by_test_id("graph-current")).to_contain_text("G2")

    page.get_by_test_id("stop-rehearsal").click()
    records = page.get_by_test_id("rehearsal-records")
    expect(records.get_by_role("link", name="Replay")).to_have_count(1)
    expect(page.get_by_test_id("viser-frame")).to_have_count(0)

    # The stored replay plays offline: viser's standalone page, sandboxed, draws the scene.
    href = records.get_by_role("link", name="Replay").get_attribute("href")
    assert href and href.endswith("/replay.html")
    page.goto(href)
    expect(page.locator("canvas").first).to_be_visible()
