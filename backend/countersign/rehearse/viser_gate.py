"""Only the app's proxy may talk to a rehearsal's viser server.

viser listens on a loopback port that any local process can reach, and it has no notion of
credentials: whoever connects can click an outcome. Each rehearsal therefore has a secret that
the proxy sends in a request header (`VIEWER_HEADER`); a websocket without it is refused before
viser builds a client for it, so none of its messages is ever handled.

viser exposes no hook before its connection callbacks, so the gate goes first in its websocket
server's connect callbacks (private attributes of viser 1.1, reached through viser_adapter and
checked by tests/web tests that connect without the secret)."""

from __future__ import annotations

import hmac
import logging
from typing import Any

from . import viser_adapter

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
    expected = secret.encode()

    async def gate(client: Any) -> None:
        sent = viser_adapter.connection_request_header(server, client.client_id, VIEWER_HEADER)
        if sent is not None and hmac.compare_digest(sent.encode(), expected):
            return
        # Forget the client viser just registered, then end its handler: the message
        # consumer never starts, so nothing this connection sent reaches a callback.
        await viser_adapter.refuse_client(server, client.client_id, 1008,
                                          "not through the app", quiet=_FILTER)
        raise ViewerRefused("a websocket without the rehearsal's secret")

    viser_adapter.connect_first(server, gate)
    # viser listens from its constructor on: whoever connected before the gate is cut off
    # (it can only come back through the gate). The scene has no controls yet at this point.
    viser_adapter.disconnect_all(server)
