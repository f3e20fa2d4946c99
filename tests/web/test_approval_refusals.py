"""Every refused signature is a clear 4xx problem document and records nothing."""

from __future__ import annotations

import base64
import json
from collections.abc import Callable
from typing import Any

import pytest
from sqlalchemy import text

from countersign.approvals import dsse
from countersign.approvals.statement import statement_bytes

from .approval_helpers import (
    MISSION,
    Signer,
    approve,
    counts,
    envelope_for,
    new_version,
    prepare,
    register_key,
    sign_prepared,
    submit,
)
from .conftest import PASSWORD, World


def _refused(world: World, client: Any, path: str, body: dict[str, Any], status: int,
             words: str) -> None:
    before = counts(world.database)
    if "envelope" in body:  # every signed request carries the fresh password
        body = {"password": PASSWORD, **body}
    response = client.post(path, json=body)
    assert response.status_code == status, response.text
    assert response.headers["content-type"] == "application/problem+json"
    assert words in response.json()["detail"], response.json()["detail"]
    assert counts(world.database) == before, "a refused request recorded something"


def _resigned(prepared: dict[str, Any], signer: Signer,
              change: Callable[[dict[str, Any]], None]) -> str:
    statement = json.loads(json.dumps(prepared["statement"]))
    change(statement)
    return envelope_for(statement_bytes(statement), signer)


@pytest.fixture
def setup(world: World) -> tuple[World, Any, Signer, int]:
    supervisor = world.client("supervisor")
    signer = register_key(supervisor)
    return world, supervisor, signer, submit(world, new_version(world))


def test_unknown_key(setup: tuple[World, Any, Signer, int]) -> None:
    world, supervisor, signer, submission = setup
    prepared = prepare(supervisor, submission, signer)
    stranger = dsse.generate_key()
    envelope = json.dumps(dsse.sign_envelope(dsse.unb64(prepared["payload"], "p"), stranger))
    _refused(world, supervisor, f"/api/submissions/{submission}/decision",
             {"envelope": envelope}, 403, "is not registered")
    _refused(world, supervisor, f"/api/submissions/{submission}/statement",
             {"decision": "approved", "key_id": "f" * 64}, 403, "is not registered")


def test_revoked_key(setup: tuple[World, Any, Signer, int]) -> None:
    world, supervisor, signer, submission = setup
    prepared = prepare(supervisor, submission, signer)
    response = supervisor.post(f"/api/keys/{signer.key_id}/revoke",
                               json={"password": PASSWORD, "reason": "laptop lost"})
    assert response.status_code == 200
    _refused(world, supervisor, f"/api/submissions/{submission}/decision",
             {"envelope": sign_prepared(prepared, signer)}, 403, "was revoked")


@pytest.mark.parametrize("role", ["operator", "auditor", "admin"])
def test_wrong_role(setup: tuple[World, Any, Signer, int], role: str) -> None:
    world, supervisor, signer, submission = setup
    envelope = sign_prepared(prepare(supervisor, submission, signer), signer)
    _refused(world, world.client(role), f"/api/submissions/{submission}/decision",
             {"envelope": envelope}, 403, "role may not")


def test_someone_elses_key(setup: tuple[World, Any, Signer, int]) -> None:
    world, _, signer, submission = setup
    admin = world.client("admin")
    assert admin.post("/api/users", json={"username": "supervisor2", "role": "supervisor",
                                          "password": PASSWORD,
                                          "admin_password": PASSWORD}).status_code == 201
    other, _ = world.browser("supervisor")  # any signed-in client works for the token below
    token = _token_for(world, "supervisor2")
    other.headers["Authorization"] = f"Bearer {token}"
    _refused(world, other, f"/api/submissions/{submission}/statement",
             {"decision": "approved", "key_id": signer.key_id}, 403, "belongs to someone else")


def _token_for(world: World, username: str) -> str:
    from sqlalchemy import select

    from countersign.store.accounts import create_token
    from countersign.store.tables import User

    with world.database.session() as db:
        user = db.scalars(select(User).where(User.username == username)).one()
        return create_token(db, user=user, name="t", signer=world.database.log_signer)[1]


def test_self_approval(world: World) -> None:
    """A supervisor who authored (or edited) a version cannot decide on it."""
    admin = world.client("admin")
    response = admin.post("/api/users", json={"username": "dual", "role": "operator",
                                              "password": PASSWORD})
    dual_id = response.json()["id"]
    dual = world.client()
    dual.headers["Authorization"] = f"Bearer {_token_for(world, 'dual')}"
    number = dual.post(f"/api/missions/{MISSION}/versions").json()["number"]
    submission = submit(world, number)
    assert admin.patch(f"/api/users/{dual_id}", json={
        "role": "supervisor", "admin_password": PASSWORD}).status_code == 200
    signer = register_key(dual)
    _refused(world, dual, f"/api/submissions/{submission}/statement",
             {"decision": "approved", "key_id": signer.key_id}, 403, "separation of duties")
    # Signing the statement another supervisor was handed does not help either.
    honest = world.client("supervisor")
    prepared = prepare(honest, submission, register_key(honest))
    statement = prepared["statement"]
    statement["predicate"].update(supervisor="dual", key_id=signer.key_id)
    _refused(world, dual, f"/api/submissions/{submission}/decision",
             {"envelope": envelope_for(statement_bytes(statement), signer)}, 403,
             "separation of duties")


