"""The live viewer's ticket is a bearer secret in its URL
(`/rehearsal/{id}/t/{ticket}/`, and its websocket on that path); the server's logs must not
print it. A real `countersign serve` (one uvicorn process, and gunicorn with two workers) is
sent the viewer's page, an asset under it and a websocket handshake, and its log output is read:
the requests are logged with `[ticket]` in the ticket's place, and the ticket appears nowhere."""

from __future__ import annotations

import base64
import http.client
import os
import secrets
import subprocess
import sys
import time
from pathlib import Path

import pytest

from countersign.web.gunicorn_server import reuse_port_available

from ..ports import free_port


def _get(port: int, path: str, headers: dict[str, str] | None = None) -> int:
    connection = http.client.HTTPConnection("127.0.0.1", port, timeout=60)
    try:
        connection.request("GET", path, headers=headers or {})
        return connection.getresponse().status
    finally:
        connection.close()


def _healthy(port: int, process: subprocess.Popen[bytes], log: Path) -> None:
    deadline = time.monotonic() + 180  # a loaded machine starts a server slowly
    while time.monotonic() < deadline:
        assert process.poll() is None, log.read_text(errors="replace")[-4000:]
        try:
            if _get(port, "/api/health") == 200:
                return
        except OSError:
            pass
        time.sleep(0.3)
    pytest.fail("countersign serve did not answer /api/health")


@pytest.mark.parametrize("workers", [1, 2])
def test_no_viewer_ticket_in_the_server_log(tmp_path: Path, workers: int) -> None:
    if workers > 1 and not reuse_port_available():
        pytest.skip("several server processes need SO_REUSEPORT")
    port, log = free_port(), tmp_path / "server.log"
    ticket = secrets.token_urlsafe(24)
    env = {**os.environ, "COUNTERSIGN_DATABASE_URL": ""}
    with log.open("wb") as out:
        process = subprocess.Popen(
            [sys.executable, "-m", "countersign.cli", "serve", "--port", str(port),
             "--data-dir", str(tmp_path / "data"), "--workers", str(workers)],
            stdout=out, stderr=subprocess.STDOUT, env=env)
    try:
        _healthy(port, process, log)
        assert _get(port, f"/rehearsal/r1/t/{ticket}/") in (403, 404)
        assert _get(port, f"/rehearsal/r1/t/{ticket}/assets/index.js?v=1") in (403, 404)
        handshake = {"Connection": "Upgrade", "Upgrade": "websocket",
                     "Sec-WebSocket-Version": "13",
                     "Sec-WebSocket-Key": base64.b64encode(os.urandom(16)).decode()}
        assert _get(port, f"/rehearsal/r1/t/{ticket}", handshake) in (403, 404)
        process.terminate()
        process.wait(timeout=60)
    finally:
        if process.poll() is None:
            process.kill()
            process.wait()
    text = log.read_text(errors="replace")
    assert ticket not in text, text[-4000:]
    # The requests were logged (the filter hides the ticket, not the line).
    assert '"WebSocket /rehearsal/r1/t/[ticket]"' in text, text[-4000:]
    if workers == 1:  # gunicorn keeps no access log unless told to
        assert "GET /rehearsal/r1/t/[ticket]/ HTTP/1.1" in text, text[-4000:]
        assert "GET /rehearsal/r1/t/[ticket]/assets/index.js?v=1 HTTP/1.1" in text, text[-4000:]
