"""viser's browser client, served by the app, and its websocket, proxied to the rehearsal.

The browser never reaches a rehearsal's viser port: the app serves viser's bundled client (one
self-contained `index.html` in the installed package) at `/rehearsal/{id}/`, and the client
opens its websocket on that same URL (`ws://host/rehearsal/{id}`, viser strips the slash). The
route checks the session and the Origin before the upgrade; this module then relays frames in
both directions between the browser and `ws://127.0.0.1:{port}`, and

- drops viser's share-link messages (`ShareUrlRequest`/`ShareUrlDisconnect` from the browser,
  `ShareUrlUpdated` from the server): a rehearsal is never published through viser's tunnel;
- forwards only frames that viser can decode (binary msgpack with a known message type) and at
  most `MAX_FRAME` bytes; a browser that keeps sending malformed frames, oversized frames or a
  flood of frames is disconnected (1008/1009). viser never sees a malformed frame.
"""

from __future__ import annotations

import asyncio
import contextlib
import functools
import logging
import re
import time
from collections.abc import Awaitable, Callable
from dataclasses import dataclass, field
from typing import Any

import anyio
import anyio.abc
import msgspec
import zstandard
from starlette.websockets import WebSocket, WebSocketDisconnect
from websockets.asyncio.client import ClientConnection, connect
from websockets.exceptions import ConnectionClosed, InvalidHandshake
from websockets.typing import Subprotocol

from ..rehearse.viser_gate import VIEWER_HEADER

log = logging.getLogger("countersign.rehearsal")

MAX_FRAME = 1024 * 1024  # browser -> rehearsal: GUI clicks and camera moves are tiny
MAX_MALFORMED = 8  # malformed frames tolerated (and dropped) before the browser is cut off
MAX_FRAMES_PER_SECOND = 400  # camera moves arrive at display rate; far above that is abuse
SHARE_FROM_BROWSER = frozenset({"ShareUrlRequest", "ShareUrlDisconnect"})
SHARE_FROM_SERVER = "ShareUrlUpdated"
# What viser's client sends and viser's server handles (its register_handler calls in 1.1),
# less file uploads and render answers, which a rehearsal never asks for. Anything else from a
# browser is malformed.
FROM_BROWSER = frozenset({
    "ViewerCameraMessage", "GuiUpdateMessage", "GuiButtonHoldMessage", "GuiFormDirtyMessage",
    "GuiFormSubmitMessage", "ScenePointerMessage", "SceneNodeClickMessage",
    "SceneNodeDragMessage", "TransformControlsUpdateMessage",
    "TransformControlsDragStartMessage", "TransformControlsDragEndMessage",
    "CommandTriggerMessage", "LocalStorageGetItemResponseMessage",
})
POLICY_VIOLATION, TOO_BIG, GOING_AWAY = 1008, 1009, 1001
CLOSE_TIMEOUT_S = 2.0  # how long a close frame may take to go out

# viser's client loads one inline loader script that decompresses the bundle, injects it as an
# inline module script, compiles zstd WebAssembly and starts a blob: worker; its bundle also
# evaluates generated code (Chromium reports an EvalError without 'unsafe-eval'). Nothing is
# fetched from other origins and the websocket goes back to this origin only.
# `sandbox allow-scripts` gives the viewer an opaque origin: whatever runs in it (viser's code,
# or markup smuggled into the scene) cannot read the app's cookies, storage or IndexedDB keys,
# and its requests to the app carry no session. Its websocket is authorised by a ticket in its
# URL instead (viewer_tickets.py).
CLIENT_CSP = ("sandbox allow-scripts; default-src 'none'; "
              "script-src 'self' 'unsafe-inline' 'unsafe-eval' 'wasm-unsafe-eval'; "
              "worker-src 'self' blob:; style-src 'self' 'unsafe-inline'; "
              "img-src 'self' data: blob:; font-src 'self' data:; "
              "connect-src 'self' {sockets} data: blob:; media-src 'self' data: blob:; "
              "frame-ancestors 'self'; base-uri 'none'; form-action 'none'")
_HOST = re.compile(r"[A-Za-z0-9.-]{1,253}(:[0-9]{1,5})?|\[[0-9A-Fa-f:.]{2,45}\](:[0-9]{1,5})?")


def client_csp(host: str | None) -> str:
    """CLIENT_CSP for a request to `host`. In an opaque origin 'self' matches nothing for
    viser's websocket (it is opened from a blob: worker), so the app's own host is named."""
    if host and _HOST.fullmatch(host):
        return CLIENT_CSP.format(sockets=f"ws://{host} wss://{host}")
    return CLIENT_CSP.format(sockets="")
# The standalone replay is viser's client plus the recording inlined; it needs no network.
REPLAY_CSP = ("default-src 'none'; script-src 'unsafe-inline' 'unsafe-eval' 'wasm-unsafe-eval'; "
              "worker-src blob:; style-src 'unsafe-inline'; img-src data: blob:; "
              "font-src data:; connect-src data: blob:; media-src data: blob:; "
              "frame-ancestors 'self'; base-uri 'none'; form-action 'none'; sandbox allow-scripts")


