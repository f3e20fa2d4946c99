"""the surviving mutants: the offline verifier (and the
`audit verify` command) checks log-wide rules, whatever the tables say; the server refuses
stale statements and keys revoked before they signed."""

from __future__ import annotations

import json
from datetime import timedelta
from typing import Any

import pytest
from sqlalchemy import text

from countersign.approvals.bundle import verify_bundle
from countersign.approvals.log_rules import check_log
from countersign.approvals.statement import statement_bytes
from countersign.store.approvals import decisions, keys
from countersign.store.tables import utcnow

from .approval_helpers import (
    approve,
    bypass_triggers,
    envelope_for,
    new_version,
    prepare,
    register_key,
    sign_prepared,
    submit,
)
from .conftest import PASSWORD, World


def _problems(world: World) -> list[str]:
    bundle = world.client("auditor").get("/api/audit/bundle").json()
    report = verify_bundle(bundle, trusted_log_key=bundle["log_key"]["public_key"])
    return report.problems


def test_two_decisions_on_one_submission_are_named(world: World,
                                                   monkeypatch: pytest.MonkeyPatch) -> None:
    """Finding 4's end state: with the guards gone (no index, no open-state check) the log
    holds an approval and a rejection of one submission; the verifier names both entries."""
    with world.database.engine.begin() as connection:
        connection.execute(text("DROP INDEX uq_approvals_decision_submission"))
    supervisor = world.client("supervisor")
    signer = register_key(supervisor)
    submission = submit(world, new_version(world))
    approved = sign_prepared(prepare(supervisor, submission, signer, "approved"), signer)
    rejected = sign_prepared(prepare(supervisor, submission, signer, "rejected", "no"), signer)
    monkeypatch.setattr(decisions, "_check_open", lambda ctx: None)
    first = supervisor.post(f"/api/submissions/{submission}/decision",
                            json={"envelope": approved, "password": PASSWORD})
    assert first.status_code == 201, first.text
    monkeypatch.setattr(decisions, "_check_fresh", lambda *a, **k: None)
    second = supervisor.post(f"/api/submissions/{submission}/decision",
                             json={"envelope": rejected, "password": PASSWORD})
    assert second.status_code == 201, second.text
    problems = _problems(world)
    assert any(f"both decide submission {submission}: one decision per submission" in p
               for p in problems), problems


def test_a_deleted_revocation_row_is_named(world: World) -> None:
    """Finding 5: deleting a revocation's approvals row made the approval look valid."""
    supervisor = world.client("supervisor")
    signer = register_key(supervisor)
    approval = approve(world, supervisor, signer, submit(world, new_version(world)))
    prepared = supervisor.post(f"/api/approvals/{approval['id']}/statement",
                               json={"reason": "closed area", "key_id": signer.key_id}).json()
    revoked = supervisor.post(f"/api/approvals/{approval['id']}/revoke", json={
        "envelope": sign_prepared(prepared, signer), "password": PASSWORD})
    assert revoked.status_code == 201, revoked.text
    assert _problems(world) == []
    with world.database.engine.begin() as connection:
        if connection.dialect.name == "postgresql":
            connection.execute(text("ALTER TABLE approvals DISABLE TRIGGER USER"))
        else:
            connection.execute(text("DROP TRIGGER IF EXISTS approvals_no_delete"))
        connection.execute(text("DELETE FROM approvals WHERE id = :i"),
                           {"i": revoked.json()["id"]})
        if connection.dialect.name == "postgresql":
            connection.execute(text("ALTER TABLE approvals ENABLE TRIGGER USER"))
    index = revoked.json()["log_index"]
    problems = _problems(world)
    assert any(f"log entry {index} records a signed decision (approval.revoked) but the "
               "bundle holds no envelope" in p for p in problems), problems


def test_a_key_revoked_before_it_signed_is_refused_by_the_verifier(
        world: World, monkeypatch: pytest.MonkeyPatch) -> None:
    """the survivor: the bundle's key-history check. The key's row is reset so that the
    server accepts the decision (as before this issue) and the verifier must catch it."""
    supervisor = world.client("supervisor")
    signer = register_key(supervisor)
    submission = submit(world, new_version(world))
    envelope = sign_prepared(prepare(supervisor, submission, signer), signer)
    assert supervisor.post(f"/api/keys/{signer.key_id}/revoke", json={
        "password": PASSWORD, "reason": "lost"}).status_code == 200
    bypass_triggers(world.database, "signing_keys",
                    "UPDATE signing_keys SET revoked_at = NULL WHERE id = :k", k=signer.key_id)
    # The server reads key status from the log: refused.
    refused = supervisor.post(f"/api/submissions/{submission}/decision",
                              json={"envelope": envelope, "password": PASSWORD})
    assert refused.status_code == 403 and "revoked (log entry" in refused.json()["detail"]
    # A server that trusted the row (as before) accepts it; the offline verifier must not.
    monkeypatch.setattr(keys, "logged_key_revocation", lambda db, key_id: None)
    accepted = supervisor.post(f"/api/submissions/{submission}/decision",
                               json={"envelope": envelope, "password": PASSWORD})
    assert accepted.status_code == 201, accepted.text
    index = accepted.json()["log_index"]
    problems = _problems(world)
    assert any(f"approval {accepted.json()['id']}: key {signer.key_id} was revoked" in p
               for p in problems), problems
    assert any(f"log entry {index} is signed with key {signer.key_id}, revoked" in p
               for p in problems), problems


