"""The web side: rehearsals through the app (real manager, real viser servers), the
viser websocket through the app's proxy, stored records, limits and bad input."""

from __future__ import annotations

import json
import threading
import time
from collections.abc import Callable, Iterator
from typing import Any

import pytest
from fastapi.testclient import TestClient
from sqlalchemy import select
from starlette.testclient import WebSocketDenialResponse
from starlette.websockets import WebSocketDisconnect

from countersign.orders.examples import example_bytes
from countersign.store.rehearsals import get_record
from countersign.store.tables import User
from countersign.web.rehearsal_hub import RehearsalHub
from countersign.web.routes.rehearsal_schemas import RehearsalRecordOut, RehearsalStatus
from countersign.web.viser_proxy import MAX_MALFORMED

from .conftest import World
from .described import assert_described
from .viser_client import PROTOCOL, SceneReader, encode
from .write_lock import probe_write_lock

MISSION = "search-and-sample"
ORIGIN = {"origin": "http://testserver"}
FAST = {"source": "manual", "speed": 5000}


@pytest.fixture
def app_world(world: World) -> Iterator[World]:
    """The world with the app's lifespan running (its shutdown stops every rehearsal)."""
    with TestClient(world.app):
        yield world
    assert _hub(world).count() == 0


def _hub(world: World) -> RehearsalHub:
    hub: RehearsalHub = world.app.state.rehearsals
    return hub


def _start(client: TestClient, csrf: str | None = None, **body: Any) -> dict[str, Any]:
    headers = {"X-CSRF-Token": csrf} if csrf else {}
    response = client.post(f"/api/missions/{MISSION}/rehearsals", json={**FAST, **body},
                           headers=headers)
    assert response.status_code == 201, response.text
    data: dict[str, Any] = response.json()
    return data


def _wait(client: TestClient, rehearsal: str, done: Callable[[dict[str, Any]], bool],
          timeout: float = 30.0) -> dict[str, Any]:
    deadline = time.monotonic() + timeout
    while True:
        response = client.get(f"/api/rehearsals/{rehearsal}")
        assert response.status_code == 200, response.text
        status: dict[str, Any] = response.json()["status"]
        if done(status):
            return status
        assert time.monotonic() < deadline, f"rehearsal did not get there: {status}"
        time.sleep(0.05)


def _waiting(status: dict[str, Any]) -> bool:
    return bool(status["state"] == "waiting_for_outcome")


def test_start_steer_stop_and_read_the_record(app_world: World) -> None:
    operator = app_world.client("operator")
    started = _start(operator)
    rid = started["id"]
    assert started["viewer"] == f"/rehearsal/{rid}/" and started["mission"] == MISSION
    assert started["version"] is None and started["orders_digest"].startswith("sha256:")
    first = _wait(operator, rid, _waiting)
    assert_described(RehearsalStatus, first)
    assert first["question"] and first["current_goal"]
    goal = first["current_goal"]["id"]
    chosen = operator.post(f"/api/rehearsals/{rid}/outcome", json={"outcome": "succeed"})
    assert chosen.status_code == 200, chosen.text
    after = _wait(operator, rid, lambda s: s["step"] >= 1)
    assert after["outcomes"][0] == {"goal": goal, "outcome": "succeed"}
    fault = operator.post(f"/api/rehearsals/{rid}/faults", json={"fault": "gps_loss"})
    assert fault.status_code == 200, fault.text
    assert_described(RehearsalStatus, fault.json()["status"])
    assert fault.json()["status"]["fault_notice"]
    # A fault the rehearsal does not have is the request's mistake (422, named), not a
    # conflict with the rehearsal's state.
    unknown = operator.post(f"/api/rehearsals/{rid}/faults", json={"fault": "warp_drive"})
    assert unknown.status_code == 422 and "warp_drive" in unknown.text, unknown.text
    assert operator.post(f"/api/rehearsals/{rid}/outcome",
                         json={"outcome": "maybe"}).status_code == 422

    stopped = operator.post(f"/api/rehearsals/{rid}/stop")
    assert stopped.status_code == 200, stopped.text
    digest = stopped.json()["digest"]
    assert digest.startswith("sha256:") and stopped.json()["replay"].endswith("/replay.html")

    # The record: every role reads it; the replay is viser's standalone page under a strict CSP.
    auditor = app_world.client("auditor")
    record = auditor.get(f"/api/rehearsal-records/{digest}")
    assert record.status_code == 200, record.text
    body = record.json()
    assert body["record"]["outcomes"][0] == "succeed" and body["owner"] == "operator1"
    assert body["record"]["orders"]["digest"] == started["orders_digest"]
    _assert_whole_record(app_world, digest, body["record"])
    replay = auditor.get(f"/api/rehearsal-records/{digest}/replay.html")
    assert replay.status_code == 200 and replay.headers["content-type"].startswith("text/html")
    assert "__VISER_EMBED_DATA__" in replay.text
    csp = replay.headers["content-security-policy"]
    assert "sandbox" in csp and "default-src 'none'" in csp and "connect-src data: blob:" in csp
    listed = auditor.get(f"/api/missions/{MISSION}/rehearsal-records").json()
    assert [r["digest"] for r in listed] == [digest]

    # Closed: 410 on every live route and the viewer; the events tell the story.
    assert operator.get(f"/api/rehearsals/{rid}").status_code == 410
    assert operator.post(f"/api/rehearsals/{rid}/stop").status_code == 410
    assert operator.post(f"/api/rehearsals/{rid}/outcome",
                         json={"outcome": "fail"}).status_code == 410
    assert operator.get(f"/rehearsal/{rid}/").status_code == 410
    events = app_world.client("admin").get("/api/events", params={"limit": 1000}).json()
    kinds = [e["kind"] for e in events if e["kind"].startswith("rehearsal.")]
    assert kinds == ["rehearsal.started", "rehearsal.outcome", "rehearsal.fault",
                     "rehearsal.recorded"]
    assert events[-1]["detail"]["record_digest"] == digest


