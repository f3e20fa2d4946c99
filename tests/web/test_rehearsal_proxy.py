"""The viser websocket proxy (web/viser_proxy.py) against a real viser server: frames pass
both ways, share-link requests are dropped, malformed or tampering frames never reach viser and
cost the browser its connection, never the server."""

from __future__ import annotations

import threading
from collections.abc import Iterator

import msgspec
import pytest
import viser
import zstandard
from starlette.applications import Starlette
from starlette.routing import WebSocketRoute
from starlette.testclient import TestClient
from starlette.websockets import WebSocket, WebSocketDisconnect

from countersign.web import viser_proxy
from countersign.web.viser_proxy import ProxyStats, open_upstream, relay

from .viser_client import PROTOCOL, SceneReader, decode_frame, encode


@pytest.fixture
def server() -> Iterator[viser.ViserServer]:
    started = viser.ViserServer(host="127.0.0.1", port=0, verbose=False)
    try:
        yield started
    finally:
        started.stop()


def _proxy_app(port: int, seen: list[ProxyStats]) -> Starlette:
    async def endpoint(websocket: WebSocket) -> None:
        upstream = await open_upstream(port, list(websocket.scope.get("subprotocols", [])))
        await websocket.accept(subprotocol=upstream.subprotocol)
        stats = ProxyStats()
        seen.append(stats)
        await relay(websocket, upstream, stats)

    return Starlette(routes=[WebSocketRoute("/ws", endpoint)])


def test_frames_pass_and_a_click_reaches_viser(server: viser.ViserServer) -> None:
    clicked = threading.Event()
    button = server.gui.add_button("Succeed")
    button.on_click(lambda _event: clicked.set())
    server.scene.add_frame("/vehicle")
    seen: list[ProxyStats] = []
    with TestClient(_proxy_app(server.get_port(), seen)) as client, \
            client.websocket_connect("/ws", subprotocols=[PROTOCOL]) as socket:
        reader = SceneReader(socket)
        reader.read_until(lambda r: r.button("Succeed") is not None
                          and "FrameMessage" in r.types())
        reader.click(str(reader.button("Succeed")))
        assert clicked.wait(10)
    assert seen[0].to_server == 2 and seen[0].to_browser >= 1


def test_share_requests_are_dropped_both_ways(server: viser.ViserServer) -> None:
    seen: list[ProxyStats] = []
    with TestClient(_proxy_app(server.get_port(), seen)) as client, \
            client.websocket_connect("/ws", subprotocols=[PROTOCOL]) as socket:
        server.gui.add_button("ready")
        SceneReader(socket).read_until(lambda r: r.button("ready") is not None)
        socket.send_bytes(encode({"type": "ShareUrlRequest"}))
        socket.send_bytes(encode({"type": "ShareUrlDisconnect"}))
        clicked = threading.Event()
        probe = server.gui.add_button("probe")
        probe.on_click(lambda _event: clicked.set())
        reader = SceneReader(socket, hello=False)
        reader.read_until(lambda r: r.button("probe") is not None)
        reader.click(str(reader.button("probe")))
        assert clicked.wait(10)  # later frames still pass
    assert seen[0].dropped_share == 2
    assert getattr(server, "_share_tunnel", None) is None  # viser never heard of them


