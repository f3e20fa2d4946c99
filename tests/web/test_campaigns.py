"""Campaigns through the API on the in-process runner (SQLite) and, with
COUNTERSIGN_TEST_POSTGRES_URL, the procrastinate queue: start, follow, cancel, bounds,
per-person concurrency, the offered probabilities (never written into orders), attachment."""

from __future__ import annotations

import json
import time
from typing import Any

import pytest
from fastapi.testclient import TestClient
from sqlalchemy import text

from countersign.approvals import dsse
from countersign.approvals.bundle import verify_bundle
from countersign.campaigns.stats import goal_probabilities
from countersign.store import campaigns as store
from countersign.web.routes.campaign_schemas import (
    CampaignRecord,
    CampaignResults,
    CampaignSpecOut,
    OfferedProbabilities,
)

from .approval_helpers import (
    MISSION,
    approve,
    new_version,
    prepare,
    register_key,
    submit,
)
from .conftest import World
from .described import assert_described


def _wait_finished(client: TestClient, campaign_id: str, timeout_s: float = 600) -> dict[str, Any]:
    deadline = time.monotonic() + timeout_s
    while True:
        body: dict[str, Any] = client.get(f"/api/campaigns/{campaign_id}").json()
        if body["state"] not in ("queued", "running"):
            return body
        assert time.monotonic() < deadline, f"campaign still {body['state']}: {body['done']}"
        time.sleep(0.2)


def _start(client: TestClient, number: int, **body: Any) -> Any:
    return client.post(f"/api/missions/{MISSION}/versions/{number}/campaigns",
                       json={"simulations": 4, **body})


@pytest.fixture
def sqlite_world(world: World) -> World:
    if world.database.engine.dialect.name != "sqlite":
        pytest.skip("the in-process runner runs the jobs on SQLite; PostgreSQL needs workers "
                    "(tests/campaigns/test_campaign_kill.py)")
    return world


def test_a_campaign_runs_reports_and_offers_probabilities(sqlite_world: World) -> None:
    world = sqlite_world
    number = new_version(world)
    operator = world.client("operator")
    started = _start(operator, number, faults=["none", "nav_drift"])
    assert started.status_code == 201, started.text
    campaign = started.json()
    assert campaign["state"] in ("queued", "running") and campaign["simulations"] == 4
    done = _wait_finished(operator, campaign["id"])
    assert done["state"] == "finished" and done["done"] == 4
    results = done["results"]
    assert results["coverage"]["total_paths"] == 75
    assert results["simulations"] == 4
    assert sum(results["energy_wh"]["histogram"]["counts"]) == 4
    auditor = world.client("auditor")
    offered = auditor.get(f"/api/campaigns/{campaign['id']}/probabilities")
    assert offered.status_code == 200
    assert set(offered.json()["goals"]["G1"]["point"]) == {"succeed", "fail", "violate"}
    _assert_whole_answers(world, done, offered.json())
    # Offered, not written: the version's orders carry no p.
    version = operator.get(f"/api/missions/{MISSION}/versions/{number}").json()
    assert all("p" not in g for g in version["orders"]["goals"])
    listed = auditor.get(f"/api/missions/{MISSION}/campaigns").json()
    assert [c["id"] for c in listed] == [campaign["id"]]
    # Attached to a submission of exactly that version, by the submitting operator.
    submission = submit(world, number)
    refused = world.client("supervisor").post(f"/api/submissions/{submission}/campaigns",
                                              json={"campaign": campaign["id"]})
    assert refused.status_code == 403
    attached = operator.post(f"/api/submissions/{submission}/campaigns",
                             json={"campaign": campaign["id"]})
    assert attached.status_code == 201, attached.text
    assert attached.json()["digest"] == done["digest"]
    assert auditor.get(f"/api/submissions/{submission}/campaigns").json()[0]["campaign"] \
        == campaign["id"]


def _assert_whole_answers(world: World, done: dict[str, Any], offered: dict[str, Any]) -> None:
    """The answers are the stored records, and their response models describe those records
    field for field (the front end's types come from the models)."""
    with world.database.session() as db:
        row = store.get(db, done["id"])
        spec, record = row.spec, row.record
    assert record is not None
    assert done["spec"] == spec and done["results"] == record["results"]
    assert offered["goals"] == goal_probabilities(record["results"])
    assert_described(CampaignSpecOut, spec)
    assert_described(CampaignResults, record["results"])
    assert_described(dict[str, OfferedProbabilities], offered["goals"])


