"""On a real rehearsal (viser server and its thread).

The pace is counted in frames, not wall time: the first choice must come after a bounded
number of frames whatever the machine's load (wall times are printed, never asserted)."""

from __future__ import annotations

import contextlib
import time

import pytest

from countersign.orders.model import Orders
from countersign.rehearse.manager import (
    GOAL_FRAMES,
    SLOW_FRAMES,
    Rehearsal,
    RehearsalManager,
    RehearsalOptions,
)
from countersign.rehearse.sim import Simulation
from countersign.rehearse.sources import make_source
from countersign.verify.legs import leg_lengths, mission_legs

from .viser_client import ViserTestClient


def _wait(predicate, timeout: float = 120.0) -> bool:  # type: ignore[no-untyped-def]
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        if predicate():
            return True
        time.sleep(0.05)
    return bool(predicate())


def _waiting(rehearsal: Rehearsal) -> bool:
    return bool(rehearsal.status()["state"] == "waiting_for_outcome")


def test_the_first_choice_comes_after_a_bounded_number_of_frames(
    manager: RehearsalManager, exemplar: Orders
) -> None:
    started = time.perf_counter()
    rehearsal = manager.start(exemplar, owner="alice", options=RehearsalOptions(source="manual"))
    with ViserTestClient(rehearsal.port, secret=rehearsal.viewer_secret) as client:
        client.hello()
        assert _wait(lambda: _waiting(rehearsal)), rehearsal.status()
        wall = time.perf_counter() - started
        status = rehearsal.status()
        print(f"first choice after {status['first_question_frame']} frames, "
              f"{status['sim_time_s']:.0f} simulated s, {wall:.2f} s wall")
        # The whole plan of G1 was flown (no shortcut), in about GOAL_FRAMES frames.
        assert status["current_goal"]["id"] == "G1"
        assert status["current_goal"]["progress"] == 1.0
        # G1's plan lasts its duration cost (5,400 s); the mission starts where G1 starts.
        assert status["sim_time_s"] >= 5_400
        assert status["first_question_frame"] <= GOAL_FRAMES + 4 * SLOW_FRAMES
        assert status["pace"] == "auto"


def test_skip_runs_to_the_next_decision(manager: RehearsalManager, exemplar: Orders) -> None:
    rehearsal = manager.start(exemplar, owner="alice",
                              options=RehearsalOptions(source="manual", speed=1.0))
    rehearsal.skip()
    assert _wait(lambda: _waiting(rehearsal))
    # At one simulated second per wall second G1 would take hours; skipping takes frames.
    assert rehearsal.status()["frames"] <= 10
    with pytest.raises(ValueError, match="nothing to skip"):
        rehearsal.skip()


def test_a_fault_pressed_while_waiting_is_queued_with_a_message(
    manager: RehearsalManager, exemplar: Orders
) -> None:
    rehearsal = manager.start(exemplar, owner="alice", options=RehearsalOptions(source="manual"))
    rehearsal.skip()
    assert _wait(lambda: _waiting(rehearsal))
    text = rehearsal.inject("leak")
    assert text.startswith("Fault queued: leak") and "G1 is waiting" in text
    status = rehearsal.status()
    assert status["queued_faults"] == ["leak"] and status["faults"] == []
    assert status["fault_notice"]["state"] == "queued"
    assert any(e["kind"] == "fault_queued" for e in status["events"])
    with pytest.raises(ValueError, match="already queued"):
        rehearsal.inject("leak")
    rehearsal.choose("succeed")
    # Applied when the next goal starts.
    status = rehearsal.status()
    assert status["faults"] == ["leak"] and status["queued_faults"] == []
    assert status["current_goal"]["id"] == "G2"


def _play_to_the_end(rehearsal: Rehearsal) -> None:
    for _ in range(20):
        if rehearsal.status()["state"] == "finished":
            return
        if _waiting(rehearsal):
            rehearsal.choose("violate")
        else:
            with contextlib.suppress(ValueError):
                rehearsal.skip()
        _wait(lambda: rehearsal.status()["state"] != "running", timeout=60)
    raise AssertionError(rehearsal.status())


