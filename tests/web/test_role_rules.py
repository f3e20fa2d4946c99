"""Who may decide comes from the log, not the users table.

A database writer runs `UPDATE users SET role = 'supervisor'` for an operator, who registers a
key and approves. The app refuses the decision naming the mismatch; with that guard switched
off (as a server that trusted the row would be), `countersign audit verify` and the offline
verifier name the decision, the person and the log entry that gave their real role. The vectors
in frontend/src/crypto/__fixtures__/roles.json are shared with the browser's copy
(src/crypto/roleRules.test.ts)."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

import pytest
from sqlalchemy import text

from countersign import cli
from countersign.approvals import dsse
from countersign.approvals.bundle import verify_bundle
from countersign.approvals.log_rules import check_log
from countersign.approvals.role_rules import check_roles
from countersign.store.accounts import create_token, create_user
from countersign.store.approvals import duties, keys
from countersign.store.tables import User

from .approval_helpers import (
    MISSION,
    Signer,
    approve,
    new_version,
    prepare,
    register_key,
    sign_prepared,
    submit,
)
from .conftest import PASSWORD, World

VECTORS = (Path(__file__).parents[2] / "frontend" / "src" / "crypto" / "__fixtures__"
           / "roles.json")
CASES: list[dict[str, Any]] = json.loads(VECTORS.read_text())["cases"]


@pytest.mark.parametrize("case", CASES, ids=[c["name"] for c in CASES])
def test_shared_role_vectors(case: dict[str, Any]) -> None:
    assert check_roles(case["events"]) == case["problems"]


def test_check_log_carries_the_role_rule() -> None:
    assert check_log(CASES[0]["events"]) == CASES[0]["problems"]


def _events(bundle: dict[str, Any]) -> list[dict[str, Any]]:
    return [json.loads(entry)["event"] for entry in bundle["entries"]]


def _key_anyway(client: Any, monkeypatch: pytest.MonkeyPatch) -> Signer:
    """A key registered with the log's role check switched off there (as before this issue)."""
    monkeypatch.setattr(keys, "decision_refusal_from_log", lambda db, user, signer: None)
    signer = register_key(client)
    monkeypatch.undo()
    return signer


def _promoted_in_the_table(world: World) -> tuple[Any, int]:
    """An operator the log created (mallory), promoted by an UPDATE of the users table."""
    with world.database.session() as db:
        mallory = create_user(db, username="mallory", role="operator", password=PASSWORD,
                              signer=world.database.log_signer)
        token = create_token(db, user=mallory, name="tests", signer=world.database.log_signer)[1]
    with world.database.engine.begin() as connection:
        connection.execute(text("UPDATE users SET role = 'supervisor' WHERE username = "
                                "'mallory'"))
    client = world.client()
    client.headers["Authorization"] = f"Bearer {token}"
    created = next(i for i, e in enumerate(_events(world.client("auditor").get(
        "/api/audit/bundle").json())) if e["kind"] == "user.created"
        and e["detail"]["user"] == "mallory")
    return client, created


def test_an_operator_promoted_in_the_table_may_not_decide(
        world: World, monkeypatch: pytest.MonkeyPatch) -> None:
    client, created = _promoted_in_the_table(world)
    named = (f"the users table says mallory is supervisor, but the log made mallory operator "
             f"in log entry {created}")
    refused_key = client.post("/api/keys", json={
        "public_key": dsse.public_text(dsse.generate_key()), "name": "x", "password": PASSWORD})
    assert refused_key.status_code == 403 and named in refused_key.json()["detail"], \
        refused_key.text
    signer = _key_anyway(client, monkeypatch)
    number = new_version(world)
    submission = submit(world, number)
    statement = client.post(f"/api/submissions/{submission}/statement",
                            json={"decision": "approved", "key_id": signer.key_id})
    assert statement.status_code == 403 and named in statement.json()["detail"], statement.text
    review = client.get(f"/api/missions/{MISSION}/versions/{number}/review")
    assert review.status_code == 200 and named in (review.json()["decide_refusal"] or ""), \
        review.text
    # A statement obtained anyway (the guard off while preparing) is refused at the decision.
    monkeypatch.setattr(duties, "decision_refusal_from_log", lambda db, user, signer: None)
    prepared = prepare(client, submission, signer)
    monkeypatch.undo()
    refused = client.post(f"/api/submissions/{submission}/decision", json={
        "envelope": sign_prepared(prepared, signer), "password": PASSWORD})
    assert refused.status_code == 403 and named in refused.json()["detail"], refused.text


def test_the_cli_and_the_offline_verifier_name_the_promotion(
        world: World, monkeypatch: pytest.MonkeyPatch, tmp_path: Path,
        capsys: pytest.CaptureFixture[str]) -> None:
    client, created = _promoted_in_the_table(world)
    signer = _key_anyway(client, monkeypatch)
    submission = submit(world, new_version(world))
    # A server that trusted the row (before this issue) accepts the decision...
    monkeypatch.setattr(duties, "decision_refusal_from_log", lambda db, user, signer: None)
    approval = approve(world, client, signer, submission)
    named = (f"log entry {approval['log_index']} (approval.approved) by mallory, but the log "
             f"made mallory operator in log entry {created}: only an enabled supervisor "
             "decides")
    # ...and every verifier names it.
    bundle = world.client("auditor").get("/api/audit/bundle").json()
    report = verify_bundle(bundle, trusted_log_key=bundle["log_key"]["public_key"])
    assert named in report.problems, report.problems
    assert named in check_log(_events(bundle))
    path = tmp_path / "bundle.json"
    path.write_text(json.dumps(bundle))
    assert cli.main(["audit", "verify", str(path), "--log-key",
                     bundle["log_key"]["public_key"], "--format", "json"]) == 1
    assert named in json.loads(capsys.readouterr().out)["problems"]