def _assert_whole_record(world: World, digest: str, answered: dict[str, Any]) -> None:
    """The answer is the stored record, and RehearsalRecordOut describes it field for field."""
    with world.database.session() as db:
        stored = get_record(db, digest).record
    assert answered == stored
    assert_described(RehearsalRecordOut, stored)
    assert stored["events"] and stored["runs"]


def test_roles_and_other_peoples_rehearsals(app_world: World) -> None:
    operator, supervisor = app_world.client("operator"), app_world.client("supervisor")
    rid = _start(operator)["id"]
    mine = _start(supervisor)["id"]  # supervisors rehearse too
    for role in ("auditor", "admin"):
        refused = app_world.client(role).post(f"/api/missions/{MISSION}/rehearsals", json=FAST)
        assert refused.status_code == 403
    # Someone else's live rehearsal is not found, whatever the route (nothing is revealed).
    for method, path, body in (("get", f"/api/rehearsals/{rid}", None),
                               ("post", f"/api/rehearsals/{rid}/outcome", {"outcome": "fail"}),
                               ("post", f"/api/rehearsals/{rid}/faults", {"fault": "leak"}),
                               ("post", f"/api/rehearsals/{rid}/stop", None)):
        answer = getattr(supervisor, method)(path, **({"json": body} if body else {}))
        assert answer.status_code == 404, (path, answer.text)
        assert answer.headers["content-type"] == "application/problem+json"
    assert supervisor.get(f"/rehearsal/{rid}/").status_code == 404
    assert operator.get(f"/rehearsal/{mine}/").status_code == 404
    assert operator.get("/api/rehearsals/no-such-id").status_code == 404
    assert operator.get("/api/rehearsals/bad%20id").status_code == 422
    assert app_world.client().get(f"/rehearsal/{rid}/").status_code == 401
    # The owner's viewer: viser's client, framed by this app only.
    page = operator.get(f"/rehearsal/{rid}/")
    assert page.status_code == 200 and "<div id=\"root\">" in page.text
    assert "frame-ancestors 'self'" in page.headers["content-security-policy"]
    assert page.headers["x-frame-options"] == "SAMEORIGIN"
    assert operator.get(f"/rehearsal/{rid}/other.js").status_code == 404
    still = operator.get(f"/api/rehearsals/{rid}")
    assert still.status_code == 200  # nothing above harmed it


