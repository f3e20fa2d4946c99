"""A server process killed outright (SIGKILL, the OOM killer) leaves no process behind: its
validation and password-hashing pools, their forkserver and the resource tracker all end."""

from __future__ import annotations

import http.client
import json
import os
import signal
import subprocess
import sys
from pathlib import Path

import pytest

from countersign.orders.examples import example_bytes
from countersign.store.accounts import create_token, create_user
from countersign.store.db import Database

from ..ports import free_port
from .test_server_processes import _wait

pytestmark = pytest.mark.skipif(not Path("/proc").is_dir(), reason="needs /proc (Linux)")


def _group(pgid: int) -> set[int]:
    """Live (not zombie) processes of process group `pgid`."""
    found = set()
    for entry in Path("/proc").iterdir():
        if not entry.name.isdigit():
            continue
        try:
            fields = (entry / "stat").read_text().rsplit(")", 1)[1].split()
        except OSError:
            continue
        if int(fields[2]) == pgid and fields[0] != "Z":
            found.add(int(entry.name))
    return found


def _request(port: int, method: str, path: str, body: bytes = b"",
             headers: dict[str, str] | None = None) -> int:
    connection = http.client.HTTPConnection("127.0.0.1", port, timeout=120)
    try:
        connection.request(method, path, body=body, headers=headers or {})
        response = connection.getresponse()
        response.read()
        return response.status
    except OSError:
        return 0
    finally:
        connection.close()


def test_a_killed_server_leaves_no_process_behind(tmp_path: Path) -> None:
    url = f"sqlite:///{tmp_path / 'db.sqlite'}"
    database = Database(url)
    database.migrate()
    with database.session() as db:
        user = create_user(db, username="killed", role="operator",
                           password="Vq8-orphan-check-Lp2-test", signer=database.log_signer)
        token = create_token(db, user=user, name="test", signer=database.log_signer)[1]
    database.engine.dispose()
    port = free_port()
    log = (tmp_path / "server.log").open("wb")
    server = subprocess.Popen(
        [sys.executable, "-m", "countersign.cli", "serve", "--port", str(port), "--data-dir",
         str(tmp_path / "data")], stdout=log, stderr=subprocess.STDOUT,
        env={**os.environ, "COUNTERSIGN_DATABASE_URL": url}, start_new_session=True)
    try:
        _wait(lambda: _request(port, "GET", "/api/health") == 200 or server.poll() is not None,
              "the server answers", seconds=180)
        assert server.poll() is None, (tmp_path / "server.log").read_text()[-2000:]
        # A sign-in starts the hashing process, a validation the validation processes.
        assert _request(port, "POST", "/api/auth/login", json.dumps(
            {"username": "killed", "password": "wrong"}).encode(),
            {"Content-Type": "application/json"}) == 401
        assert _request(port, "POST", "/api/validate", example_bytes("search-and-sample"),
                        {"Content-Type": "application/json",
                         "Authorization": f"Bearer {token}"}) == 200
        started = _group(server.pid) - {server.pid}
        assert len(started) >= 3, f"expected pool processes beside the server, saw {started}"
        os.kill(server.pid, signal.SIGKILL)
        server.wait(timeout=30)
        _wait(lambda: not _group(server.pid), f"every process of the server's group "
              f"({sorted(_group(server.pid))}) ended", seconds=60)
    finally:
        for pid in _group(server.pid):
            os.kill(pid, signal.SIGKILL)
        log.close()