def test_bad_campaigns_are_refused_naming_the_field(world: World) -> None:
    number = new_version(world)
    operator = world.client("operator")
    for body, word in [({"simulations": 0}, "simulations"),
                       ({"simulations": 10_001}, "simulations"),
                       ({"faults": ["boom"]}, "boom"),
                       ({"faults": ["leak"], "goals": ["G99"]}, "G99"),
                       ({"seed": -1}, "seed")]:
        response = _start(operator, number, **body)
        assert response.status_code == 422, (body, response.text)
        assert word in response.text
    assert _start(world.client("auditor"), number).status_code == 403
    assert operator.get("/api/campaigns/" + "0" * 16).status_code == 404
    assert operator.get("/api/campaigns/not-an-id").status_code == 422


def test_one_person_runs_a_bounded_number_of_campaigns_and_cancels_their_own(
        world: World, monkeypatch: pytest.MonkeyPatch) -> None:
    # No runner: the campaigns stay queued, as they would behind busy workers.
    class Idle:
        def enqueue(self, campaign_id: str, chunks: list[tuple[int, int]]) -> None:
            pass

        def close(self) -> None:
            pass

    world.app.state.campaign_runner = Idle()
    number = new_version(world)
    operator = world.client("operator")
    ids = [_start(operator, number).json()["id"] for _ in range(store.MAX_ACTIVE_PER_USER)]
    third = _start(operator, number)
    assert third.status_code == 429
    assert f"at most {store.MAX_ACTIVE_PER_USER}" in third.text
    assert _start(world.client("supervisor"), number).status_code == 201  # another person
    assert world.client("supervisor").post(f"/api/campaigns/{ids[0]}/cancel").status_code == 403
    cancelled = operator.post(f"/api/campaigns/{ids[0]}/cancel")
    assert cancelled.status_code == 200 and cancelled.json()["state"] == "cancelled"
    assert _start(operator, number).status_code == 201
    # A cancelled campaign's jobs stop without simulating.
    from countersign.jobs.tasks import run_chunk

    assert run_chunk(world.database, ids[0], 0, 4) == 0


def test_an_attached_campaign_is_signed_exported_and_checked(sqlite_world: World) -> None:
    """The signature covers the campaign the supervisor was shown: its record
    digest is in the statement, the audit bundle carries the record, and a record changed in
    the database afterwards is reported, not trusted."""
    world = sqlite_world
    number = new_version(world)
    operator = world.client("operator")
    campaign = _start(operator, number).json()
    done = _wait_finished(operator, campaign["id"])
    submission = submit(world, number)
    supervisor = world.client("supervisor")
    signer = register_key(supervisor)
    bare = prepare(supervisor, submission, signer)["statement"]["predicate"]
    assert "campaigns" not in bare  # nothing attached yet: the statement says nothing of it
    attached = operator.post(f"/api/submissions/{submission}/campaigns",
                             json={"campaign": campaign["id"]})
    assert attached.status_code == 201, attached.text
    # Attached: the statement to sign cites the campaign's record by digest.
    prepared = prepare(supervisor, submission, signer)
    assert prepared["statement"]["predicate"]["campaigns"] == [done["digest"]]
    payload = json.loads(dsse.unb64(prepared["payload"], "payload"))
    assert payload["predicate"]["campaigns"] == [done["digest"]]
    approve(world, supervisor, signer, submission)

    bundle = world.client("auditor").get("/api/audit/bundle").json()
    assert bundle["campaigns"][done["digest"]]["orders"]["digest"] \
        == operator.get(f"/api/missions/{MISSION}/versions/{number}").json()["digest"]
    assert verify_bundle(bundle).problems == []
    with world.database.session() as db:
        stored = store.get(db, campaign["id"]).record
    assert bundle["campaigns"] == {done["digest"]: stored}
    assert_described(CampaignRecord, stored)

    # A database writer edits the stored campaign record: the bundle's check names it.
    with world.database.engine.begin() as connection:
        row = connection.execute(text("SELECT record FROM campaigns WHERE id = :id"),
                                 {"id": campaign["id"]}).scalar_one()
        record = json.loads(row) if isinstance(row, str) else row
        record["simulations"] = 1000
        connection.execute(text("UPDATE campaigns SET record = :r WHERE id = :id"),
                           {"r": json.dumps(record), "id": campaign["id"]})
    tampered = world.client("auditor").get("/api/audit/bundle").json()
    problems = verify_bundle(tampered).problems
    assert any(f"the campaign record does not hash to the cited digest {done['digest']}" in p
               for p in problems), problems
    # Dropped from the bundle: named as missing.
    tampered["campaigns"] = {}
    assert any(f"lacks the campaign record {done['digest']}" in p
               for p in verify_bundle(tampered).problems)


