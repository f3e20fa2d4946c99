"""Ten rehearsals at once in one process: all progress, all stop cleanly, nothing leaks."""

from __future__ import annotations

import socket
import threading
import time

import pytest

from countersign.orders.model import Orders
from countersign.rehearse.manager import RehearsalLimit, RehearsalManager, RehearsalOptions


def _open(port: int) -> bool:
    with socket.socket() as probe:
        probe.settimeout(1.0)
        return probe.connect_ex(("127.0.0.1", port)) == 0


def _settle(predicate, timeout: float = 15.0) -> bool:  # type: ignore[no-untyped-def]
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        if predicate():
            return True
        time.sleep(0.1)
    return bool(predicate())


def test_ten_rehearsals_at_once(exemplar: Orders) -> None:
    baseline = {t.ident for t in threading.enumerate()}
    manager = RehearsalManager(max_active=10, idle_timeout_s=600)
    try:
        sources = ["simulate", "manual", "replay", "tour", "simulate"] * 2
        rehearsals = [
            manager.start(exemplar, owner=f"user{k}", options=RehearsalOptions(
                source=source, seed=k, path_index=k + 1 if source == "replay" else None,  # type: ignore[arg-type]
                speed=2_000))
            for k, source in enumerate(sources)
        ]
        with pytest.raises(RehearsalLimit):
            manager.start(exemplar, owner="eleventh", options=RehearsalOptions())
        ports = [r.port for r in rehearsals]
        assert len(set(ports)) == 10 and all(_open(p) for p in ports)
        assert len({r.id for r in rehearsals}) == 10
        # All make progress concurrently.
        assert _settle(lambda: all(r.status()["sim_time_s"] > 600 for r in rehearsals), 30)
        manual = rehearsals[1]
        assert _settle(lambda: manual.status()["state"] == "waiting_for_outcome", 30)
        manual.choose("succeed")
        assert _settle(lambda: manual.status()["step"] == 1)
    finally:
        manager.shutdown()
    assert all(r.status()["state"] == "stopped" for r in rehearsals)
    assert manager.active() == []
    assert not any(_open(p) for p in ports)
    # Every thread we started (simulation, viser's event loop and pools) is gone.
    assert _settle(lambda: {t.ident for t in threading.enumerate()} <= baseline), [
        t.name for t in threading.enumerate() if t.ident not in baseline]
    records = [r.record() for r in rehearsals]
    assert all(rec.has_replay for rec in records)
    assert len({rec.digest for rec in records}) == 10