def test_cookie_sessions_need_csrf_and_bodies_are_checked(app_world: World) -> None:
    browser, csrf = app_world.browser("operator")
    assert browser.post(f"/api/missions/{MISSION}/rehearsals", json=FAST).status_code == 403
    rid = _start(browser, csrf)["id"]
    for body in ({"source": "dream"}, {"seed": -1}, {"path_index": 0}, {"faults": ["x"] * 9},
                 {"faults": ["gps loss; drop"]}, {"speed": 0}, {"unknown": 1},
                 {"version": 0}):
        answer = browser.post(f"/api/missions/{MISSION}/rehearsals", json={**FAST, **body},
                              headers={"X-CSRF-Token": csrf})
        assert answer.status_code == 422, (body, answer.text)
    missing = browser.post(f"/api/missions/{MISSION}/rehearsals", json={**FAST, "version": 9},
                           headers={"X-CSRF-Token": csrf})
    assert missing.status_code == 404
    nowhere = browser.post("/api/missions/nope/rehearsals", json=FAST,
                           headers={"X-CSRF-Token": csrf})
    assert nowhere.status_code == 404
    replay_of_path = browser.post(f"/api/missions/{MISSION}/rehearsals",
                                  json={**FAST, "source": "replay", "path_index": 10**9},
                                  headers={"X-CSRF-Token": csrf})
    assert replay_of_path.status_code == 422
    assert browser.post(f"/api/rehearsals/{rid}/stop").status_code == 403  # no CSRF token
    assert browser.post(f"/api/rehearsals/{rid}/stop",
                        headers={"X-CSRF-Token": csrf}).status_code == 200


def test_limits_per_user_and_in_total(app_world: World) -> None:
    hub = _hub(app_world)
    operator, supervisor = app_world.client("operator"), app_world.client("supervisor")
    ids = [_start(operator)["id"] for _ in range(hub.per_user)]
    refused = operator.post(f"/api/missions/{MISSION}/rehearsals", json=FAST)
    assert refused.status_code == 429 and "stop one first" in refused.json()["detail"]
    hub.total = hub.per_user + 1
    _start(supervisor)
    busy = supervisor.post(f"/api/missions/{MISSION}/rehearsals", json=FAST)
    assert busy.status_code == 503
    assert operator.post(f"/api/rehearsals/{ids[0]}/stop").status_code == 200
    _start(operator)  # a slot is free again


def _socket(client: TestClient, rid: str, headers: dict[str, str] | None = None) -> Any:
    return client.websocket_connect(f"/rehearsal/{rid}", subprotocols=[PROTOCOL],
                                    headers=headers if headers is not None else ORIGIN)


def test_websocket_is_refused_before_the_upgrade(app_world: World) -> None:
    operator, csrf = app_world.browser("operator")
    rid = _start(operator, csrf)["id"]
    supervisor, _ = app_world.browser("supervisor")
    anonymous = app_world.client()
    cases = [
        (anonymous, rid, ORIGIN, 401),  # no session
        (supervisor, rid, ORIGIN, 404),  # somebody else's rehearsal
        (operator, "no-such-rehearsal", ORIGIN, 404),
        (operator, rid, {"origin": "https://evil.example"}, 403),  # cross-site
        (operator, rid, {}, 403),  # a cookie without an Origin
    ]
    for client, target, headers, status in cases:
        with pytest.raises(WebSocketDenialResponse) as denied, _socket(client, target, headers):
            pass
        assert denied.value.status_code == status, (target, headers)
    # A bearer token needs no Origin (no ambient authority), but a foreign one is refused.
    token = app_world.client("operator")
    with _socket(token, rid, {}) as socket:
        SceneReader(socket).read_until(lambda r: r.button("Succeed") is not None)
    with pytest.raises(WebSocketDenialResponse), _socket(token, rid, {"origin": "http://x.y"}):
        pass
    assert operator.post(f"/api/rehearsals/{rid}/stop",
                         headers={"X-CSRF-Token": csrf}).status_code == 200
    with pytest.raises(WebSocketDenialResponse) as closed, _socket(operator, rid):
        pass
    assert closed.value.status_code == 410


def test_the_scene_through_the_proxy_and_a_gui_click(app_world: World) -> None:
    operator, csrf = app_world.browser("operator")
    rid = _start(operator, csrf)["id"]
    _wait(operator, rid, _waiting)
    with _socket(operator, rid) as socket:
        reader = SceneReader(socket)
        reader.read_until(lambda r: r.button("Succeed") is not None
                          and "FrameMessage" in r.types())
        socket.send_bytes(encode({"type": "ShareUrlRequest"}))
        reader.click(str(reader.button("Fail")))
        status = _wait(operator, rid, lambda s: s["step"] >= 1)
        assert status["outcomes"][0]["outcome"] == "fail"
    stats = app_world.app.state.rehearsal_proxies[-1]
    assert stats.dropped_share == 1 and stats.to_server >= 2


