"""A real rehearsal's viser server, driven over its websocket by a small test client."""

from __future__ import annotations

import socket
import time

import msgspec

from countersign.orders.examples import load_example
from countersign.orders.model import Orders
from countersign.rehearse.manager import RehearsalManager, RehearsalOptions

from .viser_client import ViserTestClient


def _wait(predicate, timeout: float = 20.0) -> bool:  # type: ignore[no-untyped-def]
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        if predicate():
            return True
        time.sleep(0.05)
    return bool(predicate())


def test_scene_nodes_and_a_gui_click_chooses_the_outcome(
    manager: RehearsalManager, exemplar: Orders
) -> None:
    rehearsal = manager.start(exemplar, owner="alice",
                              options=RehearsalOptions(source="manual", speed=100_000),
                              controls=True)
    with ViserTestClient(rehearsal.port, secret=rehearsal.viewer_secret) as client:
        client.hello()
        assert client.wait_for(lambda c: "/vehicle" in c.scene_nodes())
        nodes = client.scene_nodes()
        for name in ("/world/seafloor", "/world/surface", "/areas/A/outline", "/areas/A/label",
                     "/areas/LANE/fill", "/areas/BASE/label", "/vehicle/label",
                     "/contacts/V1", "/world/recovery"):
            assert name in nodes, name
        assert nodes["/areas/A/label"]["props"]["text"] == "Area A"
        theme = client.theme()
        assert theme is not None and theme["show_share_button"] is False

        # G1 is animated to the end of its plan, then the Figure 6 question waits.
        assert _wait(lambda: rehearsal.status()["state"] == "waiting_for_outcome")
        assert client.wait_for(lambda c: c.button("Fail")["props"]["disabled"] is False)
        assert any("Did goal Succeed" in text for text in client.markdown())
        client.click("Fail")
        assert _wait(lambda: rehearsal.status()["step"] == 1)
        status = rehearsal.status()
        assert status["outcomes"][0] == {"goal": "G1", "outcome": "fail"}
        # Fail on G1 leads to G3 (Search Area B) in the exemplar.
        assert _wait(lambda: (rehearsal.status()["current_goal"] or {}).get("id") == "G3")

        # The outcome is drawn into the scene: an amber marker and its label.
        assert client.wait_for(lambda c: "/outcomes/0/label" in c.scene_nodes())
        nodes = client.scene_nodes()
        assert nodes["/outcomes/0/label"]["props"]["text"] == "G1: fail"
        assert tuple(nodes["/outcomes/0"]["props"]["color"]) == (235, 160, 20)

    record = manager.stop(rehearsal.id)
    assert record.to_json()["inputs"]["choices"][0]["outcome"] == "fail"
    html = record.replay_html()
    assert html.startswith(b"<!doctype html>") and b"__VISER_EMBED_DATA__" in html


def test_a_click_in_the_wrong_state_is_ignored(
    manager: RehearsalManager, exemplar: Orders
) -> None:
    # At 1x the simulation's first goal lasts well over an hour of wall time: no outcome can
    # come from the simulation itself while the test looks, however slow the machine is.
    rehearsal = manager.start(exemplar, owner="alice",
                              options=RehearsalOptions(source="simulate", speed=1), controls=True)
    with ViserTestClient(rehearsal.port, secret=rehearsal.viewer_secret) as client:
        client.hello()
        assert client.wait_for(lambda c: "/vehicle" in c.scene_nodes())
        assert _wait(lambda: rehearsal.status()["state"] == "running")
        client.click("Succeed")  # disabled in the GUI; a crafted click must change nothing
        client.pump(0.5)
        assert rehearsal.status()["outcomes"] == []
        assert rehearsal.status()["state"] == "running"


def test_fault_button_injects_the_fault(manager: RehearsalManager, exemplar: Orders) -> None:
    rehearsal = manager.start(exemplar, owner="alice",
                              options=RehearsalOptions(source="simulate", speed=50), controls=True)
    with ViserTestClient(rehearsal.port, secret=rehearsal.viewer_secret) as client:
        client.hello()
        assert client.wait_for(lambda c: "/vehicle" in c.scene_nodes())
        client.click("Leak")
        assert _wait(lambda: "leak" in rehearsal.status()["faults"])
        # A leak is a safety-equipment failure: the exemplar's C2 ends the goal (violate).
        assert _wait(lambda: rehearsal.status()["step"] >= 1)
        assert rehearsal.status()["outcomes"][0]["outcome"] == "violate"


