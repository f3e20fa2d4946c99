"""Only the app's proxy may talk to a rehearsal's viser server.

viser listens on a loopback port that any local process can reach, and it has no notion of
credentials: whoever connects can click an outcome. Each rehearsal therefore has a secret that
the proxy sends in a request header (`VIEWER_HEADER`); a websocket without it is refused before
viser builds a client for it, so none of its messages is ever handled.

viser exposes no hook before its connection callbacks, so the gate goes first in its websocket
server's connect callbacks (private attributes of viser 1.1, checked by tests/api tests that
connect without the secret)."""

from __future__ import annotations

import hmac
import logging
from typing import Any

VIEWER_HEADER = "X-Countersign-Viewer"


class ViewerRefused(Exception):
    """Raised inside viser's connection handler: the connection ends before any message."""


class _QuietRefusals(logging.Filter):
    def filter(self, record: logging.LogRecord) -> bool:
        exc = record.exc_info[1] if record.exc_info else None
        return not isinstance(exc, ViewerRefused)


_FILTER = _QuietRefusals()


def install(server: Any, secret: str) -> None:
    """Refuse every websocket of `server` (a viser.ViserServer) without `secret`."""
    websock = server._websock_server
    expected = secret.encode()

    async def gate(client: Any) -> None:
        connection = websock._live_connections.get(client.client_id)
        sent = ""
        if connection is not None and connection.request is not None:
            sent = connection.request.headers.get(VIEWER_HEADER, "")
        if connection is not None and hmac.compare_digest(sent.encode(), expected):
            return
        # Forget the client viser just registered, then end its handler: the message
        # consumer never starts, so nothing this connection sent reaches a callback.
        websock._live_connections.pop(client.client_id, None)
        websock._client_state_from_id.pop(client.client_id, None)
        if connection is not None:
            connection.logger.logger.addFilter(_FILTER)
            await connection.close(1008, "not through the app")
        raise ViewerRefused("a websocket without the rehearsal's secret")

    websock._client_connect_cb.insert(0, gate)
    # viser listens from its constructor on: whoever connected before the gate is cut off
    # (it can only come back through the gate). The scene has no controls yet at this point.
    websock.disconnect_all_clients()