def test_malformed_frames_harm_neither_the_rehearsal_nor_the_app(app_world: World) -> None:
    operator, csrf = app_world.browser("operator")
    rid = _start(operator, csrf)["id"]
    _wait(operator, rid, _waiting)
    with _socket(operator, rid) as socket:
        reader = SceneReader(socket, hello=False)
        reader.read_until(lambda r: r.button("Succeed") is not None)
        uuid = str(reader.button("Succeed"))
        frames = [b"", b"\xc1", b"garbage", encode([1]), encode({"type": "Nope"}),
                  encode({"type": "GuiUpdateMessage", "uuid": uuid,
                          "updates": {"sync_cb": None, "value": True}}),
                  encode({"type": "GuiUpdateMessage", "uuid": uuid, "updates": {"label": 1}}),
                  encode({"type": "ViewerCameraMessage", "fov": "wide"}),
                  encode({"type": "ShareUrlRequest"})]
        with pytest.raises(WebSocketDisconnect) as closed:
            for _ in range(3):
                for frame in frames:
                    socket.send_bytes(frame)
            socket.send_text("{}")
            while True:
                socket.receive_bytes()
        assert closed.value.code == 1008
    stats = app_world.app.state.rehearsal_proxies[-1]
    assert stats.malformed == MAX_MALFORMED + 1 and stats.to_server == 0
    # The rehearsal still answers, its GUI still works through a new connection, and the app
    # still serves everyone else.
    assert operator.get(f"/api/rehearsals/{rid}").json()["status"]["step"] == 0
    with _socket(operator, rid) as socket:
        reader = SceneReader(socket)
        reader.read_until(lambda r: r.button("Succeed") is not None)
        reader.click(str(reader.button("Succeed")))
        _wait(operator, rid, lambda s: s["step"] >= 1)
    assert app_world.client("auditor").get("/api/health").status_code == 200
    assert operator.post(f"/api/rehearsals/{rid}/stop",
                         headers={"X-CSRF-Token": csrf}).status_code == 200


def test_ten_rehearsals_at_once_progress_and_stop_without_leaks(app_world: World) -> None:
    hub = _hub(app_world)
    hub.per_user = 10
    operator = app_world.client("operator")
    baseline = threading.active_count()
    ids: list[str] = []
    errors: list[str] = []
    lock = threading.Lock()

    def start(seed: int) -> None:
        response = operator.post(f"/api/missions/{MISSION}/rehearsals",
                                 json={"source": "simulate", "seed": seed, "speed": 2000})
        with lock:
            if response.status_code == 201:
                ids.append(response.json()["id"])
            else:
                errors.append(response.text)

    starters = [threading.Thread(target=start, args=(seed,)) for seed in range(10)]
    for thread in starters:
        thread.start()
    for thread in starters:
        thread.join(60)
    assert not errors and len(ids) == 10
    for rid in ids:
        _wait(operator, rid, lambda s: s["sim_time_s"] > 0 or s["state"] == "finished")
    digests = set()
    for rid in ids:
        stopped = operator.post(f"/api/rehearsals/{rid}/stop")
        assert stopped.status_code == 200, stopped.text
        digests.add(stopped.json()["digest"])
    assert len(digests) == 10  # ten seeds, ten different records
    assert hub.count() == 0
    deadline = time.monotonic() + 20
    while threading.active_count() > baseline and time.monotonic() < deadline:
        time.sleep(0.1)
    assert threading.active_count() <= baseline, [t.name for t in threading.enumerate()]


