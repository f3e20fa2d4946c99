"""Every use of viser's private API, in one place (viser 1.1; pinned <1.2 in pyproject).

viser offers no public hook for what the rehearsal needs: refusing a websocket before its
client exists (the viewer gate), dropping share-link requests, and the wire format's message
base class (the app's proxy). When viser changes these, tests/codebase/test_private_apis.py fails
first, naming the attribute."""

from __future__ import annotations

from collections.abc import Awaitable, Callable
from pathlib import Path
from typing import Any


def _websock(server: Any) -> Any:
    return server._websock_server


def share_message_types() -> tuple[type, ...]:
    """The messages by which a client asks viser to open (or close) a public share tunnel."""
    from viser import _messages

    return (_messages.ShareUrlRequest, _messages.ShareUrlDisconnect)


def message_base() -> type:
    """The base class of every message of viser's wire format (msgpack, by class name)."""
    from viser import _messages

    cls: type = _messages.Message
    return cls


def replace_handler(server: Any, message_cls: type, handler: Callable[[Any, Any], None]) -> None:
    """Make `handler` the only handler of `message_cls` on `server`'s websocket server."""
    websock = _websock(server)
    if message_cls in websock._incoming_handlers:
        websock.unregister_handler(message_cls)
    websock.register_handler(message_cls, handler)


def connection_request_header(server: Any, client_id: int, name: str) -> str | None:
    """Header `name` of the HTTP request that opened client `client_id`'s websocket; None when
    the connection is unknown or has no request."""
    connection = _websock(server)._live_connections.get(client_id)
    if connection is None or connection.request is None:
        return None
    value: str = connection.request.headers.get(name, "")
    return value


async def refuse_client(server: Any, client_id: int, code: int, reason: str,
                        quiet: Any = None) -> None:
    """Forget the client viser just registered and close its websocket, so that its message
    consumer never starts; `quiet` (a logging.Filter) keeps the refusal out of viser's log."""
    websock = _websock(server)
    connection = websock._live_connections.pop(client_id, None)
    websock._client_state_from_id.pop(client_id, None)
    if connection is not None:
        if quiet is not None:
            connection.logger.logger.addFilter(quiet)
        await connection.close(code, reason)


def connect_first(server: Any, callback: Callable[[Any], Awaitable[None]]) -> None:
    """Run `callback` before every other connection callback of `server` (viser has no
    public hook that runs before its own)."""
    _websock(server)._client_connect_cb.insert(0, callback)


def disconnect_all(server: Any) -> None:
    _websock(server).disconnect_all_clients()


def client_index_path() -> Path:
    """viser's built client: one self-contained HTML file inside the installed package."""
    import viser

    return Path(viser.__file__).resolve().parent / "client" / "build" / "index.html"
