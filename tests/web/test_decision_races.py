"""Finding 4 / item 6: races closed by the database. On PostgreSQL (READ COMMITTED)
approve and reject posted at once were both accepted, and parallel submits of one version left
several active submissions. Row locks serialise them; unique partial indexes back them up.
Runs on both engines (SQLite serialises writers already); the PostgreSQL run is the one that
found the race."""

from __future__ import annotations

import threading
from collections import Counter

import httpx
import pytest

from countersign.store import login_throttle

from .approval_helpers import MISSION, new_version, prepare, register_key, sign_prepared, submit
from .conftest import PASSWORD, World, count_rows

DECISION_ROUNDS = 20
SUBMIT_ROUNDS = 10
SUBMITTERS = 4


def _at_once(server: str, token: str, posts: list[tuple[str, dict[str, object]]]
             ) -> list[httpx.Response]:
    barrier = threading.Barrier(len(posts))
    answers: list[httpx.Response | None] = [None] * len(posts)

    def post(i: int) -> None:
        with httpx.Client(base_url=server, timeout=120,
                          headers={"Authorization": f"Bearer {token}"}) as client:
            barrier.wait(timeout=60)
            answers[i] = client.post(posts[i][0], json=posts[i][1])

    threads = [threading.Thread(target=post, args=(i,)) for i in range(len(posts))]
    for thread in threads:
        thread.start()
    for thread in threads:
        thread.join(timeout=180)
    assert all(a is not None for a in answers), "a request did not finish"
    return [a for a in answers if a is not None]


def test_approve_and_reject_at_once_give_exactly_one_decision(
        world: World, server: str, monkeypatch: pytest.MonkeyPatch) -> None:
    # Forty decisions in a minute by one supervisor: the race is the subject here, the
    # password throttle (10 checks per account per minute) is test_password_throttle's.
    monkeypatch.setattr(login_throttle, "ACCOUNT_HASHES_PER_MINUTE", 1000)
    monkeypatch.setattr(login_throttle, "ADDRESS_HASHES_PER_MINUTE", 1000)
    supervisor = world.client("supervisor")
    signer = register_key(supervisor)
    for _ in range(DECISION_ROUNDS):
        submission = submit(world, new_version(world))
        approve = sign_prepared(prepare(supervisor, submission, signer, "approved"), signer)
        reject = sign_prepared(prepare(supervisor, submission, signer, "rejected", "no"),
                               signer)
        path = f"/api/submissions/{submission}/decision"
        answers = _at_once(server, world.tokens["supervisor"], [
            (path, {"envelope": approve, "password": PASSWORD}),
            (path, {"envelope": reject, "password": PASSWORD})])
        statuses = Counter(a.status_code for a in answers)
        assert statuses == Counter({201: 1, 409: 1}), [a.text for a in answers]
        refused = next(a for a in answers if a.status_code == 409)
        assert refused.headers["content-type"] == "application/problem+json"
        assert count_rows(world.database, "SELECT count(*) FROM approvals WHERE "
                          f"submission_id = {submission}") == 1


def test_parallel_submits_of_one_version_give_one_active_submission(world: World,
                                                                    server: str) -> None:
    for _ in range(SUBMIT_ROUNDS):
        number = new_version(world)
        path = f"/api/missions/{MISSION}/versions/{number}/submit"
        answers = _at_once(server, world.tokens["operator"], [(path, {})] * SUBMITTERS)
        statuses = Counter(a.status_code for a in answers)
        assert statuses == Counter({201: 1, 409: SUBMITTERS - 1}), [a.text for a in answers]
        assert count_rows(world.database, (
            "SELECT count(*) FROM submissions s JOIN mission_versions v ON v.id = s.version_id "
            f"WHERE v.mission_id = '{MISSION}' AND v.number = {number} "
            "AND s.state IN ('submitted', 'approved')")) == 1
