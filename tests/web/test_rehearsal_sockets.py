"""And, the rehearsal viewer's sockets (real viser servers):
viser's port answers only the app's proxy, the sandboxed viewer gets in with a per-rehearsal
ticket that opens nothing else, sockets are capped per rehearsal and per user and end with
their session, and idle rehearsals make room when every slot is taken."""

from __future__ import annotations

import re
import time
from collections.abc import Iterator
from typing import Any

import pytest
from fastapi.testclient import TestClient
from starlette.testclient import WebSocketDenialResponse
from starlette.websockets import WebSocketDisconnect
from websockets.exceptions import ConnectionClosed, InvalidHandshake, InvalidStatus
from websockets.sync.client import connect as raw_connect

from countersign.web.rehearsal_hub import RehearsalHub

from .conftest import World
from .viser_client import PROTOCOL, SceneReader, encode

MISSION = "search-and-sample"
FAST = {"source": "manual", "speed": 5000}
NULL_ORIGIN = {"origin": "null"}  # what a sandboxed (opaque-origin) document sends


@pytest.fixture
def app_world(world: World) -> Iterator[World]:
    with TestClient(world.app):
        yield world


def _hub(world: World) -> RehearsalHub:
    hub: RehearsalHub = world.app.state.rehearsals
    return hub


def _start(client: TestClient, csrf: str | None = None) -> str:
    response = client.post(f"/api/missions/{MISSION}/rehearsals", json=FAST,
                           headers={"X-CSRF-Token": csrf} if csrf else {})
    assert response.status_code == 201, response.text
    return str(response.json()["id"])


def _status(client: TestClient, rid: str) -> dict[str, Any]:
    response = client.get(f"/api/rehearsals/{rid}")
    assert response.status_code == 200, response.text
    status: dict[str, Any] = response.json()["status"]
    return status


def _wait_waiting(client: TestClient, rid: str) -> None:
    deadline = time.monotonic() + 30
    while _status(client, rid)["state"] != "waiting_for_outcome":
        assert time.monotonic() < deadline
        time.sleep(0.05)


def _ticket_path(client: TestClient, rid: str) -> str:
    """The viewer URL the owner's /rehearsal/{id}/ sends the frame to."""
    answer = client.get(f"/rehearsal/{rid}/", follow_redirects=False)
    assert answer.status_code == 303, answer.text
    location = answer.headers["location"]
    assert re.fullmatch(rf"/rehearsal/{rid}/t/[A-Za-z0-9_-]{{40,}}/", location), location
    return location


def _ticket_socket(client: TestClient, path: str) -> Any:
    return client.websocket_connect(path.rstrip("/"), subprotocols=[PROTOCOL],
                                    headers=NULL_ORIGIN)


def test_viser_port_refuses_a_local_process_without_the_secret(app_world: World) -> None:
    operator, csrf = app_world.browser("operator")
    rid = _start(operator, csrf)
    _wait_waiting(operator, rid)
    port = _status(operator, rid)["port"]
    # The proxy (with the secret) sees the controls; take the Fail button's id from it.
    with _ticket_socket(operator, _ticket_path(operator, rid)) as socket:
        reader = SceneReader(socket)
        reader.read_until(lambda r: r.button("Fail") is not None)
        fail = str(reader.button("Fail"))
    # A local process with no credentials: viser closes it before any message is handled.
    with raw_connect(f"ws://127.0.0.1:{port}", subprotocols=[PROTOCOL],  # type: ignore[list-item]
                     open_timeout=10, proxy=None) as intruder:
        camera = {"type": "ViewerCameraMessage", "wxyz": [1.0, 0.0, 0.0, 0.0],
                  "position": [0.0, -50.0, 30.0], "fov": 1.0, "near": 0.01, "far": 1000.0,
                  "image_height": 600, "image_width": 800, "look_at": [0.0, 0.0, 0.0],
                  "up_direction": [0.0, 0.0, 1.0]}
        with pytest.raises(ConnectionClosed):
            intruder.send(encode(camera))
            intruder.send(encode({"type": "GuiUpdateMessage", "uuid": fail,
                                  "updates": {"value": True}}))
            while True:  # nothing of the scene is sent to it either
                frame = intruder.recv(timeout=10)
                assert not isinstance(frame, bytes) or len(frame) < 16, "scene leaked"
    # The click never landed: the rehearsal still waits for its first outcome.
    deadline = time.monotonic() + 2.0
    while time.monotonic() < deadline:
        status = _status(operator, rid)
        assert status["step"] == 0 and status["state"] == "waiting_for_outcome", status
        time.sleep(0.1)


