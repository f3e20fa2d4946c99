"""5 (key status), 7: a decision needs the supervisor's fresh password; a key
revoked in the log stays revoked whatever its row says; editors of any earlier revision, later
promoted, cannot decide."""

from __future__ import annotations

from typing import Any

from sqlalchemy import select

from countersign.store.accounts import create_token
from countersign.store.login_throttle import FREE_FAILURES
from countersign.store.tables import User

from .approval_helpers import (
    MISSION,
    Signer,
    bypass_triggers,
    counts,
    new_version,
    prepare,
    register_key,
    sign_prepared,
    submit,
)
from .conftest import PASSWORD, World, count_rows


def _post_decision(client: Any, submission: int, envelope: str, **extra: Any) -> Any:
    return client.post(f"/api/submissions/{submission}/decision",
                       json={"envelope": envelope, **extra})


def test_a_validly_signed_decision_without_the_password_is_refused(world: World) -> None:
    supervisor = world.client("supervisor")
    signer = register_key(supervisor)
    submission = submit(world, new_version(world))
    envelope = sign_prepared(prepare(supervisor, submission, signer), signer)
    before = counts(world.database)
    for extra, words in (({}, "needs your password"), ({"password": ""}, "needs your password"),
                         ({"password": "not it at all"}, "password is wrong")):
        response = _post_decision(supervisor, submission, envelope, **extra)
        assert response.status_code == 403, response.text
        assert response.headers["content-type"] == "application/problem+json"
        assert words in response.json()["detail"]
        assert counts(world.database) == before, "a refused decision recorded something"
    # The wrong password counted against the sign-in throttle, as a failed sign-in does.
    assert count_rows(world.database,
                      "SELECT count(*) FROM login_attempts WHERE outcome = 'failed'") == 1
    response = _post_decision(supervisor, submission, envelope, password=PASSWORD)
    assert response.status_code == 201, response.text


def test_wrong_decision_passwords_are_throttled_like_sign_in(world: World) -> None:
    supervisor = world.client("supervisor")
    signer = register_key(supervisor)
    submission = submit(world, new_version(world))
    envelope = sign_prepared(prepare(supervisor, submission, signer), signer)
    for _ in range(FREE_FAILURES):
        assert _post_decision(supervisor, submission, envelope,
                              password="guess").status_code == 403
    # Past the free failures, sign-in's back-off (store/login_throttle.py) holds for both.
    response = _post_decision(supervisor, submission, envelope, password=PASSWORD)
    assert response.status_code == 429, response.text
    assert world.client().post("/api/auth/login", json={
        "username": world.usernames["supervisor"], "password": PASSWORD}).status_code == 429


def test_a_revocation_needs_the_password(world: World) -> None:
    supervisor = world.client("supervisor")
    signer = register_key(supervisor)
    submission = submit(world, new_version(world))
    envelope = sign_prepared(prepare(supervisor, submission, signer), signer)
    approval = _post_decision(supervisor, submission, envelope, password=PASSWORD).json()["id"]
    response = supervisor.post(f"/api/approvals/{approval}/statement",
                               json={"reason": "wrong area", "key_id": signer.key_id})
    assert response.status_code == 200, response.text
    revocation = sign_prepared(response.json(), signer)
    path = f"/api/approvals/{approval}/revoke"
    refused = supervisor.post(path, json={"envelope": revocation})
    assert refused.status_code == 403 and "password" in refused.json()["detail"]
    assert supervisor.post(path, json={"envelope": revocation,
                                       "password": PASSWORD}).status_code == 201


def test_a_key_revoked_in_the_log_stays_revoked_when_its_row_is_reset(world: World) -> None:
    """Finding 5: `UPDATE signing_keys SET revoked_at = NULL` made a revoked key usable."""
    supervisor = world.client("supervisor")
    signer = register_key(supervisor)
    response = supervisor.post(f"/api/keys/{signer.key_id}/revoke",
                               json={"password": PASSWORD, "reason": "lost laptop"})
    assert response.status_code == 200, response.text
    bypass_triggers(world.database, "signing_keys",
                    "UPDATE signing_keys SET revoked_at = NULL WHERE id = :kid",
                    kid=signer.key_id)
    submission = submit(world, new_version(world))
    response = supervisor.post(f"/api/submissions/{submission}/statement",
                               json={"decision": "approved", "reason": "",
                                     "key_id": signer.key_id})
    assert response.status_code == 403, response.text
    assert "revoked (log entry" in response.json()["detail"]
    listed = {k["key_id"]: k for k in supervisor.get("/api/keys").json()}
    assert listed[signer.key_id]["status"] == "revoked"


def _token(world: World, username: str) -> str:
    with world.database.session() as db:
        user = db.scalars(select(User).where(User.username == username)).one()
        return create_token(db, user=user, name="t", signer=world.database.log_signer)[1]


def test_an_editor_of_an_earlier_revision_promoted_to_supervisor_cannot_decide(
        world: World) -> None:
    """Finding 6: only events whose digest equalled the version's counted as editing. `dual`
    edits the draft; the operator edits it again (so no event of dual's has the version's
    digest) and cuts the version; dual is promoted and tries to approve."""
    admin = world.client("admin")
    created = admin.post("/api/users", json={"username": "dual", "role": "operator",
                                             "password": PASSWORD})
    assert created.status_code == 201, created.text
    dual = world.client()
    dual.headers["Authorization"] = f"Bearer {_token(world, 'dual')}"
    mission = dual.get(f"/api/missions/{MISSION}")
    orders = mission.json()["orders"]
    orders["title"] = "Edited by dual"
    response = dual.put(f"/api/missions/{MISSION}/draft", json={"orders": orders},
                        headers={"If-Match": mission.headers["ETag"]})
    assert response.status_code == 200, response.text
    operator = world.client("operator")
    mission = operator.get(f"/api/missions/{MISSION}")
    orders = mission.json()["orders"]
    orders["title"] = "Edited again by the operator"
    response = operator.put(f"/api/missions/{MISSION}/draft", json={"orders": orders},
                            headers={"If-Match": mission.headers["ETag"]})
    assert response.status_code == 200, response.text
    submission = submit(world, new_version(world))
    assert admin.patch(f"/api/users/{created.json()['id']}",
                       json={"role": "supervisor", "admin_password": PASSWORD}).status_code == 200
    signer: Signer = register_key(dual)
    response = dual.post(f"/api/submissions/{submission}/statement",
                         json={"decision": "approved", "reason": "", "key_id": signer.key_id})
    assert response.status_code == 403, response.text
    assert "separation of duties" in response.json()["detail"]
    # An edit made after this version was cut is someone else's version's business.
    other = world.client("supervisor")
    assert prepare(other, submission, register_key(other))["statement"]