def test_malformed_messages_and_share_requests_do_no_harm(
    manager: RehearsalManager, exemplar: Orders
) -> None:
    rehearsal = manager.start(exemplar, owner="alice",
                              options=RehearsalOptions(source="manual", speed=2_000), controls=True)
    server = rehearsal._server
    assert server is not None
    with ViserTestClient(rehearsal.port, secret=rehearsal.viewer_secret) as client:
        client.hello()
        assert client.wait_for(lambda c: "/vehicle" in c.scene_nodes())
        uuid = client.button("Succeed")["uuid"]
        client.send({"type": "ShareUrlRequest"})
        client.send({"type": "GuiUpdateMessage", "uuid": "no-such-uuid", "updates": {"value": 1}})
        client.send({"type": "GuiUpdateMessage", "uuid": uuid, "updates": {"no_such_prop": 1}})
        client.send({"type": "GuiUpdateMessage", "uuid": uuid, "updates": "not a dict"})
        client.pump(0.5)
        assert not client.closed  # handled (and ignored) by the server's handlers
    # Undecodable frames make viser close that one connection, nothing more.
    for message in ({"type": "NoSuchMessage", "x": 1}, {"no type": True}):
        with ViserTestClient(rehearsal.port, secret=rehearsal.viewer_secret) as client:
            client.send(message)
            client.pump(0.5)
            assert client.closed
    bad_frames: list[bytes | str] = [
        b"\x00\x01garbage", "text frame", msgspec.msgpack.encode([1, 2, 3]),
        msgspec.msgpack.encode({"type": "ViewerCameraMessage", "wxyz": "x"}),
    ]
    for frame in bad_frames:
        with ViserTestClient(rehearsal.port, secret=rehearsal.viewer_secret) as client:
            client.send_raw(frame)
            client.pump(0.3)
    time.sleep(0.5)
    assert server._share_tunnel is None  # no tunnel was opened
    assert rehearsal.status()["state"] in ("running", "waiting_for_outcome")
    # The server still serves a new client, with the whole scene.
    with ViserTestClient(rehearsal.port, secret=rehearsal.viewer_secret) as client:
        client.hello()
        assert client.wait_for(lambda c: "/areas/A/outline" in c.scene_nodes())


def test_stop_frees_the_port(manager: RehearsalManager, exemplar: Orders) -> None:
    rehearsal = manager.start(exemplar, owner="alice",
                              options=RehearsalOptions(source="simulate", speed=1_000))
    port = rehearsal.port
    with socket.create_connection(("127.0.0.1", port), timeout=5):
        pass
    first = manager.stop(rehearsal.id)
    assert manager.stop(rehearsal.id) is first  # idempotent
    assert rehearsal.status()["state"] == "stopped"
    with socket.socket() as probe:
        assert probe.connect_ex(("127.0.0.1", port)) != 0


HOSTILE = '<iframe srcdoc="<script>parent.__pwned=1</script>"></iframe><img src=x onerror=x()>'


def test_user_text_reaches_the_scene_as_text_never_markdown(
    manager: RehearsalManager, exemplar: Orders
) -> None:
    """Viser's markdown passes raw HTML, so the goal's title (the orders author's
    text) is shown in a read-only text field and never enters markdown."""
    from countersign.orders.canonical import orders_to_json
    from countersign.orders.reader import orders_from_data

    data = orders_to_json(exemplar)
    for goal in data["goals"]:
        goal["title"] = HOSTILE + " [x](javascript:alert(1)) ![i](http://e/x.png)"
    # Area titles reach the scene as 3D labels, the mission title as the panel's label.
    for area in data["areas"]:
        area["title"] = HOSTILE + " [a](javascript:alert(1))"
    data["title"] = HOSTILE
    hostile = orders_from_data(data)
    rehearsal = manager.start(hostile, owner="alice",
                              options=RehearsalOptions(source="manual", speed=100_000),
                              controls=True)
    with ViserTestClient(rehearsal.port, secret=rehearsal.viewer_secret) as client:
        client.hello()
        assert _wait(lambda: rehearsal.status()["state"] == "waiting_for_outcome")
        assert client.wait_for(lambda c: any("Goal:" in t for t in c.markdown()))
        assert client.wait_for(lambda c: any(
            e["props"].get("value", "").startswith(HOSTILE) for e in c.gui().values()
            if e["type"] == "GuiTextMessage"))
        for text in client.markdown():
            assert "<" not in text and "](" not in text, text
        # viser draws a scene label's text as glyphs (a texture), never as HTML or markdown:
        # the hostile area titles go there verbatim, as text.
        labels = [n["props"]["text"] for n in client.scene_nodes().values()
                  if n["type"] == "LabelMessage"]
        assert sum(t.startswith(HOSTILE) for t in labels) == len(data["areas"]), labels
        # The panel's label is React text in viser's client (ControlPanel), not markdown.
        assert any(m.get("type") == "SetGuiPanelLabelMessage" and m.get("label") == HOSTILE[:80]
                   for m in client.messages)
    manager.stop(rehearsal.id)


def test_a_goal_inside_a_refinement_is_decided_in_the_scene(manager: RehearsalManager) -> None:
    """The viser panel's Succeed decides G1's first goal inside (G1/G1.1#1); its marker is
    labelled by its last id (G1.1#1), so the goals of one refinement, which share an area, do
    not pile full ids up there."""
    orders = load_example("search-and-sample-refined")
    rehearsal = manager.start(orders, owner="alice",
                              options=RehearsalOptions(source="manual", speed=100_000),
                              controls=True)
    with ViserTestClient(rehearsal.port, secret=rehearsal.viewer_secret) as client:
        client.hello()
        assert client.wait_for(lambda c: "/vehicle" in c.scene_nodes())
        assert _wait(lambda: rehearsal.status()["state"] == "waiting_for_outcome")
        assert rehearsal.status()["current_goal"]["id"] == "G1/G1.1#1"
        assert client.wait_for(lambda c: c.button("Succeed")["props"]["disabled"] is False)
        client.click("Succeed")
        assert _wait(lambda: rehearsal.status()["step"] == 1)
        assert rehearsal.status()["outcomes"][0] == {"goal": "G1/G1.1#1", "outcome": "succeed"}
        assert client.wait_for(lambda c: "/outcomes/0/label" in c.scene_nodes())
        assert client.scene_nodes()["/outcomes/0/label"]["props"]["text"] == "G1.1#1: succeed"
    manager.stop(rehearsal.id)
