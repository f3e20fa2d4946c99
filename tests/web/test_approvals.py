"""Submission, signed decisions, keys, the transparency log and the audit API."""

from __future__ import annotations

import json
from datetime import UTC, datetime, timedelta

import pytest
from sqlalchemy import text
from sqlalchemy.exc import DBAPIError

from countersign.approvals import dsse
from countersign.approvals.bundle import verify_bundle
from countersign.approvals.merkle import verify_consistency, verify_inclusion
from countersign.store.approvals import keys as keys_store

from .approval_helpers import (
    MISSION,
    approve,
    counts,
    new_version,
    prepare,
    register_key,
    sign_prepared,
    submit,
)
from .conftest import PASSWORD, World


def test_operator_submits_supervisor_signs_auditor_verifies(world: World) -> None:
    number = new_version(world)
    submission = submit(world, number)
    supervisor = world.client("supervisor")
    signer = register_key(supervisor)
    prepared = prepare(supervisor, submission, signer)
    statement = prepared["statement"]
    assert statement["_type"] == "https://in-toto.io/Statement/v1"
    assert statement["subject"][0]["name"] == f"{MISSION}@v{number}"
    predicate = statement["predicate"]
    assert predicate["decision"] == "approved"
    assert predicate["author"] == "operator1" and predicate["supervisor"] == "supervisor1"
    assert predicate["paths"]["count"] == 75
    assert predicate["report_digest"].startswith("sha256:")

    envelope = sign_prepared(prepared, signer)
    response = supervisor.post(f"/api/submissions/{submission}/decision",
                               json={"envelope": envelope, "password": PASSWORD})
    assert response.status_code == 201, response.text
    approval = response.json()
    assert approval["decision"] == "approved" and approval["log_index"] is not None
    assert world.client("auditor").get(f"/api/missions/{MISSION}").json()["status"] == "approved"

    auditor = world.client("auditor")
    detail = auditor.get(f"/api/approvals/{approval['id']}").json()
    assert detail["envelope"] == envelope  # stored verbatim
    assert detail["orders"]["id"] == MISSION and "Search Area A" in detail["plain"]
    assert detail["paths"]["count"] == 75 and detail["key"]["status"] == "active"
    proof, checkpoint = detail["inclusion"], detail["checkpoint"]
    entry = auditor.get("/api/log/entries", params={"start": approval["log_index"],
                                                    "limit": 1}).json()[0]
    assert json.loads(entry["entry"])["event"]["kind"] == "approval.approved"
    assert verify_inclusion(bytes.fromhex(entry["leaf_hash"]), proof["index"], proof["size"],
                            [bytes.fromhex(h) for h in proof["hashes"]],
                            bytes.fromhex(checkpoint["root"]))

    bundle = auditor.get("/api/audit/bundle").json()
    report = verify_bundle(bundle, trusted_log_key=checkpoint["public_key"])
    assert report.ok, report.problems
    assert report.approvals == 1 and report.entries == len(bundle["entries"])


def test_history_filters(world: World) -> None:
    supervisor = world.client("supervisor")
    signer = register_key(supervisor)
    first = approve(world, supervisor, signer, submit(world, new_version(world)))
    rejected = approve(world, supervisor, signer, submit(world, new_version(world)),
                       decision="rejected", reason="rendezvous too close to the lane")
    auditor = world.client("auditor")

    def ids(**params: str) -> list[int]:
        response = auditor.get("/api/approvals", params=params)
        assert response.status_code == 200, response.text
        return [item["id"] for item in response.json()["items"]]

    assert ids() == [rejected["id"], first["id"]]
    assert ids(decision="rejected") == [rejected["id"]]
    assert ids(mission=MISSION, operator="operator1", supervisor="supervisor1",
               vehicle="remus-100") == [rejected["id"], first["id"]]
    assert ids(supervisor="nobody") == [] and ids(vehicle="other") == []
    tomorrow = (datetime.now(UTC) + timedelta(days=1)).isoformat()
    yesterday = (datetime.now(UTC) - timedelta(days=1)).isoformat()
    assert ids(since=tomorrow) == [] and len(ids(since=yesterday, until=tomorrow)) == 2
    page = auditor.get("/api/approvals", params={"limit": 1}).json()
    assert page["next_cursor"] == rejected["id"]
    assert [i["id"] for i in auditor.get("/api/approvals", params={
        "limit": 1, "cursor": page["next_cursor"]}).json()["items"]] == [first["id"]]
    assert world.client("operator").get("/api/approvals").status_code == 403


