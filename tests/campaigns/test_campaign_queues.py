"""The in-process runner's queues: owners taken in turn, a lone owner (the
command line's, whose owner is None) on every worker, and a newcomer's job started as soon as a
worker is free. The jobs are stand-ins that wait for the test to release them, so the order in
which the runner starts them is what is asserted, not timings."""

from __future__ import annotations

import io
import json
import os
import subprocess
import sys
import threading
from pathlib import Path
from typing import Any

import pytest

from countersign.cli import campaign as cli_campaign
from countersign.jobs import inprocess
from countersign.orders.canonical import digest, orders_to_json
from countersign.orders.examples import load_example
from countersign.store import campaigns as store
from countersign.store.accounts import create_user
from countersign.store.db import Database
from countersign.store.tables import User

WAIT_S = 60.0


class HeldJobs:
    """Stand-in for a chunk's job: records its start and waits to be released."""

    def __init__(self) -> None:
        self.started: list[tuple[str, int]] = []
        self.release: dict[tuple[str, int], threading.Event] = {}
        self.changed = threading.Condition()

    def __call__(self, database: Database, campaign_id: str, start: int, stop: int,
                 on_stored: Any) -> int:
        key = (campaign_id, start)
        with self.changed:
            self.release[key] = threading.Event()
            self.started.append(key)
            self.changed.notify_all()
        assert self.release[key].wait(WAIT_S), f"job {key} never released"
        return 0

    def until_started(self, count: int) -> list[tuple[str, int]]:
        with self.changed:
            assert self.changed.wait_for(lambda: len(self.started) >= count, WAIT_S)
            return list(self.started)


@pytest.fixture
def database(tmp_path: Path) -> Database:
    database = Database(f"sqlite:///{tmp_path / 'queues.db'}")
    database.migrate()
    return database


def _campaign(database: Database, owner: int | None) -> str:
    orders = load_example("search-and-sample")
    with database.session() as db:
        user = db.get(User, owner) if owner is not None else None
        return str(store.create(db, orders=orders_to_json(orders), orders_digest=digest(orders),
                                spec={"simulations": 4}, simulations=4, owner=user,
                                signer=database.log_signer).id)


def test_the_command_lines_lone_campaign_uses_every_worker(
        database: Database, monkeypatch: pytest.MonkeyPatch) -> None:
    jobs = HeldJobs()
    monkeypatch.setattr(inprocess, "_attempts", jobs)
    runner = inprocess.InProcessRunner(database, workers=2)
    try:
        campaign = _campaign(database, None)
        runner.enqueue(campaign, [(0, 1), (1, 2), (2, 3)])
        assert jobs.until_started(2) == [(campaign, 0), (campaign, 1)]
        jobs.release[(campaign, 0)].set()
        assert jobs.until_started(3)[2] == (campaign, 2)
        for event in jobs.release.values():
            event.set()
        runner.wait(WAIT_S)
        assert runner.waiting() == 0
    finally:
        runner.close()


def test_a_newcomers_job_starts_before_the_first_owners_next(
        database: Database, monkeypatch: pytest.MonkeyPatch) -> None:
    jobs = HeldJobs()
    monkeypatch.setattr(inprocess, "_attempts", jobs)
    with database.session() as db:
        first = create_user(db, username="first", role="operator",
                            password="Tq7-Lantern-Quay-41", signer=database.log_signer).id
        second = create_user(db, username="second", role="operator",
                             password="Vx3-Harbor-Mist-58", signer=database.log_signer).id
    runner = inprocess.InProcessRunner(database, workers=2)
    try:
        big = _campaign(database, first)
        small = _campaign(database, second)
        runner.enqueue(big, [(0, 1), (1, 2), (2, 3), (3, 4)])
        jobs.until_started(2)
        runner.enqueue(small, [(0, 1)])
        jobs.release[(big, 0)].set()
        assert jobs.until_started(3)[2] == (small, 0)
        for key in [(big, 1), (small, 0)]:
            jobs.release[key].set()
        assert set(jobs.until_started(5)[3:]) == {(big, 2), (big, 3)}
        for event in jobs.release.values():
            event.set()
        runner.wait(WAIT_S)
    finally:
        runner.close()


def test_the_command_line_stops_when_its_jobs_end_unfinished(
        database: Database, capsys: pytest.CaptureFixture[str]) -> None:
    campaign = _campaign(database, None)  # queued, and nothing will ever run it
    assert cli_campaign._watch(database, campaign, "text", io.StringIO(), lambda: True) == 1
    assert f"--resume {campaign}" in capsys.readouterr().err


def test_a_small_campaign_on_two_worker_processes_finishes(tmp_path: Path) -> None:
    env = {**os.environ, "COUNTERSIGN_DATA_DIR": str(tmp_path)}
    env.pop("COUNTERSIGN_DATABASE_URL", None)
    run = subprocess.run(
        [sys.executable, "-m", "countersign.cli", "campaign", "run", "example:search-and-sample",
         "-n", "8", "--chunk", "2", "--workers", "2", "--format", "json"],
        env=env, capture_output=True, timeout=600, check=False)
    assert run.returncode == 0, run.stderr.decode()[-2000:]
    report = json.loads(run.stdout)
    assert report["state"] == "finished" and report["done"] == 8