def test_share_url_updates_from_the_server_are_removed() -> None:
    batch = {"messages": [{"type": "ShareUrlUpdated", "share_url": "https://share.example/x"},
                          {"type": "FrameMessage", "name": "/a"}],
             "timestampSec": 1.0, "binaryBufferLengths": [8]}
    inner = msgspec.msgpack.encode(batch)
    compressed = zstandard.ZstdCompressor().compress(inner)
    head = len(inner).to_bytes(8, "little") + len(compressed).to_bytes(8, "little") + compressed
    buffer = bytes(range(8))
    frame = head + b"\0" * (-len(head) % 8) + buffer
    stripped, removed = viser_proxy.strip_share_from_server(frame)
    assert removed == 1
    assert [m["type"] for m in decode_frame(stripped)] == ["FrameMessage"]
    assert stripped.endswith(buffer) and (len(stripped) - len(buffer)) % 8 == 0
    untouched = head + b"\0" * (-len(head) % 8) + buffer
    plain = msgspec.msgpack.encode({"messages": [{"type": "FrameMessage"}],
                                    "timestampSec": 1.0, "binaryBufferLengths": []})
    zplain = zstandard.ZstdCompressor().compress(plain)
    other = len(plain).to_bytes(8, "little") + len(zplain).to_bytes(8, "little") + zplain
    assert viser_proxy.strip_share_from_server(other) == (other, 0)
    assert viser_proxy.strip_share_from_server(b"short") == (b"short", 0)
    assert untouched != stripped


BAD_FRAMES = [
    b"",
    b"\xc1",  # never valid msgpack
    b"not msgpack at all",
    encode([1, 2, 3]),
    encode({"no": "type"}),
    encode({"type": 7}),
    encode({"type": "NoSuchMessage"}),
    encode({"type": "SetCameraPositionMessage", "position": [0, 0, 0]}),  # server -> client
    encode({"type": "ViewerCameraMessage"}),  # fields missing
    encode({"type": "GuiUpdateMessage", "uuid": "x", "updates": {"sync_cb": 1}}),
    encode({"type": "GuiUpdateMessage", "uuid": "x", "updates": []}),
]


def test_malformed_frames_never_reach_viser_and_cut_off_the_browser(
        server: viser.ViserServer) -> None:
    clicked = threading.Event()
    button = server.gui.add_button("Fail")
    button.on_click(lambda _event: clicked.set())
    seen: list[ProxyStats] = []
    app = _proxy_app(server.get_port(), seen)
    with TestClient(app) as client:
        with client.websocket_connect("/ws", subprotocols=[PROTOCOL]) as socket:
            reader = SceneReader(socket, hello=False)
            reader.read_until(lambda r: r.button("Fail") is not None)
            uuid = str(reader.button("Fail"))
            # The server's own state is the target of the tampering frame: still intact after.
            socket.send_bytes(encode({"type": "GuiUpdateMessage", "uuid": uuid,
                                      "updates": {"sync_cb": "boom", "value": True}}))
            socket.send_text("text frames are not viser's")
            for frame in BAD_FRAMES[:6]:
                socket.send_bytes(frame)
            with pytest.raises(WebSocketDisconnect) as closed:
                for frame in BAD_FRAMES[6:]:
                    socket.send_bytes(frame)
                while True:
                    socket.receive_bytes()
            assert closed.value.code == 1008
        assert seen[0].malformed > viser_proxy.MAX_MALFORMED and seen[0].to_server == 0
        # The rehearsal's server is unharmed: a new browser connects and its click works.
        with client.websocket_connect("/ws", subprotocols=[PROTOCOL]) as socket:
            reader = SceneReader(socket)
            reader.read_until(lambda r: r.button("Fail") is not None)
            reader.click(str(reader.button("Fail")))
            assert clicked.wait(10)


def test_oversized_frames_close_the_browser_only(server: viser.ViserServer) -> None:
    seen: list[ProxyStats] = []
    with TestClient(_proxy_app(server.get_port(), seen)) as client:
        with client.websocket_connect("/ws", subprotocols=[PROTOCOL]) as socket:
            socket.send_bytes(b"\x81" + b"x" * (viser_proxy.MAX_FRAME + 1))
            with pytest.raises(WebSocketDisconnect) as closed:
                while True:
                    socket.receive_bytes()
            assert closed.value.code == 1009
        with client.websocket_connect("/ws", subprotocols=[PROTOCOL]) as socket:
            server.gui.add_button("still here")
            SceneReader(socket).read_until(lambda r: r.button("still here") is not None)
