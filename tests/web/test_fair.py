"""Fair, bounded work: one user's heavy validations leave a validation process for
another user's small edit; the expensive routes are rate limited per user with a 429 problem."""

from __future__ import annotations

import inspect
import json
import os
import threading
import time
import uuid
from pathlib import Path

import pytest
from argon2.exceptions import VerifyMismatchError
from fastapi.testclient import TestClient
from sqlalchemy import func, select

from countersign.orders.examples import example_bytes
from countersign.orders.model import Orders
from countersign.plan.examples import gravitas_data
from countersign.settings import Settings
from countersign.store import accounts, login_throttle
from countersign.store.accounts import HASHER, create_token, create_user
from countersign.store.db import Database
from countersign.store.hashing import HASH_NICENESS, HASH_SLOTS, BoundedHasher
from countersign.store.tables import LoginAttempt, User
from countersign.verify import validate
from countersign.web.app import create_app
from countersign.web.fair import PlanSlots, Rate, RateLimiter
from countersign.web.validation_pool import SUBMITTER

from ..heavy_orders import heavy_orders
from .conftest import World
from .hasher_probe import probe

PATIENCE_S = 600.0  # how long a poll waits on a loaded machine before the test gives up


def _poll(condition, what: str) -> None:  # type: ignore[no-untyped-def]
    deadline = time.monotonic() + PATIENCE_S
    while not condition():
        if time.monotonic() > deadline:
            raise AssertionError(f"gave up waiting: {what}")
        time.sleep(0.02)


def test_a_second_users_edit_is_validated_while_the_first_users_heavy_jobs_run(
        tmp_path: Path) -> None:
    url = f"sqlite:///{tmp_path / 'fair.db'}"
    database = Database(url)
    app = create_app(Settings(data_dir=tmp_path, database_url=url, validation_processes=2),
                     database)
    tokens, ids = {}, {}
    with database.session() as db:
        for name in ("heavy", "light"):
            user = create_user(db, username=name, role="operator", password="a long password 1",
                               signer=database.log_signer)
            tokens[name], ids[name] = create_token(db, user=user, name="tests",
                                                   signer=database.log_signer)[1], user.id
    heavy_user = f"user:{ids['heavy']}"
    with TestClient(app, raise_server_exceptions=False) as client:  # lifespan: the pool
        pool = app.state.validation_pool
        statuses: list[int] = []

        def heavy(n: int) -> None:
            body = {**heavy_orders(), "description": f"heavy {n} {uuid.uuid4()}"}
            answer = client.post("/api/validate", json=body,
                                 headers={"Authorization": f"Bearer {tokens['heavy']}"})
            statuses.append(answer.status_code)

        # The heavy user sends three at once: with two processes they run one at a time, so
        # one process stays free for other users.
        threads = [threading.Thread(target=heavy, args=(n,)) for n in range(3)]
        for thread in threads:
            thread.start()
        _poll(lambda: pool.running(heavy_user) >= 1 and pool.pending(heavy_user) == 3,
              "the heavy user's validations to be queued")
        small = json.loads(example_bytes("search-and-sample"))
        small["description"] = f"a small edit {uuid.uuid4()}"
        answer = client.post("/api/validate", json=small,
                             headers={"Authorization": f"Bearer {tokens['light']}"})
        assert answer.status_code == 200, answer.text
        # Answered before any of the heavy user's jobs (each seconds of solver budget) ended.
        assert statuses == [] and pool.pending(heavy_user) == 3
        for thread in threads:
            thread.join(PATIENCE_S)
        assert statuses == [200, 200, 200]


@pytest.mark.parametrize(("kind", "method", "path", "body"), [
    ("validate", "post", "/api/validate", "exemplar"),
    ("read", "post", "/api/read", "exemplar"),
    ("import", "post", "/api/import", "exemplar"),
    ("plan", "post", "/api/plan", {"format": "countersign.plan/1", "level": 3}),
])
def test_expensive_routes_answer_429_with_retry_after_per_user(
        world: World, kind: str, method: str, path: str, body: object) -> None:
    world.app.state.rate_limiter = RateLimiter({"validate": Rate(2, 0.001), "read": Rate(
        2, 0.001), "import": Rate(2, 0.001), "plan": Rate(2, 0.001)})
    content = example_bytes("search-and-sample") if body == "exemplar" else json.dumps(
        body).encode()

    def send(client: TestClient) -> int:
        answer = client.request(method, path, content=content,
                                headers={"Content-Type": "application/json"})
        return answer.status_code

    operator = world.client("operator")
    assert [send(operator) < 429 for _ in range(2)] == [True, True]
    refused = operator.request(method, path, content=content,
                               headers={"Content-Type": "application/json"})
    assert refused.status_code == 429, refused.text
    assert int(refused.headers["Retry-After"]) >= 1
    assert refused.headers["content-type"].startswith("application/problem+json")
    problem = refused.json()
    assert problem["status"] == 429 and kind in problem["detail"]
    assert problem["instance"] == path
    # Another user has a bucket of their own.
    other = world.client("supervisor" if kind in {"read", "import"} else "auditor")
    assert send(other) < 429


