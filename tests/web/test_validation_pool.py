"""Validation beside the web process: a running app (its lifespan) validates in a pool
process at a lower priority, gives the same reports as validating in place, survives the
death of that process; /validate reads its body itself and refuses what is not orders."""

from __future__ import annotations

import json
import os
import signal
import uuid
from pathlib import Path

import pytest
from fastapi.testclient import TestClient

from countersign.orders.canonical import orders_to_json
from countersign.orders.examples import example_bytes, load_example
from countersign.orders.reader import orders_from_data
from countersign.settings import Settings
from countersign.store.accounts import create_token, create_user
from countersign.store.db import Database
from countersign.verify import validate
from countersign.web import app as app_module
from countersign.web import validation_pool
from countersign.web.app import create_app
from countersign.web.validation_pool import NICENESS

from .conftest import World


def _running_app(tmp_path: Path) -> tuple[TestClient, Database, str]:
    url = f"sqlite:///{tmp_path / 'pool.db'}"
    database = Database(url)
    app = create_app(Settings(data_dir=tmp_path, database_url=url, validation_processes=1),
                     database)
    with database.session() as db:
        user = create_user(db, username="op", role="operator", password="a long password 1",
                           signer=database.log_signer)
        token = create_token(db, user=user, name="tests", signer=database.log_signer)[1]
    return TestClient(app, raise_server_exceptions=False), database, token


def test_a_running_app_validates_in_a_pool_process(tmp_path: Path,
                                                   monkeypatch: pytest.MonkeyPatch) -> None:
    # However slow the shared machine, the app's start waits for the warm-up.
    monkeypatch.setattr(app_module, "WARM_WAIT_S", 3600.0)
    client, database, token = _running_app(tmp_path)
    client.headers["Authorization"] = f"Bearer {token}"
    # Orders no other test validated: the process keeps its recent reports (report_service),
    # and reuses a report for an edit of descriptions only, so the title differs.
    orders = {**orders_to_json(load_example("search-and-sample")),
              "title": f"pool test {uuid.uuid4()}"}
    with client:  # runs the lifespan, as `countersign serve` does
        pool = client.app.state.validation_pool  # type: ignore[attr-defined]
        assert database.reports.validator is not None
        # The app served only once its validation process had warmed up.
        [warm] = pool.wait_warm(0)
        answer = client.post("/api/validate", json=orders)
        assert answer.status_code == 200, answer.text
        assert answer.json() == validate(orders_from_data(orders)).to_json()
        first = pool.last_pid
        assert first is not None and first != os.getpid() and first == warm
        if os.getpriority(os.PRIO_PROCESS, 0) + NICENESS <= 19:
            assert os.getpriority(os.PRIO_PROCESS, first) == (
                os.getpriority(os.PRIO_PROCESS, 0) + NICENESS)

        # The pool's process dies (killed, out of memory): the next validation still answers.
        os.kill(first, signal.SIGKILL)
        # A title, not a description: an edit of descriptions only reuses the last report.
        changed = {**orders, "title": f"after the pool process died {uuid.uuid4()}"}
        again = client.post("/api/validate", json=changed)
        assert again.status_code == 200, again.text
        assert again.json()["digest"] != answer.json()["digest"]
        assert pool.last_pid not in (None, first)
    # The lifespan's end stops the pool and validation falls back to the calling thread.
    assert database.reports.validator is None


def test_validate_reads_its_body_and_refuses_what_is_not_orders(world: World) -> None:
    client = world.client("auditor")
    body = example_bytes("search-and-sample")
    first = client.post("/api/validate", content=body,
                        headers={"Content-Type": "application/json"})
    # The same bytes again are answered from their digest: the same report.
    second = client.post("/api/validate", content=body,
                         headers={"Content-Type": "application/json"})
    assert first.status_code == second.status_code == 200
    assert first.json() == second.json() and first.json()["ok"] is True
    for bad, expected in ((b"{not json", "invalid JSON"), (b"[1, 2]", "JSON object"),
                          (b"", "invalid JSON"), (b'{"id": "a", "id": "b"}', "twice")):
        answer = client.post("/api/validate", content=bad,
                             headers={"Content-Type": "application/json"})
        assert answer.status_code == 422, (bad, answer.text)
        problem = answer.json()
        assert answer.headers["content-type"].startswith("application/problem+json")
        assert any(expected in error["message"] for error in problem["errors"]), problem
    unreadable = client.post("/api/validate", content=json.dumps({"id": 5}).encode(),
                             headers={"Content-Type": "application/json"})
    assert 400 <= unreadable.status_code < 500, unreadable.text


def test_validation_processes_setting_is_checked(monkeypatch: pytest.MonkeyPatch,
                                                 tmp_path: Path) -> None:
    monkeypatch.setenv("COUNTERSIGN_VALIDATION_PROCESSES", "many")
    with pytest.raises(ValueError, match="COUNTERSIGN_VALIDATION_PROCESSES"):
        Settings.from_environment(tmp_path)
    monkeypatch.setenv("COUNTERSIGN_VALIDATION_PROCESSES", "0")
    assert Settings.from_environment(tmp_path).validation_processes == 0


def test_validation_processes_are_replaced_for_their_memory_not_their_count() -> None:
    # Bounded memory: z3 and the caches keep what they allocate, so a process whose resident
    # memory passed the limit after a job is replaced by a fresh one from the forkserver;
    # under the limit it keeps serving (and keeps its caches), however many jobs it ran.
    orders = load_example("search-and-sample")
    for limit, replaced in ((1, True), (2**40, False)):
        pool = validation_pool.ValidationPool(1, max_rss=limit)
        try:
            pids = []
            for _ in range(4):
                pool.validate(orders)
                pids.append(pool.last_pid)
            if replaced:
                assert len(set(pids)) == 4 and pool.replaced == 4, pids
            else:
                assert len(set(pids)) == 1 and pool.replaced == 0, pids
        finally:
            pool.shutdown()


def test_the_pool_starts_warm_and_sends_a_mission_to_its_last_process() -> None:
    pool = validation_pool.ValidationPool(2)
    try:
        # Started and warmed up with the pool, before any validation was asked for.
        warm = pool.wait_warm(timeout=600)
        assert len(set(warm)) == 2 and os.getpid() not in warm
        one = load_example("search-and-sample")
        other = one.model_copy(update={"id": "another-mission"})
        pids: dict[str, list[int | None]] = {one.id: [], other.id: []}
        for orders in (one, other, other, one, one, other):
            pool.validate(orders)
            pids[orders.id].append(pool.last_pid)
        # Each mission stays with the process that holds its caches; the two are spread.
        assert len(set(pids[one.id])) == 1 and len(set(pids[other.id])) == 1, pids
        assert pids[one.id][0] != pids[other.id][0] and set(warm) == {
            pids[one.id][0], pids[other.id][0]}, (pids, warm)
    finally:
        pool.shutdown()