def test_check_log_names_a_revoked_keys_later_signature_and_duplicate_submissions() -> None:
    def ev(kind: str, **detail: Any) -> dict[str, Any]:
        return {"kind": kind, "mission": "m", "detail": detail}

    events = [ev("key.registered", key_id="k"),
              ev("submission.created", submission=1, version=1),
              ev("submission.created", submission=2, version=1),
              ev("key.revoked", key_id="k"),
              ev("approval.approved", submission=1, key_id="k")]
    problems = check_log(events, enveloped=[4])
    assert any("submits m version 1 while submission 1 is still active" in p for p in problems)
    assert any("log entry 4 is signed with key k, revoked in log entry 3" in p
               for p in problems), problems


@pytest.mark.parametrize("shift,words", [(timedelta(hours=-2), "too long ago"),
                                         (timedelta(minutes=30), "in the future")])
def test_statements_outside_the_freshness_window_are_refused(
        world: World, shift: timedelta, words: str) -> None:
    """the survivor: removing STATEMENT_MAX_AGE / CLOCK_SKEW went unnoticed."""
    supervisor = world.client("supervisor")
    signer = register_key(supervisor)
    submission = submit(world, new_version(world))
    statement = json.loads(json.dumps(prepare(supervisor, submission, signer)["statement"]))
    statement["predicate"]["time"] = (utcnow() + shift).isoformat().replace("+00:00", "Z")
    response = supervisor.post(f"/api/submissions/{submission}/decision", json={
        "envelope": envelope_for(statement_bytes(statement), signer), "password": PASSWORD})
    assert response.status_code == 409, response.text
    assert words in response.json()["detail"]


def test_rows_that_disagree_with_the_log_are_reported_not_shown_as_fact(world: World) -> None:
    """Finding 5: `UPDATE submissions SET state='approved'` on a rejected one, or editing
    `approvals.decision`/reason, was shown as fact."""
    supervisor = world.client("supervisor")
    signer = register_key(supervisor)
    submission = submit(world, new_version(world))
    rejection = approve(world, supervisor, signer, submission, "rejected", "too shallow")
    auditor = world.client("auditor")
    assert auditor.get(f"/api/submissions/{submission}").json()["integrity"] == []
    assert auditor.get(f"/api/approvals/{rejection['id']}").json()["integrity"] == []
    with world.database.engine.begin() as connection:
        connection.execute(text("UPDATE submissions SET state = 'approved' WHERE id = :i"),
                           {"i": submission})
    bypass_triggers(world.database, "approvals",
                    "UPDATE approvals SET decision = 'approved', reason = 'fine' WHERE id = :i",
                    i=rejection["id"])
    shown = auditor.get(f"/api/submissions/{submission}").json()
    assert shown["integrity"] == [f"submission {submission}: the table says approved, the log "
                                  "says rejected"]
    listed = auditor.get("/api/approvals").json()["items"][0]
    assert any("the table says decision = 'approved', its log entry says 'rejected'" in p
               for p in listed["integrity"]), listed
    assert any("reason = 'fine'" in p for p in listed["integrity"])


def test_events_edited_behind_the_app_are_reported_by_the_activity_log(world: World) -> None:
    """Finding 5: editing `events` (actor, reason) was shown as fact on the activity page."""
    supervisor = world.client("supervisor")
    signer = register_key(supervisor)
    submission = submit(world, new_version(world))
    approve(world, supervisor, signer, submission, "rejected", "too shallow")
    auditor = world.client("auditor")
    events = auditor.get("/api/events", params={"limit": 1000}).json()
    assert events and all(e["integrity"] == [] for e in events)
    rejected = next(e for e in events if e["kind"] == "approval.rejected")
    with world.database.engine.connect() as connection:
        admin_id = connection.execute(text(
            "SELECT id FROM users WHERE role = 'admin' ORDER BY id LIMIT 1")).scalar_one()
    bypass_triggers(world.database, "events",
                    "UPDATE events SET actor_id = :a, detail = :d WHERE id = :i",
                    a=admin_id, d=json.dumps({**rejected["detail"], "reason": "fine"}),
                    i=rejected["id"])
    shown = {e["id"]: e for e in auditor.get("/api/events", params={"limit": 1000}).json()}
    assert shown[rejected["id"]]["integrity"] == [
        f"event {rejected['id']}: the table's actor, detail disagree with log entry "
        f"{_log_index(world, rejected['id'])}"]
    assert all(e["integrity"] == [] for i, e in shown.items() if i != rejected["id"])


def _log_index(world: World, event_id: int) -> int:
    with world.database.engine.connect() as connection:
        return int(connection.execute(text('SELECT "index" FROM log_entries WHERE event_id = :i'),
                                      {"i": event_id}).scalar_one())