def test_faults_while_waiting_skip_and_a_record_listed_at_once(app_world: World) -> None:
    """Through the API: the auto pace (no speed), skip, a fault pressed while
    a goal waits is queued with a message, one on a finished rehearsal is refused with one,
    and the stored record is in the list as soon as the stop answers."""
    client = app_world.client("operator")
    started = client.post(f"/api/missions/{MISSION}/rehearsals", json={"source": "manual"})
    assert started.status_code == 201, started.text
    rid = started.json()["id"]
    assert started.json()["status"]["pace"] == "auto"
    assert client.post(f"/api/rehearsals/{rid}/skip").status_code == 200
    _wait(client, rid, _waiting)
    refused = client.post(f"/api/rehearsals/{rid}/skip")
    assert refused.status_code == 409 and "nothing to skip" in refused.json()["detail"]
    queued = client.post(f"/api/rehearsals/{rid}/faults", json={"fault": "gps_loss"})
    assert queued.status_code == 200, queued.text
    status = queued.json()["status"]
    assert status["fault_notice"]["text"].startswith("Fault queued: GPS loss")
    assert status["queued_faults"] == ["gps_loss"]
    again = client.post(f"/api/rehearsals/{rid}/faults", json={"fault": "gps_loss"})
    assert again.status_code == 409 and "already queued" in again.json()["detail"]
    for _ in range(10):
        status = client.get(f"/api/rehearsals/{rid}").json()["status"]
        if status["state"] == "finished":
            break
        if status["state"] == "waiting_for_outcome":
            client.post(f"/api/rehearsals/{rid}/outcome", json={"outcome": "violate"})
        else:
            client.post(f"/api/rehearsals/{rid}/skip")
        _wait(client, rid, lambda s: s["state"] != "running")
    assert status["state"] == "finished" and status["sim_time_s"] > 0
    # Finished, the status holds still: the answer is the rehearsal's own status, described.
    with app_world.database.session() as db:
        user_id = db.scalars(select(User.id).where(User.username == "operator1")).one()
    assert status == _hub(app_world).get(rid, user_id=user_id).rehearsal.status()
    assert_described(RehearsalStatus, status)
    late = client.post(f"/api/rehearsals/{rid}/faults", json={"fault": "leak"})
    assert late.status_code == 409 and "finished" in late.json()["detail"]
    begin = time.perf_counter()
    stored = client.post(f"/api/rehearsals/{rid}/stop")
    print(f"stop answered in {time.perf_counter() - begin:.2f} s")
    assert stored.status_code == 200, stored.text
    listed = client.get(f"/api/missions/{MISSION}/rehearsal-records").json()
    assert listed[0]["digest"] == stored.json()["digest"]
    record = client.get(f"/api/rehearsal-records/{stored.json()['digest']}").json()["record"]
    _assert_whole_record(app_world, stored.json()["digest"], record)


def test_a_refined_mission_is_decided_goal_inside_goal(app_world: World) -> None:
    """The status names the goal inside (`G1/G1.1#1`) and the refined goals it runs inside
    (the breadcrumb); six goals decided inside G1 reach its time-out, which the status keeps
    and RehearsalStatus describes."""
    operator = app_world.client("operator")
    orders = json.loads(example_bytes("search-and-sample-refined"))
    assert operator.post("/api/missions", json=orders).status_code == 201
    response = operator.post("/api/missions/search-and-sample-refined/rehearsals", json=FAST)
    assert response.status_code == 201, response.text
    rid = response.json()["id"]
    for step, outcome in enumerate(("succeed", "fail") * 3):
        status = _wait(operator, rid, lambda s, n=step: _waiting(s) and s["step"] == n)
        assert_described(RehearsalStatus, status)
        assert status["current_goal"]["id"].startswith("G1/G1.")
        assert status["refined"]["inside"] == [{"id": "G1", "title": "Search Area A"}]
        assert status["refined"]["timeout"] is None
        chosen = operator.post(f"/api/rehearsals/{rid}/outcome", json={"outcome": outcome})
        assert chosen.status_code == 200, chosen.text
    status = _wait(operator, rid, lambda s: _waiting(s) and s["step"] == 6)
    assert_described(RehearsalStatus, status)
    assert status["current_goal"]["id"] == "G3" and status["refined"]["inside"] == []
    timeout = status["refined"]["timeout"]
    assert (timeout["goal"], timeout["returns"]) == ("G1", "fail")
    assert operator.post(f"/api/rehearsals/{rid}/stop").status_code == 200


def test_a_rehearsal_starts_without_holding_the_write_lock(
        app_world: World, monkeypatch: pytest.MonkeyPatch) -> None:
    """Starting one builds its simulation, scene and viser server (a second or more, longer
    for large orders): on SQLite, doing that inside the write transaction made every other
    user's writes wait for it."""
    world = app_world
    hub = _hub(world)
    writable_meanwhile = probe_write_lock(world, monkeypatch, hub, "start")
    operator = world.client("operator")
    started = _start(operator)
    assert writable_meanwhile == [True]
    assert operator.post(f"/api/rehearsals/{started['id']}/stop").status_code == 200
