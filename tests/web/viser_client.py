"""A small viser websocket client for tests: speaks viser's wire format (frames of
zstd-compressed msgpack message batches from the server, plain msgpack messages from the
browser) over Starlette's test websocket."""

from __future__ import annotations

import time
from typing import Any

import msgspec
import viser
import zstandard
from starlette.testclient import WebSocketTestSession

PROTOCOL = f"viser-v{viser.__version__}"


def decode_frame(frame: bytes) -> list[dict[str, Any]]:
    """The messages of one server frame (binary buffers are left out)."""
    size = int.from_bytes(frame[:8], "little")
    compressed = int.from_bytes(frame[8:16], "little")
    inner = zstandard.ZstdDecompressor().decompress(frame[16:16 + compressed],
                                                    max_output_size=size)
    batch = msgspec.msgpack.decode(inner)
    messages: list[dict[str, Any]] = batch["messages"]
    return messages


def encode(message: dict[str, Any]) -> bytes:
    return msgspec.msgpack.encode(message)


class SceneReader:
    """Collects what the server sent: messages by type, GUI components by label."""

    def __init__(self, socket: WebSocketTestSession, hello: bool = True) -> None:
        self.socket = socket
        self.messages: list[dict[str, Any]] = []
        if hello:
            self.hello()

    def hello(self) -> None:
        """viser counts a client as connected (GUI events reach callbacks) from its first
        camera message, as the browser sends on load."""
        self.socket.send_bytes(encode({
            "type": "ViewerCameraMessage", "wxyz": [1.0, 0.0, 0.0, 0.0],
            "position": [0.0, -50.0, 30.0], "fov": 1.0, "near": 0.01, "far": 1000.0,
            "image_height": 600, "image_width": 800, "look_at": [0.0, 0.0, 0.0],
            "up_direction": [0.0, 0.0, 1.0]}))

    def read_until(self, done: Any, timeout: float = 20.0) -> None:
        deadline = time.monotonic() + timeout
        while not done(self):
            if time.monotonic() > deadline:
                raise AssertionError(f"viser did not send the expected messages; saw "
                                     f"{sorted({m.get('type') for m in self.messages})}")
            self.messages.extend(decode_frame(self.socket.receive_bytes()))

    def types(self) -> set[str]:
        return {str(m.get("type")) for m in self.messages}

    def button(self, label: str) -> str | None:
        for m in self.messages:
            if m.get("type") == "GuiButtonMessage" and m.get("props", {}).get("label") == label:
                return str(m["uuid"])
        return None

    def click(self, uuid: str) -> None:
        self.socket.send_bytes(encode({"type": "GuiUpdateMessage", "uuid": uuid,
                                       "updates": {"value": True}}))