def test_another_users_small_campaign_finishes_while_one_users_big_ones_wait(
        sqlite_world: World) -> None:
    """The runner takes its owners' queues in turn, so one person's two big
    campaigns (the most one may have) do not hold back another person's small one."""
    world = sqlite_world
    number = new_version(world)
    operator, supervisor = world.client("operator"), world.client("supervisor")
    big = [_start(operator, number, simulations=2000, seed=n).json()["id"] for n in (1, 2)]
    small = _start(supervisor, number, simulations=10)
    assert small.status_code == 201, small.text
    try:
        assert _wait_finished(supervisor, small.json()["id"])["state"] == "finished"
        states = [operator.get(f"/api/campaigns/{c}").json() for c in big]
        assert [s["state"] for s in states] == ["running", "queued"] or all(
            s["state"] in ("queued", "running") for s in states), states
        assert sum(s["done"] for s in states) < 2 * 2000
    finally:
        for campaign in big:
            operator.post(f"/api/campaigns/{campaign}/cancel")


def test_two_users_running_the_same_spec_both_finish(sqlite_world: World) -> None:
    """The second campaign of the same orders and spec seals the same record
    under the same digest instead of failing on a UNIQUE digest after all its runs."""
    world = sqlite_world
    number = new_version(world)
    done = []
    for role in ("operator", "supervisor"):
        client = world.client(role)
        started = _start(client, number, faults=["none", "leak"])
        assert started.status_code == 201, started.text
        done.append(_wait_finished(client, started.json()["id"]))
    assert [d["state"] for d in done] == ["finished", "finished"], done
    assert done[0]["digest"] == done[1]["digest"] and done[0]["id"] != done[1]["id"]
    assert done[0]["results"] == done[1]["results"]


def test_fault_reach_names_a_fault_nothing_reacts_to(world: World) -> None:
    # before a campaign, which faults can change an outcome of the version.
    number = new_version(world)
    reader = world.client("auditor")
    url = f"/api/missions/{MISSION}/versions/{number}/fault-reach"
    answer = reader.get(url, params=[("fault", "leak"), ("fault", "none"),
                                     ("fault", "contact_close")])
    assert answer.status_code == 200, answer.text
    by_fault = {r["fault"]: r for r in answer.json()}
    assert set(by_fault) == {"leak", "contact_close"}  # "none" is no fault
    # The seeded mission's constraints read what both change (C2, C3; C6).
    assert by_fault["leak"]["reacts"] and by_fault["contact_close"]["reacts"]
    # Bad input is a 4xx naming what is wrong, never a 500.
    assert reader.get(url, params={"fault": "<b>"}).status_code == 422
    assert reader.get(url).status_code == 422
    assert reader.get(url, params=[("fault", "leak")] * 17).status_code == 422
    assert reader.get(f"/api/missions/{MISSION}/versions/999/fault-reach",
                      params={"fault": "leak"}).status_code == 404


def _rewrite_record(world: World, campaign_id: str, **changes: Any) -> None:
    """What a database writer who is not the app does: the record changes, its digest stays."""
    with world.database.engine.begin() as connection:
        row = connection.execute(text("SELECT record FROM campaigns WHERE id = :id"),
                                 {"id": campaign_id}).scalar_one()
        record = json.loads(row) if isinstance(row, str) else row
        record.update(changes)
        connection.execute(text("UPDATE campaigns SET record = :r WHERE id = :id"),
                           {"r": json.dumps(record), "id": campaign_id})


def test_a_record_changed_in_the_database_is_neither_shown_nor_cited(
        sqlite_world: World) -> None:
    """Before signing, not only in the audit bundle afterwards: the results of a record that no
    longer hashes to its digest are withheld with the reason, it cannot be attached, and an
    attached one changed later stops the statement from being prepared."""
    world = sqlite_world
    number = new_version(world)
    operator = world.client("operator")
    first, second = (_start(operator, number, seed=seed).json()["id"] for seed in (1, 2))
    for campaign in (first, second):
        assert _wait_finished(operator, campaign)["results"] is not None
    submission = submit(world, number)
    attached = operator.post(f"/api/submissions/{submission}/campaigns",
                             json={"campaign": first})
    assert attached.status_code == 201, attached.text
    supervisor = world.client("supervisor")
    signer = register_key(supervisor)

    _rewrite_record(world, second, simulations=1000)
    shown = operator.get(f"/api/campaigns/{second}").json()
    assert shown["results"] is None, "tampered results shown under the untampered digest"
    assert "does not hash to its digest" in shown["error"], shown
    offered = operator.get(f"/api/campaigns/{second}/probabilities")
    assert offered.status_code == 409 and "does not hash" in offered.json()["detail"]
    listed = {c["id"]: c for c in operator.get(f"/api/missions/{MISSION}/campaigns").json()}
    assert listed[second]["results"] is None
    refused = operator.post(f"/api/submissions/{submission}/campaigns",
                            json={"campaign": second})
    assert refused.status_code == 409 and "does not hash" in refused.json()["detail"], \
        refused.text

    _rewrite_record(world, first, simulations=1000)
    statement = supervisor.post(f"/api/submissions/{submission}/statement",
                                json={"decision": "approved", "key_id": signer.key_id})
    assert statement.status_code == 409, statement.text
    assert f"campaign {first}" in statement.json()["detail"]
