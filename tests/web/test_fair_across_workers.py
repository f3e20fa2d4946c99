"""Fair validation across server processes: with `serve --workers 2` one user's heavy
validations, whichever process they reach, do not hold back another user's small edit (the one
validation pool of the host, web/host_pool.py). Ordering is asserted, never time."""

from __future__ import annotations

import contextlib
import http.client
import json
import os
import signal
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
from ..ports import free_port
from ..processes import children

pytestmark = pytest.mark.skipif(not reuse_port_available(), reason="needs SO_REUSEPORT")

PATIENCE_S = 600.0  # a loaded machine is slow; this only bounds a hang
HEAVY = 4  # over two server processes: the kernel spreads the connections over both


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


def _users(tmp_path: Path) -> tuple[str, dict[str, str]]:
    url = f"sqlite:///{tmp_path / 'fair.db'}"
    database = Database(url)
    database.migrate()
    tokens = {}
    with database.session() as db:
        for name in ("heavy", "light"):
            user = create_user(db, username=name, role="operator", password="a long password 1",
                               signer=database.log_signer)
            tokens[name] = create_token(db, user=user, name="tests", signer=database.log_signer)[1]
    database.engine.dispose()
    return url, tokens


def _serve(tmp_path: Path, url: str, port: int, processes: str) -> subprocess.Popen[bytes]:
    with (tmp_path / "server.log").open("wb") as log:
        return subprocess.Popen(
            [sys.executable, "-m", "countersign.cli", "serve", "--port", str(port),
             "--data-dir", str(tmp_path / "data"), "--workers", "2",
             "--validation-processes", processes],
            stdout=log, stderr=subprocess.STDOUT, start_new_session=True,
            env={**os.environ, "COUNTERSIGN_DATABASE_URL": url})


def _wait_listening(server: subprocess.Popen[bytes], tmp_path: Path, port: int) -> None:
    deadline = time.monotonic() + PATIENCE_S
    while not _listening(port):
        assert server.poll() is None, (tmp_path / "server.log").read_text()[-3000:]
        assert time.monotonic() < deadline, "the server did not start"
        time.sleep(0.2)


def _stop(server: subprocess.Popen[bytes]) -> None:
    server.send_signal(signal.SIGTERM)
    try:
        server.wait(timeout=60)
    except subprocess.TimeoutExpired:
        server.kill()
        server.wait()


def _kill(server: subprocess.Popen[bytes]) -> None:
    """Ends the server and every process it started at once (its own session): a graceful
    stop would wait for the heavy validations still running, 30 s that test nothing."""
    with contextlib.suppress(ProcessLookupError):
        os.killpg(server.pid, signal.SIGKILL)
    server.wait()


def _host_process(master: int) -> int:
    """The validation host: the master's child started by multiprocessing's spawn."""
    for pid in children(master):
        try:
            if b"spawn_main" in Path(f"/proc/{pid}/cmdline").read_bytes():
                return pid
        except OSError:
            continue
    raise AssertionError("no validation host process")


def test_a_users_heavy_validations_on_both_workers_leave_a_turn_for_anothers_edit(
        tmp_path: Path) -> None:
    url, tokens = _users(tmp_path)
    port = free_port()
    # One validation process for the host: the heavy user's validations run one at a time
    # there, and the light user's edit takes the next turn. With a pool in each server
    # process, each would run one of the heavy user's at once and the edit would wait behind
    # the one in its own process while the other finished too.
    server = _serve(tmp_path, url, port, "1")
    finished: list[str] = []  # who was answered, in order
    lock = threading.Lock()
    try:
        _wait_listening(server, tmp_path, port)

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
        _kill(server)


def test_validation_goes_on_when_the_host_process_is_killed(tmp_path: Path) -> None:
    """Each server process falls back to a pool of its own: answers, not 500s."""
    url, tokens = _users(tmp_path)
    port = free_port()
    server = _serve(tmp_path, url, port, "2")
    try:
        _wait_listening(server, tmp_path, port)
        small = json.loads(example_bytes("search-and-sample"))
        assert _post(port, tokens["light"], small) == 200
        os.kill(_host_process(server.pid), signal.SIGKILL)
        for n in range(6):  # new connections: both server processes answer some
            # A goal's title, which the checks read: each edit is validated in a pool. An edit
            # of descriptions alone is answered with the report the process made before
            # (verify/reuse.py), and when every one reached the process that had answered the
            # first, no pool was asked and no fallback logged.
            small["goals"][0]["title"] = f"after the host ended {n} {uuid.uuid4()}"
            assert _post(port, tokens["light"], small) == 200
        assert server.poll() is None
    finally:
        _stop(server)
    assert "validating in this server process's own pool" in (
        tmp_path / "server.log").read_text()
