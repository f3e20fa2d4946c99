"""A small viser websocket client for tests: speaks the wire protocol of viser 1.1 directly.

Server -> client frames: [8 bytes msgpack size][8 bytes compressed size][zstd(msgpack)]
[padding][raw binary buffers]; the msgpack holds {"messages": [...]} where each message is a
dict with a "type" (the message class name) and its fields. Client -> server frames are plain
msgpack dicts of the same shape. A client counts as connected (and its GUI clicks reach
callbacks) only after its first ViewerCameraMessage, as the browser sends.
"""

from __future__ import annotations

import time
from collections.abc import Callable
from typing import Any

import msgspec
import viser
import zstandard
from websockets.exceptions import ConnectionClosed
from websockets.sync.client import ClientConnection, connect


class ViserTestClient:
    def __init__(self, port: int, host: str = "127.0.0.1", secret: str | None = None) -> None:
        # The app's rehearsals answer only with their secret (rehearse/viser_gate.py).
        self.ws: ClientConnection = connect(
            f"ws://{host}:{port}", subprotocols=[f"viser-v{viser.__version__}"],  # type: ignore[list-item]
            open_timeout=10, max_size=None,
            additional_headers={"X-Countersign-Viewer": secret} if secret else None,
        )
        self.messages: list[dict[str, Any]] = []
        self.closed = False
        self._decompressor = zstandard.ZstdDecompressor()

    def close(self) -> None:
        self.ws.close()

    def __enter__(self) -> ViserTestClient:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()

    # ------------------------------------------------------------------------------ receive

    def _decode(self, frame: bytes) -> list[dict[str, Any]]:
        size = int.from_bytes(frame[0:8], "little")
        compressed = int.from_bytes(frame[8:16], "little")
        inner = self._decompressor.decompress(frame[16:16 + compressed], max_output_size=size)
        payload = msgspec.msgpack.decode(inner)
        return list(payload["messages"])

    def pump(self, seconds: float = 0.3) -> None:
        """Receive whatever arrives within `seconds`."""
        deadline = time.monotonic() + seconds
        while True:
            left = deadline - time.monotonic()
            if left <= 0:
                return
            try:
                frame = self.ws.recv(timeout=left)
            except TimeoutError:
                return
            except ConnectionClosed:
                # viser closes a connection whose message it cannot decode.
                self.closed = True
                return
            if isinstance(frame, bytes):
                self.messages.extend(self._decode(frame))

    def wait_for(self, predicate: Callable[[ViserTestClient], bool], timeout: float = 20.0) -> bool:
        deadline = time.monotonic() + timeout
        while time.monotonic() < deadline:
            if predicate(self):
                return True
            self.pump(0.2)
        return predicate(self)

    # ------------------------------------------------------------------------------ state

    def scene_nodes(self) -> dict[str, dict[str, Any]]:
        """Scene node name -> its latest create message, minus removed nodes."""
        nodes: dict[str, dict[str, Any]] = {}
        for message in self.messages:
            kind = message.get("type", "")
            name = message.get("name")
            if not isinstance(name, str):
                continue
            if kind == "RemoveSceneNodeMessage":
                nodes.pop(name, None)
            elif kind.endswith("Message") and "props" in message:
                nodes[name] = message
        return nodes

    def gui(self) -> dict[str, dict[str, Any]]:
        """GUI uuid -> create message, with later property updates applied to its props."""
        elements: dict[str, dict[str, Any]] = {}
        for message in self.messages:
            kind = message.get("type", "")
            if kind.startswith("Gui") and kind.endswith("Message") and "props" in message:
                elements[message["uuid"]] = {**message, "props": dict(message["props"])}
            elif kind == "GuiUpdateMessage" and message.get("uuid") in elements:
                elements[message["uuid"]]["props"].update(message.get("updates", {}))
        return elements

    def button(self, label: str) -> dict[str, Any]:
        for element in self.gui().values():
            if element["type"] == "GuiButtonMessage" and element["props"].get("label") == label:
                return element
        raise KeyError(label)

    def markdown(self) -> list[str]:
        return [e["props"].get("_markdown", "") for e in self.gui().values()
                if e["type"] == "GuiMarkdownMessage"]

    def theme(self) -> dict[str, Any] | None:
        themes = [m for m in self.messages if m.get("type") == "ThemeConfigurationMessage"]
        return themes[-1] if themes else None

    # ------------------------------------------------------------------------------ send

    def send(self, message: dict[str, Any]) -> None:
        self.send_raw(msgspec.msgpack.encode(message))

    def send_raw(self, data: bytes | str) -> None:
        try:
            self.ws.send(data)
        except ConnectionClosed:
            self.closed = True

    def hello(self) -> None:
        """The camera message a browser sends first; registers this client with the server."""
        self.send({
            "type": "ViewerCameraMessage",
            "wxyz": [1.0, 0.0, 0.0, 0.0], "position": [0.0, -50.0, 30.0], "fov": 1.0,
            "near": 0.01, "far": 1000.0, "image_height": 480, "image_width": 640,
            "look_at": [0.0, 0.0, 0.0], "up_direction": [0.0, 0.0, 1.0],
        })

    def click(self, label: str) -> None:
        uuid = self.button(label)["uuid"]
        self.send({"type": "GuiUpdateMessage", "uuid": uuid, "updates": {"value": True}})
