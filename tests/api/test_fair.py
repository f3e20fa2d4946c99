"""Fair, bounded work (issue 15): one user's heavy validations leave a validation process for
another user's small edit; the expensive routes are rate limited per user with a 429 problem."""

from __future__ import annotations

import json
import threading
import time
import uuid
from pathlib import Path

import pytest
from fastapi.testclient import TestClient

from countersign.orders.examples import example_bytes
from countersign.store.accounts import create_token, create_user
from countersign.store.db import Database
from countersign.web.app import create_app
from countersign.web.fair import Rate, RateLimiter
from countersign.web.settings import Settings

from ..heavy_orders import heavy_orders
from .conftest import World

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
            user = create_user(db, username=name, role="operator", password="a long password 1")
            tokens[name], ids[name] = create_token(db, user=user, name="tests")[1], user.id
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
