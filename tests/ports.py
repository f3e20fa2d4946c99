"""Loopback ports for the servers tests start (uvicorn, `countersign serve`, gunicorn, MOOSDB).

Binding to port 0, closing and handing the number to a server leaves a gap in which the
kernel may give the same number to someone else: another xdist worker doing the same, another
test session on the machine, or any outgoing connection (the kernel takes those from the same
ephemeral range, /proc/sys/net/ipv4/ip_local_port_range). `free_port()` closes the gap:

- it hands out ports just below the ephemeral range, which the kernel never gives out on its
  own, so no bind to 0 and no outgoing connection can take one;
- among processes that use it (xdist workers, other sessions on the machine), a port is held
  by a POSIX record lock on its byte of one shared lock file, which the holder keeps until it
  exits (the kernel drops the lock if it dies), so no two hold the same port;
- a port something already listens on (or that lingers in TIME_WAIT) is passed over."""

from __future__ import annotations

import fcntl
import os
import random
import socket
import tempfile
import threading
from pathlib import Path

# How many ports below the ephemeral range are handed out: a session needs a few dozen.
SPAN = 8_000
LOCK_FILE = Path(tempfile.gettempdir()) / "countersign-test-ports.lock"
_FALLBACK_EPHEMERAL_LOW = 32_768  # Linux's default, where /proc does not say

_guard = threading.Lock()
_held: set[int] = set()  # this process's ports: its own record locks never conflict
_lock_fd: int | None = None  # kept open: closing any descriptor of the file drops its locks


def candidate_ports() -> range:
    """The ports handed out: the SPAN ports just below the kernel's ephemeral range."""
    try:
        low = int(Path("/proc/sys/net/ipv4/ip_local_port_range").read_text().split()[0])
    except (OSError, ValueError, IndexError):
        low = _FALLBACK_EPHEMERAL_LOW
    return range(max(1024, low - SPAN), low)


def free_port() -> int:
    """A loopback port nobody listens on and that no other user of this helper holds; it
    stays this process's until the process exits."""
    ports = candidate_ports()
    start = random.randrange(len(ports))  # spread concurrent callers over the range
    with _guard:
        fd = _lock_file()
        for step in range(len(ports)):
            port = ports[(start + step) % len(ports)]
            if port in _held or not _lock(fd, port):
                continue
            if _bindable(port):
                _held.add(port)
                return port
            fcntl.lockf(fd, fcntl.LOCK_UN, 1, port)
    raise RuntimeError(f"no free loopback port in {ports.start}-{ports.stop - 1}")


def _lock_file() -> int:
    global _lock_fd
    if _lock_fd is None:
        _lock_fd = os.open(LOCK_FILE, os.O_RDWR | os.O_CREAT, 0o666)
    return _lock_fd


def _lock(fd: int, port: int) -> bool:
    try:
        fcntl.lockf(fd, fcntl.LOCK_EX | fcntl.LOCK_NB, 1, port)
    except OSError:  # another process holds it
        return False
    return True


def _bindable(port: int) -> bool:
    """Whether a server could listen on the port now (without SO_REUSEADDR: a port in
    TIME_WAIT counts as taken too)."""
    with socket.socket(socket.AF_INET, socket.SOCK_STREAM) as probe:
        try:
            probe.bind(("127.0.0.1", port))
        except OSError:
            return False
    return True