def test_a_finished_rehearsal_shows_its_simulated_time(
    manager: RehearsalManager, exemplar: Orders
) -> None:
    rehearsal = manager.start(exemplar, owner="alice", options=RehearsalOptions(source="manual"),
                              controls=True)
    with ViserTestClient(rehearsal.port, secret=rehearsal.viewer_secret) as client:
        client.hello()
        _play_to_the_end(rehearsal)
        status = rehearsal.status()
        assert status["sim_time_s"] > 0 and status["energy_used_wh"] > 0
        # The CLI viewer's panel is brought up to date after the last choice too.
        assert client.wait_for(lambda c: any("finished" in t for t in c.markdown()))
        text = next(t for t in client.markdown() if "**Time:**" in t)
        print(text)
        assert "0h00m" not in text
        assert "energy" not in text.lower() or "Energy left" in text
    record = manager.stop(rehearsal.id).to_json()
    assert record["sim_time_s"] == status["sim_time_s"] > 0


def test_failing_with_a_fault_on_a_finished_rehearsal_is_refused(
    manager: RehearsalManager, exemplar: Orders
) -> None:
    rehearsal = manager.start(exemplar, owner="alice", options=RehearsalOptions(source="manual"))
    _play_to_the_end(rehearsal)
    with pytest.raises(ValueError, match="finished: GPS loss was not injected"):
        rehearsal.inject("gps_loss")


def test_the_legs_flown_are_the_verifiers_legs(exemplar: Orders) -> None:
    """Every leg between goals is flown along verify/legs' leg, of its length
    (geodesic metres) within 1e-6 relative, and priced as the budget prices a leg."""
    expected = leg_lengths(exemplar)
    for choice in ("succeed", "fail", "violate"):
        sim = Simulation(exemplar, seed=3, source=make_source("manual", exemplar))
        while sim.state != "finished":
            sim.advance(86_400.0)
            if sim.state == "waiting_for_outcome":
                sim.choose(choice)
        assert sim.flown_legs, choice
        for leg in sim.flown_legs:
            want = expected[(leg["from"], leg["outcome"])]
            assert leg["length_m"] == pytest.approx(want, rel=1e-6), leg
            assert leg["planned_m"] == pytest.approx(want, rel=1e-9), leg


def test_the_scene_draws_the_verifiers_legs_and_charts(
    manager: RehearsalManager, exemplar: Orders
) -> None:
    from countersign.orders.model import Chart

    area = exemplar.areas[0]
    chart = Chart(id="KO1", title="<b>Keep out</b>", kind="keep_out", polygon=area.polygon)
    rehearsal = manager.start(exemplar, owner="alice", options=RehearsalOptions(source="manual"),
                              charts=[chart])
    world = rehearsal._sim.world
    with ViserTestClient(rehearsal.port, secret=rehearsal.viewer_secret) as client:
        client.hello()
        assert client.wait_for(lambda c: "/vehicle" in c.scene_nodes())
        nodes = client.scene_nodes()
        legs = [n for n in nodes if n.startswith("/legs/") and not n.endswith("/label")]
        assert len(legs) == len(world.legs) > 0
        # One label of letters per leg pair (legs sharing their middle), the first leg's first.
        letter = {"succeed": "s", "fail": "f", "violate": "c"}
        labels = [nodes[n]["props"]["text"] for n in nodes if n.startswith("/leg_labels/")]
        assert 0 < len(labels) <= len(world.legs)
        assert all(set(text.split()) <= set(letter.values()) for text in labels), labels
        assert letter[world.legs[0].outcome] in nodes["/leg_labels/0"]["props"]["text"].split()
        assert world.legs == mission_legs(exemplar)[2]  # the verifier's legs, drawn
        # A chart's title is text in a label (never markup), drawn in the verifier's frame.
        assert nodes["/charts/chart_KO1/label"]["props"]["text"] == "<b>Keep out</b>"
        # No GUI in the app's viewer: the page holds the controls.
        assert not [e for e in client.gui().values() if e["type"] == "GuiButtonMessage"]
