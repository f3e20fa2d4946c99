"""A team's rehearsal on a real viser server: one scene with every vehicle (its own
colour, its vehicle id as a text label), their paths, the meeting points and the meeting."""

from __future__ import annotations

import itertools
import json
import time
from typing import Any

from countersign.orders.examples import example_bytes
from countersign.orders.reader import orders_from_data
from countersign.rehearse.label_layout import LINE, width_of
from countersign.rehearse.manager import RehearsalManager, RehearsalOptions
from countersign.rehearse.team_rehearsal import TeamRehearsal

from .viser_client import ViserTestClient

MARKUP = "<img src=x onerror=alert(1)> **Area C**"


def _wait(predicate: Any, timeout: float = 300.0) -> bool:
    # Generous: the machine is shared; this bounds a hang, it does not time anything.
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        if predicate():
            return True
        time.sleep(0.1)
    return bool(predicate())


def test_one_scene_shows_every_vehicle_their_paths_and_the_meeting(
        manager: RehearsalManager) -> None:
    data = json.loads(example_bytes("search-and-sample-team"))
    # The orders author's text reaches the scene as text, never markup.
    for member in data["team"]:
        for area in member["orders"]["areas"]:
            if area["id"] == "C":
                area["title"] = MARKUP
    orders = orders_from_data(data)
    rehearsal = manager.start(orders, owner="alice",
                              options=RehearsalOptions(source="simulate", speed=100_000))
    assert isinstance(rehearsal, TeamRehearsal)
    with ViserTestClient(rehearsal.port, secret=rehearsal.viewer_secret) as client:
        client.hello()
        vehicles = {"remus-100": "/vehicles/remus-100_0", "vehicle-2": "/vehicles/vehicle-2_1"}
        assert client.wait_for(lambda c: all(v in c.scene_nodes() for v in vehicles.values()))
        nodes = client.scene_nodes()
        colours = set()
        for vehicle, node in vehicles.items():
            assert nodes[f"{node}/label"]["props"]["text"] == vehicle
            colours.add(tuple(nodes[node]["props"]["color"]))
        assert len(colours) == 2
        # Both members' areas in one frame, the shared ones once; the meeting points.
        for name in ("/areas/A/outline", "/areas/B/label", "/areas/D/fill", "/areas/C/label",
                     "/areas/BASE/label", "/meetings/R1/remus-100", "/meetings/R1/vehicle-2",
                     "/meetings/R1/label", "/world/surface"):
            assert name in nodes, name
        assert nodes["/areas/C/label"]["props"]["text"] == MARKUP
        assert nodes["/meetings/R1/label"]["props"]["text"] == "meeting R1"
        # Both vehicles' meeting points are the one Area C: they lie close together.
        a = nodes["/meetings/R1/remus-100"]["props"]
        b = nodes["/meetings/R1/vehicle-2"]["props"]
        assert a["color"] == b["color"]
        assert _near(_position(client, "/meetings/R1/remus-100"),
                     _position(client, "/meetings/R1/vehicle-2"))

        assert _wait(lambda: rehearsal.status()["state"] == "finished")
        status = rehearsal.status()
        assert [m["vehicle"] for m in status["team"]["members"]] == ["remus-100", "vehicle-2"]
        assert status["team"]["meetings"][0]["meet"] == "R1"
        # Each vehicle's path in its colour, and the meeting drawn where it happened.
        assert client.wait_for(lambda c: any("met at R1" in str(n["props"].get("text"))
                                             for n in c.scene_nodes().values()))
        nodes = client.scene_nodes()
        for node in vehicles.values():
            trail = f"/trails/{node.rsplit('/', 1)[1]}/0"
            assert trail in nodes, trail
        met = [n["props"]["text"] for n in nodes.values()
               if "met at R1" in str(n["props"].get("text"))]
        # One label for the one meeting, naming both vehicles (a marker at each).
        assert len(met) == 1 and met[0].startswith("remus-100, vehicle-2 met at R1: ")

    record = manager.stop(rehearsal.id)
    body = record.to_json()
    assert body["team"]["vehicles"] == ["remus-100", "vehicle-2"]
    assert all(e["vehicle"] in ("remus-100", "vehicle-2") for e in body["events"])
    assert record.replay_html().startswith(b"<!doctype html>")