def test_rejection_needs_a_reason_and_withdrawal(world: World) -> None:
    supervisor = world.client("supervisor")
    signer = register_key(supervisor)
    submission = submit(world, new_version(world))
    response = supervisor.post(f"/api/submissions/{submission}/statement",
                               json={"decision": "rejected", "key_id": signer.key_id})
    assert response.status_code == 400 and "reason" in response.json()["detail"]
    operator = world.client("operator")
    # A second submission of the same version is refused while the first is open.
    assert operator.post(f"/api/missions/{MISSION}/versions/1/submit").status_code == 409
    response = operator.post(f"/api/submissions/{submission}/withdraw")
    assert response.status_code == 200 and response.json()["state"] == "withdrawn"
    assert operator.post(f"/api/submissions/{submission}/withdraw").status_code == 409
    response = supervisor.post(f"/api/submissions/{submission}/statement",
                               json={"decision": "approved", "key_id": signer.key_id})
    assert response.status_code == 409
    kinds = [e["kind"] for e in world.client("auditor").get("/api/events").json()]
    assert "submission.created" in kinds and "submission.withdrawn" in kinds


def test_versions_with_errors_cannot_be_submitted(world: World) -> None:
    operator = world.client("operator")
    mission = operator.get(f"/api/missions/{MISSION}")
    orders = mission.json()["orders"]
    orders["goals"][0]["next"]["succeed"] = "NOWHERE"
    response = operator.put(f"/api/missions/{MISSION}/draft", json={"orders": orders},
                            headers={"If-Match": mission.headers["ETag"]})
    assert response.status_code == 200, response.text
    number = new_version(world)
    response = operator.post(f"/api/missions/{MISSION}/versions/{number}/submit")
    assert response.status_code == 409
    assert "G3" in response.json()["detail"]
    assert response.headers["content-type"] == "application/problem+json"


def test_key_registration_needs_the_password_and_keys_rotate(world: World) -> None:
    supervisor = world.client("supervisor")
    key = dsse.generate_key()
    before = counts(world.database)
    response = supervisor.post("/api/keys", json={"public_key": dsse.public_text(key),
                                                  "password": "not the password"})
    assert response.status_code == 403
    response = supervisor.post("/api/keys", json={"public_key": "AAAA", "password": PASSWORD})
    assert response.status_code == 400
    assert world.client("operator").post("/api/keys", json={
        "public_key": dsse.public_text(key), "password": PASSWORD}).status_code == 403
    assert counts(world.database) == before

    old = register_key(supervisor, "old")
    first = approve(world, supervisor, old, submit(world, new_version(world)))
    new = register_key(supervisor, "new")
    response = supervisor.post(f"/api/keys/{old.key_id}/revoke",
                               json={"password": PASSWORD, "reason": "rotated"})
    assert response.status_code == 200 and response.json()["status"] == "revoked"
    # The revoked key signs nothing new; the new one does; the old approval still verifies.
    submission = submit(world, new_version(world))
    response = supervisor.post(f"/api/submissions/{submission}/statement",
                               json={"decision": "approved", "key_id": old.key_id})
    assert response.status_code == 403 and "revoked" in response.json()["detail"]
    approve(world, supervisor, new, submission)
    bundle = world.client("auditor").get("/api/audit/bundle").json()
    report = verify_bundle(bundle)
    assert report.ok, report.problems
    assert report.approvals == 2 and first["key_id"] == old.key_id
    statuses = {k["key_id"]: k["status"] for k in world.client("auditor").get("/api/keys").json()}
    assert statuses == {old.key_id: "revoked", new.key_id: "active"}