# viser's client, as built, cannot start in an opaque origin; this shim, run before viser's
# loader, adapts the two places where it fails (checked by tests/e2e/test_rehearsal_page.py):
# - history.replaceState with a URL throws SecurityError: it tidies viser's own URL, which
#   the frame does not need, so the call becomes a no-op there;
# - its websocket worker is a module worker from a blob: URL, which an opaque origin cannot
#   load; its source needs no module features except revoking its own URL, so it starts as a
#   classic worker without that first statement.
_OPAQUE_ORIGIN_SHIM = b"""<script>(function(){
var h=window.history,r=h.replaceState;
h.replaceState=function(){try{return r.apply(h,arguments)}
catch(e){if(!(e instanceof DOMException))throw e}};
var B=window.Blob,first="URL.revokeObjectURL(import.meta.url);";
var P=function(parts,options){if(parts&&parts[0]===first)parts=parts.slice(1);
return new B(parts,options)};
P.prototype=B.prototype;window.Blob=P;
var W=window.Worker;
var V=function(url,options){
if(options&&options.type==="module"&&String(url).indexOf("blob:")===0){
options=Object.assign({},options);delete options.type}
return new W(url,options)};
V.prototype=W.prototype;window.Worker=V;
})();</script>"""


@functools.cache
def client_index() -> bytes:
    """viser's built client (a single self-contained HTML file in the installed package),
    with the opaque-origin shim first in its head."""
    from ..rehearse.viser_adapter import client_index_path

    html = client_index_path().read_bytes()
    head = html.index(b"<head>") + len(b"<head>")
    return html[:head] + _OPAQUE_ORIGIN_SHIM + html[head:]


@functools.cache
def _viser_message_class() -> Any:
    from ..rehearse.viser_adapter import message_base

    return message_base()


@dataclass
class ProxyStats:
    """What one proxied connection saw; kept by the app for tests and the event log."""

    to_server: int = 0
    to_browser: int = 0
    dropped_share: int = 0
    malformed: int = 0
    close_code: int | None = None
    started: float = field(default_factory=time.monotonic)


def check_from_browser(frame: bytes) -> str:
    """The viser message type of a browser frame; ValueError when viser could not decode it."""
    try:
        data = msgspec.msgpack.decode(frame)
    except msgspec.DecodeError:
        raise ValueError("not msgpack") from None
    if not isinstance(data, dict) or not isinstance(data.get("type"), str):
        raise ValueError("not a viser message")
    kind: str = data["type"]
    if kind in SHARE_FROM_BROWSER:
        return kind
    if kind not in FROM_BROWSER:
        raise ValueError(f"{kind[:60]!r} is not a message a viser client sends")
    if kind == "GuiUpdateMessage":
        # viser's server sets every named attribute of the GUI handle's state; its client only
        # ever sends the value, so anything else would be tampering with the server's state.
        updates = data.get("updates")
        if not isinstance(updates, dict) or set(updates) != {"value"}:
            raise ValueError("a GUI update from a browser changes the value only")
    try:
        _viser_message_class().deserialize(frame)
    except Exception as exc:  # viser's decoder raises whatever the bad input provokes
        raise ValueError(f"viser cannot decode a {kind[:60]!r} message") from exc
    return kind


def strip_share_from_server(frame: bytes) -> tuple[bytes, int]:
    """The server frame without `ShareUrlUpdated` messages, and how many were removed.

    viser's frame: [8 bytes msgpack size][8 bytes compressed size][zstd msgpack]
    [padding to 8][binary buffers]. Frames without a share message pass through unchanged."""
    if len(frame) < 16:
        return frame, 0
    size = int.from_bytes(frame[:8], "little")
    compressed_size = int.from_bytes(frame[8:16], "little")
    end = 16 + compressed_size
    if end > len(frame) or size > 64 * 1024 * 1024:
        return frame, 0
    try:
        inner = zstandard.ZstdDecompressor().decompress(frame[16:end], max_output_size=size)
    except zstandard.ZstdError:
        return frame, 0
    if SHARE_FROM_SERVER.encode() not in inner:
        return frame, 0
    batch = msgspec.msgpack.decode(inner)
    messages = batch.get("messages", []) if isinstance(batch, dict) else []
    kept = [m for m in messages if not (isinstance(m, dict) and m.get("type") == SHARE_FROM_SERVER)]
    removed = len(messages) - len(kept)
    if not removed:
        return frame, 0
    batch["messages"] = kept
    new_inner = msgspec.msgpack.encode(batch)
    compressed = zstandard.ZstdCompressor(level=1).compress(new_inner)
    buffers = frame[_aligned(end):]
    head = len(new_inner).to_bytes(8, "little") + len(compressed).to_bytes(8, "little")
    body = head + compressed
    return body + b"\0" * (_aligned(len(body)) - len(body)) + buffers, removed


def _aligned(offset: int) -> int:
    return (offset + 7) // 8 * 8