def test_a_user_runs_one_plan_at_a_time_and_a_process_a_few(world: World) -> None:
    slots = PlanSlots(per_user=1, total=2)
    world.app.state.plan_slots = slots
    with world.database.session() as db:
        ids = {role: db.query(User).filter_by(username=world.usernames[role]).one().id
               for role in ("operator", "auditor", "supervisor")}
    client = world.client("operator")
    with slots.hold(f"user:{ids['operator']}"):  # the operator's plan still being solved
        busy = client.post("/api/plan", json=gravitas_data())
        assert busy.status_code == 429 and int(busy.headers["Retry-After"]) >= 1
        assert busy.headers["content-type"].startswith("application/problem+json")
        assert "plan of yours" in busy.json()["detail"]
        # Another user's plan runs meanwhile.
        assert world.client("auditor").post("/api/plan", json=gravitas_data()).status_code == 200
        with slots.hold(f"user:{ids['auditor']}"):  # two plans in this process: full
            full = world.client("supervisor").post("/api/plan", json=gravitas_data())
            assert full.status_code == 429 and "busy" in full.json()["detail"]
    assert client.post("/api/plan", json=gravitas_data()).status_code == 200


def test_password_hashes_take_a_bounded_slot() -> None:
    hasher = BoundedHasher(slots=1, time_cost=1, memory_cost=8, parallelism=1)
    stored = hasher.hash("a long password 1")
    results: list[bool] = []
    hasher.slots.acquire()  # another login's hash holds the only slot
    try:
        waiting = threading.Thread(target=lambda: results.append(
            hasher.verify(stored, "a long password 1")))
        waiting.start()
        waiting.join(0.5)
        assert waiting.is_alive() and results == []
    finally:
        hasher.slots.release()
    waiting.join(PATIENCE_S)
    assert results == [True]
    assert isinstance(HASHER, BoundedHasher) and HASHER.slots._initial_value == HASH_SLOTS


def test_a_running_server_hashes_in_a_low_priority_process() -> None:
    hasher = BoundedHasher(time_cost=1, memory_cost=8, parallelism=1)
    stored = hasher.hash("a long password 1")
    hasher.use_processes()
    try:
        seen = probe(hasher)
        assert seen is not None
        pid, niceness = seen
        assert pid != os.getpid()
        assert niceness == HASH_NICENESS
        assert hasher.verify(stored, "a long password 1")
        with pytest.raises(VerifyMismatchError):  # a wrong password fails as in a thread
            hasher.verify(stored, "another password 2")
    finally:
        hasher.stop_processes()
    assert probe(hasher) is None


def test_a_login_beyond_the_hash_queue_is_refused_at_once_and_not_counted(
        world: World, monkeypatch: pytest.MonkeyPatch) -> None:
    hasher = BoundedHasher(time_cost=1, memory_cost=8, parallelism=1)
    monkeypatch.setattr(accounts, "HASHER", hasher)
    monkeypatch.setattr(login_throttle, "HASHER", hasher)  # every password check's
    hasher.use_processes(waiting=0)  # as if a flood held every place in the queue
    assert probe(hasher) is not None  # the hashing process is up
    try:
        answer = world.client().post("/api/auth/login", json={
            "username": "operator1", "password": "not the password"})
    finally:
        hasher.stop_processes()
    assert answer.status_code == 503, answer.text
    assert answer.headers["content-type"].startswith("application/problem+json")
    assert answer.headers["Retry-After"] == "1" and "busy" in answer.json()["detail"]
    with world.database.session() as db:  # the refused try costs the account nothing
        assert db.scalar(select(func.count()).select_from(LoginAttempt)) == 0


def test_health_answers_on_the_event_loop(world: World) -> None:
    # Not in a worker thread: logins and plans holding every thread cannot delay it.
    route = next(r for r in world.app.routes if getattr(r, "path", "") == "/api/health")
    assert inspect.iscoroutinefunction(route.endpoint)  # type: ignore[attr-defined]


def test_a_draft_edit_is_validated_in_its_authors_queue(world: World) -> None:
    seen: list[str] = []

    def validator(orders: Orders) -> dict[str, object]:
        seen.append(SUBMITTER.get())
        return validate(orders).to_json()

    world.database.reports.validator = validator
    client = world.client("operator")
    orders = client.get("/api/missions/search-and-sample").json()["orders"]
    orders["title"] = f"Edited {uuid.uuid4()}"
    answer = client.put("/api/missions/search-and-sample/draft", json={"orders": orders},
                        headers={"If-Match": '"1"'})
    assert answer.status_code == 200, answer.text
    with world.database.session() as db:
        operator = db.query(User).filter_by(username=world.usernames["operator"]).one()
    # Reading the mission (its report) and saving the edit both validate, in the operator's queue.
    assert seen and set(seen) == {f"user:{operator.id}"}
