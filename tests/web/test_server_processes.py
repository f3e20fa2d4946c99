"""`countersign serve --workers N` (gunicorn, uvicorn workers, reuse_port) as a real process
tree: a listening socket per server process (connections spread over them), a dead process
replaced and its helper processes ended, a taken port refused, and every process gone after
SIGTERM."""

from __future__ import annotations

import http.client
import os
import signal
import socket
import subprocess
import sys
import time
from collections import Counter
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path

import pytest

from countersign.web.gunicorn_server import reuse_port_available

from ..ports import free_port
from ..processes import children

pytestmark = pytest.mark.skipif(
    not (reuse_port_available() and Path("/proc/net/tcp").exists()),
    reason="needs SO_REUSEPORT and /proc (Linux)")


def _tcp_rows(port: int, state: str) -> list[str]:
    """Socket inodes of this machine's IPv4 TCP sockets on local `port` in `state` (hex)."""
    rows = []
    for line in Path("/proc/net/tcp").read_text().splitlines()[1:]:
        fields = line.split()
        if int(fields[1].rsplit(":", 1)[1], 16) == port and fields[3] == state:
            rows.append(fields[9])
    return rows


def _owners(inodes: list[str]) -> Counter[int]:
    """How many of these sockets each process holds."""
    wanted, owners = set(inodes), Counter[int]()
    for entry in Path("/proc").iterdir():
        if not entry.name.isdigit():
            continue
        try:
            for fd in (entry / "fd").iterdir():
                target = os.readlink(fd)
                if target.startswith("socket:[") and target[8:-1] in wanted:
                    owners[int(entry.name)] += 1
        except OSError:
            continue
    return owners


def _descendants(pid: int) -> set[int]:
    found, todo = set(), [pid]
    while todo:
        for child in children(todo.pop()):
            if child not in found:
                found.add(child)
                todo.append(child)
    return found


def _gone(pid: int) -> bool:
    path = Path(f"/proc/{pid}/stat")
    try:
        return "Z" in path.read_text().rsplit(")", 1)[1].split()[0]
    except OSError:
        return True


def _wait(condition: object, what: str, seconds: float = 60) -> None:
    deadline = time.monotonic() + seconds
    while not condition():  # type: ignore[operator]
        assert time.monotonic() < deadline, f"timed out waiting until {what}"
        time.sleep(0.2)


@contextmanager
def _serve(tmp_path: Path, port: int, workers: int) -> Iterator[subprocess.Popen[bytes]]:
    env = {**os.environ, "COUNTERSIGN_DATABASE_URL": ""}
    log = (tmp_path / "server.log").open("wb")
    process = subprocess.Popen(
        [sys.executable, "-m", "countersign.cli", "serve", "--port", str(port), "--data-dir",
         str(tmp_path / "data"), "--workers", str(workers)],
        stdout=log, stderr=subprocess.STDOUT, env=env)
    try:
        yield process
    finally:
        if process.poll() is None:
            process.terminate()
            try:
                process.wait(timeout=40)
            except subprocess.TimeoutExpired:
                process.kill()
                process.wait()
        log.close()


def _health(port: int) -> int:
    """GET /api/health on a new connection. A connection the kernel queued on a process that
    was dying is reset: retried, as a browser or load balancer would."""
    for attempt in range(5):
        connection = http.client.HTTPConnection("127.0.0.1", port, timeout=60)
        try:
            connection.request("GET", "/api/health")
            return connection.getresponse().status
        except ConnectionResetError:
            if attempt == 4:
                raise
            time.sleep(0.2)
        finally:
            connection.close()
    raise AssertionError("unreachable")


def test_workers_listen_each_share_connections_and_are_replaced(tmp_path: Path) -> None:
    port = free_port()
    with _serve(tmp_path, port, 2) as server:
        _wait(lambda: len(_tcp_rows(port, "0A")) == 2 or server.poll() is not None,
              "two server processes listen")
        assert server.poll() is None, (tmp_path / "server.log").read_text()[-2000:]
        listeners = _owners(_tcp_rows(port, "0A"))
        assert len(listeners) == 2 and server.pid not in listeners, listeners

        # 40 kept-alive connections, as 40 browsers: the kernel spreads them over both.
        connections = []
        for _ in range(40):
            connection = http.client.HTTPConnection("127.0.0.1", port, timeout=60)
            connection.request("GET", "/api/health")
            response = connection.getresponse()
            response.read()
            assert response.status == 200
            connections.append(connection)
        held = _owners([inode for inode in _tcp_rows(port, "01")])
        serving = {pid: n for pid, n in held.items() if pid in listeners}
        assert len(serving) == 2 and min(serving.values()) >= 5, serving
        for connection in connections:
            connection.close()

        # A server process that dies is replaced; the port keeps answering meanwhile (once the
        # dead process's socket is closed: connections the kernel had queued on it are reset).
        victim = next(iter(listeners))
        _wait(lambda: _descendants(victim), "the victim has started its helper processes")
        orphans = _descendants(victim)  # its forkserver, hashers and validation processes
        os.kill(victim, signal.SIGKILL)
        _wait(lambda: victim not in _owners(_tcp_rows(port, "0A")), "the killed one is closed")
        assert _health(port) == 200
        _wait(lambda: len(_owners(_tcp_rows(port, "0A"))) == 2
              and victim not in _owners(_tcp_rows(port, "0A")), "a new process listens")
        assert all(_health(port) == 200 for _ in range(10))
        _wait(lambda: all(_gone(pid) for pid in orphans), "the killed one's helpers ended")

        workers = _descendants(server.pid)
        server.send_signal(signal.SIGTERM)
        assert server.wait(timeout=40) == 0
    assert not _tcp_rows(port, "0A")
    for pid in workers:  # every process of the tree, helpers of the workers included
        _wait(lambda pid=pid: _gone(pid), f"process {pid} ended", seconds=10)


def test_a_taken_port_is_refused_with_its_reason(tmp_path: Path) -> None:
    with socket.socket() as taken:
        taken.bind(("127.0.0.1", free_port()))
        taken.listen()
        port = taken.getsockname()[1]
        with _serve(tmp_path, port, 2) as server:
            assert server.wait(timeout=60) == 1
    log = (tmp_path / "server.log").read_text()
    assert f"cannot listen on 127.0.0.1:{port}" in log and "Traceback" not in log


def test_processes_that_cannot_start_stop_the_server() -> None:
    """An app that fails before it serves would fail in every replacement: no restart loop."""
    code = ("import sys\nfrom countersign.web.gunicorn_server import serve_workers\n"
            "def app():\n    import countersign.no_such_module\n"
            "sys.exit(serve_workers(app, host='127.0.0.1', "
            "port=0, workers=2, log_level='critical'))")
    started = time.monotonic()
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                          timeout=120)
    assert done.returncode != 0 and time.monotonic() - started < 60, done.stderr[-2000:]
    assert "No module named 'countersign.no_such_module'" in done.stderr