@pytest.mark.parametrize("field,value,words", [
    ("report_digest", "sha256:" + "0" * 64, "report_digest"),
    ("version", 7, "version"),
    ("author", "someone", "author"),
    ("supervisor", "operator1", "supervisor"),
])
def test_stale_or_altered_statement(setup: tuple[World, Any, Signer, int], field: str,
                                    value: Any, words: str) -> None:
    world, supervisor, signer, submission = setup
    prepared = prepare(supervisor, submission, signer)
    envelope = _resigned(prepared, signer, lambda s: s["predicate"].__setitem__(field, value))
    _refused(world, supervisor, f"/api/submissions/{submission}/decision",
             {"envelope": envelope}, 409, words)


def test_stale_subject_digest(setup: tuple[World, Any, Signer, int]) -> None:
    world, supervisor, signer, submission = setup
    prepared = prepare(supervisor, submission, signer)
    envelope = _resigned(prepared, signer,
                         lambda s: s["subject"][0]["digest"].__setitem__("sha256", "ab" * 32))
    _refused(world, supervisor, f"/api/submissions/{submission}/decision",
             {"envelope": envelope}, 409, "the statement signs sha256:abab")


def test_outdated_report(setup: tuple[World, Any, Signer, int]) -> None:
    """The report changed (e.g. a new checker version) after the statement was prepared."""
    world, supervisor, signer, submission = setup
    prepared = prepare(supervisor, submission, signer)
    with world.database.engine.begin() as connection:
        rows = connection.execute(text("SELECT digest, checker_version, report FROM "
                                       "validation_reports")).all()
        for digest, checker, report in rows:
            data = json.loads(report) if isinstance(report, str) else report
            data["findings"].append({"code": "VACUOUS", "severity": "warning",
                                     "subjects": ["C1"], "message": "new check"})
            connection.execute(text("UPDATE validation_reports SET report = :r WHERE digest = "
                                    ":d AND checker_version = :c"),
                               {"r": json.dumps(data), "d": digest, "c": checker})
    _refused(world, supervisor, f"/api/submissions/{submission}/decision",
             {"envelope": sign_prepared(prepared, signer)}, 409, "report_digest")


def test_statement_for_another_submission(setup: tuple[World, Any, Signer, int]) -> None:
    world, supervisor, signer, submission = setup
    other = submit(world, new_version(world))
    envelope = sign_prepared(prepare(supervisor, submission, signer), signer)
    _refused(world, supervisor, f"/api/submissions/{other}/decision", {"envelope": envelope},
             409, f"about submission {submission}")


def test_replayed_envelope(setup: tuple[World, Any, Signer, int]) -> None:
    world, supervisor, signer, submission = setup
    envelope = sign_prepared(prepare(supervisor, submission, signer), signer)
    response = supervisor.post(f"/api/submissions/{submission}/decision",
                               json={"envelope": envelope, "password": PASSWORD})
    assert response.status_code == 201
    _refused(world, supervisor, f"/api/submissions/{submission}/decision",
             {"envelope": envelope}, 409, "replay refused")


def test_signature_over_different_bytes(setup: tuple[World, Any, Signer, int]) -> None:
    world, supervisor, signer, submission = setup
    prepared = prepare(supervisor, submission, signer)
    payload = dsse.unb64(prepared["payload"], "p")
    forged = signer.key.sign(dsse.pae(dsse.PAYLOAD_TYPE, payload.replace(b"approved",
                                                                         b"rejected")))
    envelope = json.dumps({"payloadType": dsse.PAYLOAD_TYPE, "payload": prepared["payload"],
                           "signatures": [{"keyid": signer.key_id, "sig": dsse.b64(forged)}]})
    _refused(world, supervisor, f"/api/submissions/{submission}/decision",
             {"envelope": envelope}, 400, "does not verify")
    # Signing the raw payload instead of the PAE is refused too.
    raw = json.dumps({"payloadType": dsse.PAYLOAD_TYPE, "payload": prepared["payload"],
                      "signatures": [{"keyid": signer.key_id,
                                      "sig": dsse.b64(signer.key.sign(payload))}]})
    _refused(world, supervisor, f"/api/submissions/{submission}/decision",
             {"envelope": raw}, 400, "does not verify")


@pytest.mark.parametrize("envelope,words", [
    ("not json", "not JSON"),
    ("{}", "payloadType, payload and signatures"),
    (json.dumps({"payloadType": "text/plain", "payload": "", "signatures": []}),
     "exactly one signature"),
])
def test_malformed_envelopes(setup: tuple[World, Any, Signer, int], envelope: str,
                             words: str) -> None:
    world, supervisor, _, submission = setup
    _refused(world, supervisor, f"/api/submissions/{submission}/decision",
             {"envelope": envelope}, 400, words)


def test_non_canonical_payload(setup: tuple[World, Any, Signer, int]) -> None:
    world, supervisor, signer, submission = setup
    prepared = prepare(supervisor, submission, signer)
    payload = json.dumps(prepared["statement"], indent=1).encode()
    _refused(world, supervisor, f"/api/submissions/{submission}/decision",
             {"envelope": envelope_for(payload, signer)}, 400, "not canonical")
    assert base64.b64decode(prepared["payload"]) != payload


def test_decided_submission_takes_no_second_decision(setup: tuple[World, Any, Signer, int]
                                                     ) -> None:
    world, supervisor, signer, submission = setup
    prepared_again = prepare(supervisor, submission, signer, "rejected", "late")
    approve(world, supervisor, signer, submission)
    _refused(world, supervisor, f"/api/submissions/{submission}/decision",
             {"envelope": sign_prepared(prepared_again, signer)}, 409, "is approved")
