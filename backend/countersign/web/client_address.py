"""The client's address for the password throttle (store/login_throttle.py), for every route.

The address is the ASGI scope's client: the peer of the connection, or what uvicorn's proxy
headers middleware put there from `X-Forwarded-For`, which it trusts only from
FORWARDED_ALLOW_IPS (loopback by default). Nothing here reads a header itself, so a client
cannot choose the address its guesses are counted under."""

from __future__ import annotations

from starlette.types import ASGIApp, Receive, Scope, Send

from ..store.login_throttle import CLIENT_ADDRESS


class ClientAddress:
    """Plain ASGI: sets CLIENT_ADDRESS for the request; the route's worker thread inherits it
    (anyio copies the context into the thread)."""

    def __init__(self, app: ASGIApp) -> None:
        self.app = app

    async def __call__(self, scope: Scope, receive: Receive, send: Send) -> None:
        if scope["type"] != "http":
            await self.app(scope, receive, send)
            return
        client = scope.get("client")
        token = CLIENT_ADDRESS.set(client[0] if client else None)
        try:
            await self.app(scope, receive, send)
        finally:
            CLIENT_ADDRESS.reset(token)
