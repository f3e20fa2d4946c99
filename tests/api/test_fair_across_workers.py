"""Fair validation across server processes: with `serve --workers 2` one user's heavy
validations, whichever process they reach, do not hold back another user's small edit (the one
validation pool of the host, web/host_pool.py). Ordering is asserted, never time."""

from __future__ import annotations

import http.client
import json
import os
import signal
import socket
import subprocess
import sys
import threading
import time
import uuid
from pathlib import Path

import pytest

from countersign.orders.examples import example_bytes
from countersign.store.accounts import create_token, create_user
from countersign.store.db import Database
from countersign.web.gunicorn_server import reuse_port_available

from ..heavy_orders import heavy_orders

pytestmark = pytest.mark.skipif(not reuse_port_available(), reason="needs SO_REUSEPORT")

PATIENCE_S = 600.0  # a loaded machine is slow; this only bounds a hang
HEAVY = 4  # over two server processes: the kernel spreads the connections over both


def _free_port() -> int:
    with socket.socket() as sock:
        sock.bind(("127.0.0.1", 0))
        return int(sock.getsockname()[1])


def _post(port: int, token: str, body: dict[str, object]) -> int:
    connection = http.client.HTTPConnection("127.0.0.1", port, timeout=PATIENCE_S)
    try:
        connection.request("POST", "/api/validate", body=json.dumps(body), headers={
            "Authorization": f"Bearer {token}", "Content-Type": "application/json"})
        response = connection.getresponse()
        response.read()
        return response.status
    finally:
        connection.close()


def _listening(port: int) -> bool:
    try:
        connection = http.client.HTTPConnection("127.0.0.1", port, timeout=30)
        connection.request("GET", "/api/health")
        return connection.getresponse().status == 200
    except OSError:
        return False


def test_a_users_heavy_validations_on_both_workers_leave_a_turn_for_anothers_edit(
        tmp_path: Path) -> None:
    url = f"sqlite:///{tmp_path / 'fair.db'}"
    database = Database(url)
    database.migrate()
    tokens = {}
    with database.session() as db:
        for name in ("heavy", "light"):
            user = create_user(db, username=name, role="operator", password="a long password 1")
            tokens[name] = create_token(db, user=user, name="tests")[1]
    database.engine.dispose()
    port = _free_port()
    # One validation process for the host: the heavy user's validations run one at a time
    # there, and the light user's edit takes the next turn. With a pool in each server
    # process, each would run one of the heavy user's at once and the edit would wait behind
    # the one in its own process while the other finished too.
    log = (tmp_path / "server.log").open("wb")
    server = subprocess.Popen(
        [sys.executable, "-m", "countersign.cli", "serve", "--port", str(port), "--data-dir",
         str(tmp_path / "data"), "--workers", "2", "--validation-processes", "1"],
        stdout=log, stderr=subprocess.STDOUT,
        env={**os.environ, "COUNTERSIGN_DATABASE_URL": url})
    finished: list[str] = []  # who was answered, in order
    lock = threading.Lock()
    try:
        deadline = time.monotonic() + PATIENCE_S
        while not _listening(port):
            assert server.poll() is None, (tmp_path / "server.log").read_text()[-3000:]
            assert time.monotonic() < deadline, "the server did not start"
            time.sleep(0.2)

        def heavy(n: int) -> None:
            body = heavy_orders()
            body["description"] = f"heavy {n} {uuid.uuid4()}"
            try:
                answer = f"heavy {_post(port, tokens['heavy'], body)}"
            except OSError:  # the server stopped at the end of the test
                answer = "heavy dropped"
            with lock:
                finished.append(answer)

        threads = [threading.Thread(target=heavy, args=(n,), daemon=True)
                   for n in range(HEAVY)]
        for thread in threads:
            thread.start()
        small = json.loads(example_bytes("search-and-sample"))
        small["description"] = f"a small edit {uuid.uuid4()}"
        status = _post(port, tokens["light"], small)
        with lock:
            finished.append(f"light {status}")
            order = list(finished)
        assert order[-1] == "light 200", order
        # Each heavy validation takes seconds of solver budget: at most the one that held the
        # host's process when the edit came in ended before it.
        assert order.count("heavy 200") <= 1 and len(order) <= 2, order
    finally:
        server.send_signal(signal.SIGTERM)
        try:
            server.wait(timeout=60)
        except subprocess.TimeoutExpired:
            server.kill()
            server.wait()
        log.close()