def _position(client: ViserTestClient, name: str) -> tuple[float, float, float]:
    """The node's latest position (set at creation, or by a later update)."""
    position = None
    for message in client.messages:
        if message.get("name") != name:
            continue
        if "position" in message:  # SetPositionMessage
            position = message["position"]
    assert position is not None, name
    return (float(position[0]), float(position[1]), float(position[2]))


def _near(a: tuple[float, float, float], b: tuple[float, float, float]) -> bool:
    return bool(sum((x - y) ** 2 for x, y in zip(a, b, strict=True)) ** 0.5 < 1.0)


def test_the_live_loop_runs_until_every_vehicle_has_ended() -> None:
    # remus-100 (first in the team) aborts on Return to Base while vehicle-2 still flies home:
    # the rehearsal's thread must go on by the team's state, not by its first member's.
    rehearsal = TeamRehearsal(orders_from_data(json.loads(example_bytes(
        "search-and-sample-team"))), owner="alice", headless=True,
        options=RehearsalOptions(source="replay", speed=100_000),
        paths={"remus-100": 2, "vehicle-2": 1})
    rehearsal.start()
    try:
        assert _wait(lambda: rehearsal.status()["state"] == "finished"), rehearsal.status()
        team = rehearsal.status()["team"]
        assert team["joint_end"] == "remus-100:ABORT + vehicle-2:COMPLETE"
        ends = {m["vehicle"]: m["sim_time_s"] for m in team["members"]}
        assert ends["remus-100"] < ends["vehicle-2"]
    finally:
        record = rehearsal.stop()
    assert record.to_json()["team"]["paths"] == {"remus-100": 2, "vehicle-2": 1}


def _drawn_at(client: ViserTestClient, nodes: dict[str, Any],
              name: str) -> tuple[float, float, float]:
    """Where a node is drawn: its position within every ancestor that has one (a path prefix
    the scene never placed is an identity frame at the origin)."""
    parts = name.strip("/").split("/")
    total = [0.0, 0.0, 0.0]
    for depth in range(1, len(parts) + 1):
        node = "/" + "/".join(parts[:depth])
        placed = [m["position"] for m in client.messages
                  if m.get("name") == node and "position" in m]
        if node in nodes and placed:
            total = [t + float(p) for t, p in zip(total, placed[-1], strict=True)]
    return (total[0], total[1], total[2])


def test_the_meeting_label_is_drawn_at_the_meeting_clear_of_area_titles(
        manager: RehearsalManager) -> None:
    orders = orders_from_data(json.loads(example_bytes("search-and-sample-team")))
    rehearsal = manager.start(orders, owner="alice",
                              options=RehearsalOptions(source="simulate", speed=0.1))
    try:
        with ViserTestClient(rehearsal.port, secret=rehearsal.viewer_secret) as client:
            client.hello()
            assert client.wait_for(lambda c: "/meetings/R1/label" in c.scene_nodes())
            nodes = client.scene_nodes()
            labels = {name: _drawn_at(client, nodes, name) for name in nodes
                      if name.endswith("/label") and name.startswith(("/areas/", "/meetings/"))}
            assert any("traffic lane" in nodes[n]["props"]["text"] for n in labels), labels
            # By its meeting point (above it, moved north a few lines at most).
            label = labels["/meetings/R1/label"]
            anchor = _position(client, "/meetings/R1/remus-100")
            assert abs(label[0] - anchor[0]) < 1e-6 and 0 <= label[1] - anchor[1] <= 4 * LINE, (
                label, anchor)
            # No two titles' boxes on the chart overlap where they are drawn.
            for (a, at), (b, bt) in itertools.combinations(labels.items(), 2):
                half = (width_of(nodes[a]["props"]["text"]) +
                        width_of(nodes[b]["props"]["text"])) / 2
                assert abs(at[1] - bt[1]) >= LINE - 1e-6 or abs(at[0] - bt[0]) >= half - 1e-6, (
                    a, at, b, bt)
    finally:
        manager.stop(rehearsal.id)