def test_the_sandboxed_viewer_gets_in_with_a_ticket_that_opens_nothing_else(
        app_world: World) -> None:
    operator, csrf = app_world.browser("operator")
    rid = _start(operator, csrf)
    other = _start(operator, csrf)
    path = _ticket_path(operator, rid)
    ticket = path.rstrip("/").rsplit("/", 1)[1]
    page = app_world.client().get(path)  # no cookie: the ticket is the authority
    assert page.status_code == 200 and "<div id=\"root\">" in page.text
    csp = page.headers["content-security-policy"]
    assert csp.startswith("sandbox allow-scripts;") and "allow-same-origin" not in csp
    with _ticket_socket(app_world.client(), path) as socket:
        SceneReader(socket).read_until(lambda r: r.button("Succeed") is not None)
    # Not for another rehearsal, not with a foreign Origin, not made up, not for the API.
    anonymous = app_world.client()
    assert anonymous.get(f"/rehearsal/{other}/t/{ticket}/").status_code == 403
    assert anonymous.get(f"/rehearsal/{rid}/t/{'x' * 43}/").status_code == 403
    for target, headers in ((f"/rehearsal/{other}/t/{ticket}", NULL_ORIGIN),
                            (f"/rehearsal/{rid}/t/{'x' * 43}", NULL_ORIGIN),
                            (path.rstrip("/"), {"origin": "https://evil.example"})):
        with pytest.raises(WebSocketDenialResponse) as denied, anonymous.websocket_connect(
                target, subprotocols=[PROTOCOL], headers=headers):
            pass
        assert denied.value.status_code == 403, target
    for header in ({"Authorization": f"Bearer {ticket}"}, {"X-CSRF-Token": ticket}):
        assert anonymous.get("/api/auth/me", headers=header).status_code == 401
        assert anonymous.post("/api/tokens", json={"name": "x"},
                              headers=header).status_code in (401, 404)
    # Somebody else cannot mint one for this rehearsal.
    supervisor, _ = app_world.browser("supervisor")
    assert supervisor.get(f"/rehearsal/{rid}/", follow_redirects=False).status_code == 404


def test_a_ticket_expires_for_new_sockets(app_world: World) -> None:
    operator, csrf = app_world.browser("operator")
    rid = _start(operator, csrf)
    _hub(app_world).viewers.ttl_s = 0.0
    path = _ticket_path(operator, rid)
    time.sleep(0.01)
    assert app_world.client().get(path).status_code == 403


def test_sockets_are_capped_per_rehearsal_and_per_user(app_world: World) -> None:
    viewers = _hub(app_world).viewers
    viewers.per_rehearsal, viewers.per_user = 2, 3
    operator, csrf = app_world.browser("operator")
    first, second = _start(operator, csrf), _start(operator, csrf)
    path = _ticket_path(operator, first)
    with _ticket_socket(operator, path), _ticket_socket(operator, path):
        with pytest.raises(WebSocketDenialResponse) as full, _ticket_socket(operator, path):
            pass
        assert full.value.status_code == 429
        other = _ticket_path(operator, second)
        with _ticket_socket(operator, other):
            with pytest.raises(WebSocketDenialResponse) as mine, _ticket_socket(operator, other):
                pass
            assert mine.value.status_code == 429 and "you have 3" in mine.value.json()["detail"]
    with _ticket_socket(operator, path):  # closed sockets free their places
        pass


def test_sockets_stop_relaying_at_logout(app_world: World) -> None:
    operator, csrf = app_world.browser("operator")
    rid = _start(operator, csrf)
    path = _ticket_path(operator, rid)
    with _ticket_socket(app_world.client(), path) as socket:
        reader = SceneReader(socket)
        reader.read_until(lambda r: r.button("Succeed") is not None)
        assert operator.post("/api/auth/logout",
                             headers={"X-CSRF-Token": csrf}).status_code == 204
        with pytest.raises(WebSocketDisconnect) as closed:
            while True:
                socket.receive_bytes()
        assert closed.value.code == 1008
    assert app_world.client().get(path).status_code == 403  # the ticket went with it


def test_sockets_of_a_session_ended_elsewhere_stop_within_the_check(
        app_world: World, monkeypatch: pytest.MonkeyPatch) -> None:
    """A session closed by another server process (here: straight in the database) is
    noticed by the periodic check."""
    from countersign.store.tables import Session

    monkeypatch.setattr("countersign.web.routes.rehearsals.SESSION_CHECK_S", 0.2)
    operator, csrf = app_world.browser("operator")
    rid = _start(operator, csrf)
    path = _ticket_path(operator, rid)
    with _ticket_socket(app_world.client(), path) as socket:
        SceneReader(socket).read_until(lambda r: r.button("Succeed") is not None)
        with app_world.database.session(write=True) as db:
            db.query(Session).delete()
            db.commit()
        with pytest.raises(WebSocketDisconnect) as closed:
            while True:
                socket.receive_bytes()
        assert closed.value.code == 1008


def test_idle_rehearsals_make_room_when_every_slot_is_taken(app_world: World) -> None:
    hub = _hub(app_world)
    hub.total = 1
    operator, supervisor = app_world.client("operator"), app_world.client("supervisor")
    idle = _start(operator)
    busy = supervisor.post(f"/api/missions/{MISSION}/rehearsals", json=FAST)
    assert busy.status_code == 503  # not idle long enough: nobody is evicted
    live = hub.get(idle, user_id=hub._live[idle].user_id)
    live.rehearsal.last_activity -= hub.evict_idle_s + 1
    _start(supervisor)
    assert _status(operator, idle)["state"] == "stopped"
    assert operator.post(f"/api/rehearsals/{idle}/stop").status_code == 200  # still recorded


def test_raw_socket_without_secret_is_refused_at_handshake_or_closed(
        app_world: World) -> None:
    """Even the handshake's HTTP side gives nothing to act with."""
    operator = app_world.client("operator")
    rid = _start(operator)
    port = _status(operator, rid)["port"]
    try:
        with raw_connect(f"ws://127.0.0.1:{port}", open_timeout=10, proxy=None) as intruder, \
                pytest.raises(ConnectionClosed):
            while True:
                intruder.recv(timeout=10)
    except (InvalidStatus, InvalidHandshake):
        pass