async def open_upstream(port: int, subprotocols: list[str],
                        secret: str | None = None) -> ClientConnection:
    """Connect to the rehearsal's viser server (loopback only), with the rehearsal's secret
    (rehearse/viser_gate.py); raises OSError when it is gone."""
    headers = {VIEWER_HEADER: secret} if secret else {}
    try:
        return await connect(
            f"ws://127.0.0.1:{port}", subprotocols=[Subprotocol(p) for p in subprotocols[:4]],
            additional_headers=headers,
            compression=None, open_timeout=5, max_size=None, ping_interval=None,
            close_timeout=2, proxy=None)
    except (InvalidHandshake, TimeoutError) as exc:
        raise OSError(f"the rehearsal's viser server did not accept: {exc}") from exc


async def relay(browser: WebSocket, upstream: ClientConnection, stats: ProxyStats,
                watch: Callable[[], Awaitable[str]] | None = None) -> None:
    """Relay frames until either side closes; the other side is then closed too. `watch`,
    when given, returns once the connection may no longer relay (its session ended), with
    the reason: the browser is then cut off."""
    try:
        sides = (functools.partial(_to_server, browser, upstream, stats),
                 functools.partial(_to_browser, browser, upstream, stats),
                 functools.partial(_watcher, browser, stats, watch))
        async with anyio.create_task_group() as group:
            for side in sides:
                group.start_soon(_until_ended, side, group)
    finally:
        # The closing handshake with viser runs on its own: the browser's side is done now.
        closing = asyncio.get_running_loop().create_task(_close_upstream(upstream))
        _CLOSING.add(closing)
        closing.add_done_callback(_CLOSING.discard)
        with anyio.CancelScope(shield=True):
            await _close(browser, stats, GOING_AWAY, "the rehearsal connection ended")


async def _to_server(browser: WebSocket, upstream: ClientConnection, stats: ProxyStats) -> None:
    """The browser's frames to viser: rate-limited, size-limited, checked, shares dropped."""
    window, count = time.monotonic(), 0
    while True:
        message = await browser.receive()
        if message["type"] == "websocket.disconnect":
            stats.close_code = stats.close_code or int(message.get("code", 1000))
            return
        frame = message.get("bytes")
        now = time.monotonic()
        if now - window >= 1.0:
            window, count = now, 0
        count += 1
        if count > MAX_FRAMES_PER_SECOND:
            await _close(browser, stats, POLICY_VIOLATION, "too many frames")
            return
        if frame is None:  # viser speaks binary only
            if await _malformed(browser, stats, "text frame"):
                return
            continue
        if len(frame) > MAX_FRAME:
            await _close(browser, stats, TOO_BIG, f"frames are at most {MAX_FRAME} bytes")
            return
        try:
            kind = check_from_browser(frame)
        except ValueError as exc:
            if await _malformed(browser, stats, str(exc)):
                return
            continue
        if kind in SHARE_FROM_BROWSER:
            stats.dropped_share += 1
            continue
        await upstream.send(frame)
        stats.to_server += 1


async def _to_browser(browser: WebSocket, upstream: ClientConnection, stats: ProxyStats) -> None:
    """viser's frames to the browser, with its share offers removed."""
    async for data in upstream:
        if isinstance(data, str):
            continue
        frame, removed = strip_share_from_server(data)
        stats.dropped_share += removed
        await browser.send_bytes(frame)
        stats.to_browser += 1
    await _close(browser, stats, GOING_AWAY, "the rehearsal ended")


async def _watcher(browser: WebSocket, stats: ProxyStats,
                   watch: Callable[[], Awaitable[str]] | None) -> None:
    if watch is None:
        await anyio.sleep_forever()
        return
    reason = await watch()
    await _close(browser, stats, POLICY_VIOLATION, reason)


async def _until_ended(side: Callable[[], Awaitable[None]], group: anyio.abc.TaskGroup) -> None:
    """Run one side of the relay; when it ends, for whatever reason, end the others."""
    try:
        await side()
    except (ConnectionClosed, WebSocketDisconnect, RuntimeError, OSError):
        pass  # either side went away
    except Exception as exc:
        log.warning("rehearsal proxy: %r", exc)
    finally:
        group.cancel_scope.cancel()  # one side ended: end the other


_CLOSING: set[asyncio.Task[None]] = set()


async def _close_upstream(upstream: ClientConnection) -> None:
    with contextlib.suppress(Exception):
        await upstream.close()


async def _malformed(browser: WebSocket, stats: ProxyStats, why: str) -> bool:
    """Count a dropped malformed frame; True when the browser was disconnected for it."""
    stats.malformed += 1
    if stats.malformed > MAX_MALFORMED:
        await _close(browser, stats, POLICY_VIOLATION, f"too many malformed frames ({why})")
        return True
    return False


async def _close(browser: WebSocket, stats: ProxyStats, code: int, reason: str) -> None:
    if stats.close_code is None:
        stats.close_code = code
    # Shielded: the other side, failing to send once the close began, cancels the relay's
    # task group; a close cancelled halfway is marked sent but never reaches the browser,
    # which then never learns why (a test client waits for it forever).
    with anyio.move_on_after(CLOSE_TIMEOUT_S, shield=True), contextlib.suppress(Exception):
        await browser.close(code, reason)