def test_a_supervisor_has_a_bounded_number_of_unrevoked_keys(
        world: World, monkeypatch: pytest.MonkeyPatch) -> None:
    monkeypatch.setattr(keys_store, "MAX_LIVE_KEYS", 2)
    supervisor = world.client("supervisor")
    first, _ = register_key(supervisor, "one"), register_key(supervisor, "two")
    third = dsse.generate_key()
    refused = supervisor.post("/api/keys", json={"public_key": dsse.public_text(third),
                                                 "password": PASSWORD, "name": "three"})
    assert refused.status_code == 409 and "at most 2" in refused.json()["detail"], refused.text
    assert len(world.client("auditor").get("/api/keys").json()) == 2
    # Revoking one makes room again.
    assert supervisor.post(f"/api/keys/{first.key_id}/revoke",
                           json={"password": PASSWORD, "reason": "rotated"}).status_code == 200
    assert supervisor.post("/api/keys", json={"public_key": dsse.public_text(third),
                                              "password": PASSWORD,
                                              "name": "three"}).status_code == 201


def test_revoking_an_approval_is_signed(world: World) -> None:
    supervisor = world.client("supervisor")
    signer = register_key(supervisor)
    approval = approve(world, supervisor, signer, submit(world, new_version(world)))
    response = supervisor.post(f"/api/approvals/{approval['id']}/statement",
                               json={"reason": "vehicle profile changed", "key_id": signer.key_id})
    assert response.status_code == 200, response.text
    prepared = response.json()
    assert prepared["statement"]["predicate"]["revokes"].startswith("sha256:")
    response = supervisor.post(f"/api/approvals/{approval['id']}/revoke",
                               json={"envelope": sign_prepared(prepared, signer),
                                     "password": PASSWORD})
    assert response.status_code == 201, response.text
    assert response.json()["decision"] == "revoked"
    assert response.json()["revokes"] == approval["id"]
    assert world.client("auditor").get(f"/api/missions/{MISSION}").json()["status"] == "revoked"
    again = supervisor.post(f"/api/approvals/{approval['id']}/statement",
                            json={"reason": "again", "key_id": signer.key_id})
    assert again.status_code == 409
    report = verify_bundle(world.client("auditor").get("/api/audit/bundle").json())
    assert report.ok and report.approvals == 2, report.problems


def test_log_proofs_and_checkpoints(world: World) -> None:
    auditor = world.client("auditor")
    first = auditor.get("/api/log/checkpoint").json()
    supervisor = world.client("supervisor")
    approve(world, supervisor, register_key(supervisor), submit(world, new_version(world)))
    second = auditor.get("/api/log/checkpoint").json()
    assert second["size"] > first["size"]
    key = dsse.public_key(second["public_key"])
    from countersign.approvals.log import verify_checkpoint_head

    head = verify_checkpoint_head(second, key)
    assert (head.size, head.root) == (second["size"], bytes.fromhex(second["root"]))
    proof = auditor.get("/api/log/consistency", params={"first": first["size"],
                                                        "second": second["size"]}).json()
    assert verify_consistency(first["size"], second["size"],
                              [bytes.fromhex(h) for h in proof["hashes"]],
                              bytes.fromhex(first["root"]), bytes.fromhex(second["root"]))
    assert auditor.get("/api/log/inclusion", params={"index": 10**6}).status_code == 404
    assert auditor.get("/api/log/checkpoint").json()["size"] == second["size"]  # no new one


@pytest.mark.parametrize("table", ["events", "log_entries", "approvals", "checkpoints",
                                   "mission_versions"])
def test_database_refuses_updates_and_deletes(world: World, table: str) -> None:
    supervisor = world.client("supervisor")
    approve(world, supervisor, register_key(supervisor), submit(world, new_version(world)))
    assert supervisor.get("/api/log/checkpoint").status_code == 200  # signs one
    column = {"events": "kind", "log_entries": "entry", "approvals": "reason",
              "checkpoints": "note", "mission_versions": "digest"}[table]
    for sql in (f"UPDATE {table} SET {column} = 'x'", f"DELETE FROM {table}"):
        with pytest.raises(DBAPIError, match="append-only"), \
                world.database.engine.begin() as connection:
            connection.execute(text(sql))