def test_a_promotion_through_the_app_lets_them_decide(world: World) -> None:
    """The control: the same person promoted by an admin (a log entry) decides, and the bundle
    verifies with no problem."""
    with world.database.session() as db:
        olga = create_user(db, username="olga", role="operator", password=PASSWORD,
                           signer=world.database.log_signer)
        olga_id, token = olga.id, create_token(db, user=olga, name="tests",
                                               signer=world.database.log_signer)[1]
    promoted = world.client("admin").patch(f"/api/users/{olga_id}", json={
        "role": "supervisor", "admin_password": PASSWORD})
    assert promoted.status_code == 200, promoted.text
    client = world.client()
    client.headers["Authorization"] = f"Bearer {token}"
    signer = register_key(client)
    approve(world, client, signer, submit(world, new_version(world)))
    bundle = world.client("auditor").get("/api/audit/bundle").json()
    report = verify_bundle(bundle, trusted_log_key=bundle["log_key"]["public_key"])
    assert report.problems == []


def test_a_demotion_whose_receipt_is_deleted_fails_closed(world: World) -> None:
    """A supervisor demoted through the app, then restored in the table with the demotion's
    receipt deleted: the guard does not read roles from an entry the signer cannot vouch for."""
    supervisor = world.client("supervisor")
    signer = register_key(supervisor)
    users = {u["username"]: u["id"] for u in world.client("admin").get("/api/users").json()}
    demoted = world.client("admin").patch(f"/api/users/{users['supervisor1']}", json={
        "role": "auditor", "admin_password": PASSWORD})
    assert demoted.status_code == 200, demoted.text
    with world.database.engine.begin() as connection:
        connection.execute(text("UPDATE users SET role = 'supervisor' WHERE username = "
                                "'supervisor1'"))
        index = connection.execute(text(
            'SELECT l."index" FROM log_entries l JOIN events e ON e.id = l.event_id '
            "WHERE e.kind = 'user.updated' ORDER BY l.\"index\" DESC LIMIT 1")).scalar_one()
        postgres = connection.dialect.name == "postgresql"
        connection.execute(text("ALTER TABLE log_receipts DISABLE TRIGGER USER" if postgres
                                else "DROP TRIGGER IF EXISTS log_receipts_no_delete"))
        connection.execute(text('DELETE FROM log_receipts WHERE "index" = :i'), {"i": index})
        if postgres:
            connection.execute(text("ALTER TABLE log_receipts ENABLE TRIGGER USER"))
    submission = submit(world, new_version(world))
    refused = supervisor.post(f"/api/submissions/{submission}/statement",
                              json={"decision": "approved", "key_id": signer.key_id})
    assert refused.status_code == 403, refused.text
    assert (f"roles cannot be read from the log: log entry {index} (user.updated) carries no "
            "receipt") in refused.json()["detail"]


def test_a_supervisor_created_by_an_admin_promoted_in_the_table_may_not_decide(
        world: World) -> None:
    """mallory is made admin by an UPDATE and creates a supervisor through the API (the route
    trusts the row): the log shows a non-admin creating the account, which gives no role."""
    with world.database.session() as db:
        mallory = create_user(db, username="mallory", role="operator", password=PASSWORD,
                              signer=world.database.log_signer)
        token = create_token(db, user=mallory, name="tests", signer=world.database.log_signer)[1]
    with world.database.engine.begin() as connection:
        connection.execute(text("UPDATE users SET role = 'admin' WHERE username = 'mallory'"))
    admin = world.client()
    admin.headers["Authorization"] = f"Bearer {token}"
    created = admin.post("/api/users", json={
        "username": "sock", "role": "supervisor", "password": PASSWORD,
        "admin_password": PASSWORD})
    assert created.status_code == 201, created.text
    with world.database.session() as db:
        sock_token = create_token(db, user=db.get_one(User, created.json()["id"]),
                                  name="tests", signer=world.database.log_signer)[1]
    sock = world.client()
    sock.headers["Authorization"] = f"Bearer {sock_token}"
    refused = sock.post("/api/keys", json={
        "public_key": dsse.public_text(dsse.generate_key()), "name": "x", "password": PASSWORD})
    assert refused.status_code == 403, refused.text
    assert "but the log gave sock no role (log entry" in refused.json()["detail"]
    bundle = world.client("auditor").get("/api/audit/bundle").json()
    report = verify_bundle(bundle, trusted_log_key=bundle["log_key"]["public_key"])
    assert any("(user.created) by mallory changes the account of sock, but the log made "
               "mallory operator" in p for p in report.problems), report.problems
