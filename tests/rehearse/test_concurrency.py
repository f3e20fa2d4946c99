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


def test_an_idle_finished_rehearsal_stops_itself() -> None:
    from countersign.orders.examples import load_example

    manager = RehearsalManager(max_active=2, idle_timeout_s=1.0)
    try:
        rehearsal = manager.start(load_example("transect-survey"), owner="alice",
                                  options=RehearsalOptions(source="simulate", speed=1_000_000))
        port = rehearsal.port
        # `state` does not count as activity (status() and the API calls do).
        assert _settle(lambda: rehearsal.state == "stopped" and manager.active() == [], 30)
        assert manager.get(rehearsal.id) is rehearsal  # still answerable, as stopped
        assert not _open(port)
        assert rehearsal.record().has_replay
    finally:
        manager.shutdown()


def test_concurrent_stops_return_one_record(exemplar: Orders) -> None:
    manager = RehearsalManager(max_active=2, idle_timeout_s=600)
    try:
        rehearsal = manager.start(exemplar, owner="alice",
                                  options=RehearsalOptions(source="simulate", speed=500))
        records: list[object] = []
        threads = [threading.Thread(target=lambda: records.append(manager.stop(rehearsal.id)))
                   for _ in range(4)]
        for thread in threads:
            thread.start()
        for thread in threads:
            thread.join(30)
        assert len(records) == 4 and all(r is records[0] for r in records)
    finally:
        manager.shutdown()
