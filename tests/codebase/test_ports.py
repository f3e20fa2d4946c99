"""Ports for test servers (tests/ports.py): outside the kernel's ephemeral range, never held by
two processes at once (xdist workers, other sessions), never one something listens on."""

from __future__ import annotations

import re
import socket
import subprocess
import sys
import textwrap
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path

import pytest

from .. import ports
from ..ports import free_port

REPO = Path(__file__).resolve().parents[2]
TESTS = REPO / "tests"
# A port picked by binding to 0 and closing: the race the helper exists to avoid.
PICKED_BY_BIND_ZERO = re.compile(r"""\.bind\(\(["'](?:127\.0\.0\.1|localhost|)["'],\s*0\)\)""")
PER_PROCESS = 40


@contextmanager
def holders(count: int, each: int) -> Iterator[list[list[int]]]:
    """`count` processes that each take `each` ports at once and hold them until the block
    ends: their ports, read once every one has taken all of its ports."""
    code = textwrap.dedent(f"""
        import sys
        from tests.ports import free_port
        print(" ".join(str(free_port()) for _ in range({each})), flush=True)
        sys.stdin.read()  # hold the ports until the test lets go
    """)
    processes = [subprocess.Popen([sys.executable, "-c", code], cwd=REPO, text=True,
                                  stdin=subprocess.PIPE, stdout=subprocess.PIPE)
                 for _ in range(count)]
    try:
        taken = []
        for process in processes:
            assert process.stdout is not None
            taken.append([int(p) for p in process.stdout.readline().split()])
        yield taken
    finally:
        for process in processes:
            assert process.stdin is not None
            process.stdin.close()
            process.wait(timeout=60)


def test_a_port_is_below_the_ephemeral_range_and_free() -> None:
    """Where no bind to 0 and no outgoing connection can be given it meanwhile."""
    low, high = (int(n) for n in Path(
        "/proc/sys/net/ipv4/ip_local_port_range").read_text().split())
    port = free_port()
    assert port < low and not low <= port <= high
    with socket.socket() as server:
        server.bind(("127.0.0.1", port))
        server.listen()


def test_processes_taking_ports_at_once_never_share_one() -> None:
    with holders(3, PER_PROCESS) as taken:
        mine = [free_port() for _ in range(PER_PROCESS)]
        every = [p for ports_of in [*taken, mine] for p in ports_of]
        assert all(len(t) == PER_PROCESS for t in taken)
        assert len(set(every)) == len(every) == 4 * PER_PROCESS


def test_a_held_port_is_passed_over_until_its_holder_exits(
        monkeypatch: pytest.MonkeyPatch) -> None:
    with holders(1, 1) as taken:
        held = taken[0][0]
        monkeypatch.setattr(ports, "candidate_ports", lambda: range(held, held + 1))
        with pytest.raises(RuntimeError, match="no free loopback port"):
            free_port()
    assert free_port() == held


def test_a_port_something_listens_on_is_passed_over(monkeypatch: pytest.MonkeyPatch) -> None:
    with socket.socket() as other:
        other.bind(("127.0.0.1", free_port()))
        other.listen()
        busy = other.getsockname()[1]
        # Held by nobody else: as if a program that does not use the helper listened there.
        ports._held.discard(busy)
        monkeypatch.setattr(ports, "candidate_ports", lambda: range(busy, busy + 1))
        with pytest.raises(RuntimeError, match="no free loopback port"):
            free_port()


def test_every_test_takes_its_ports_from_the_helper() -> None:
    found = [f"{path.relative_to(REPO)}:{n}" for path in sorted(TESTS.rglob("*.py"))
             if path.name not in ("ports.py", "test_ports.py")
             for n, line in enumerate(path.read_text().splitlines(), 1)
             if PICKED_BY_BIND_ZERO.search(line)]
    assert found == [], f"use tests/ports.py free_port(): {found}"
