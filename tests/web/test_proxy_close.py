"""The rehearsal proxy's close frame goes out even when the relay is cancelled while sending
it (a CI run hung in tests/web/test_rehearsal_sockets.py: at sign-out the watcher began the
1008 close, the other side's failed send cancelled the relay, and the close never arrived)."""

from __future__ import annotations

import threading
from typing import Any

import anyio

from countersign.web.viser_proxy import POLICY_VIOLATION, ProxyStats, _close


class SlowBrowser:
    """A browser socket whose close takes a moment to send, as a busy one does."""

    def __init__(self) -> None:
        self.closed: tuple[int, str] | None = None

    async def close(self, code: int, reason: str) -> None:
        await anyio.sleep(0.05)
        self.closed = (code, reason)


def test_a_close_cancelled_halfway_still_reaches_the_browser() -> None:
    browser = SlowBrowser()

    async def main() -> None:
        async with anyio.create_task_group() as group:
            browser_socket: Any = browser
            group.start_soon(_close, browser_socket, ProxyStats(), POLICY_VIOLATION, "signed out")
            await anyio.sleep(0.01)
            group.cancel_scope.cancel()  # the other side failed: the relay ends

    # Its own thread: other tests of the suite leave an event loop running in this one.
    worker = threading.Thread(target=anyio.run, args=(main,))
    worker.start()
    worker.join(timeout=30)
    assert not worker.is_alive()
    assert browser.closed == (POLICY_VIOLATION, "signed out")
