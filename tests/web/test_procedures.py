"""The procedure library over the API: roles, CSRF, bad input, signed decisions,
the review's "uses only approved procedures", and rows a database writer changed."""

from __future__ import annotations

import copy
import json
from importlib import resources
from pathlib import Path
from typing import Any

import pytest
from fastapi.testclient import TestClient
from sqlalchemy import text

from countersign.approvals import dsse
from countersign.approvals.statement import statement_bytes
from countersign.orders.procedure import procedure_from_data
from countersign.store import procedures as procedures_store
from countersign.web.deps import CSRF_HEADER

from .approval_helpers import Signer, register_key, sign_prepared
from .conftest import PASSWORD, World
from .write_lock import probe_write_lock

EXAMPLES = resources.files("countersign.orders.examples") / "procedures"
NAME = "cell-search"
BASE = f"/api/procedures/{NAME}/versions/1"


def _document() -> dict[str, Any]:
    data: dict[str, Any] = json.loads((EXAMPLES / "library" / "cell-search-1.json").read_text())
    return data


def _orders() -> dict[str, Any]:
    data: dict[str, Any] = json.loads(
        (EXAMPLES / "search-and-sample-procedure.json").read_text())
    return data


def _save(world: World, document: dict[str, Any] | None = None) -> dict[str, Any]:
    response = world.client("operator").post("/api/procedures", json=document or _document())
    assert response.status_code == 201, response.text
    data: dict[str, Any] = response.json()
    return data


def _decide(world: World, client: TestClient, signer: Signer, decision: str = "approved",
            reason: str = "", base: str = BASE) -> Any:
    prepared = client.post(f"{base}/statement", json={"decision": decision, "reason": reason,
                                                      "key_id": signer.key_id})
    assert prepared.status_code == 200, prepared.text
    return client.post(f"{base}/decision", json={
        "envelope": sign_prepared(prepared.json(), signer), "password": PASSWORD})


def _uses(world: World, mission: str, number: int = 1) -> dict[str, Any]:
    response = world.client("auditor").get(f"/api/missions/{mission}/versions/{number}/procedures")
    assert response.status_code == 200, response.text
    data: dict[str, Any] = response.json()
    return data


def _mission_version(world: World, orders: dict[str, Any]) -> dict[str, Any]:
    operator = world.client("operator")
    created = operator.post("/api/missions", json=orders)
    assert created.status_code == 201, created.text
    version = operator.post(f"/api/missions/{orders['id']}/versions")
    assert version.status_code == 201, version.text
    data: dict[str, Any] = created.json()
    return data


def test_operator_saves_a_version_everyone_reads_it(world: World) -> None:
    saved = _save(world)
    expected = procedure_from_data(_document())
    assert saved["digest"] == expected.digest and saved["reference"] == expected.reference()
    assert saved["integrity"] == [] and saved["approved_by"] is None
    assert saved["log_index"] is not None and saved["author"] == world.usernames["operator"]
    for role in ("operator", "supervisor", "auditor", "admin"):
        got = world.client(role).get(BASE)
        assert got.status_code == 200 and got.json()["document"] == expected.to_json()
        listed = world.client(role).get("/api/procedures", params={"name": NAME}).json()
        assert [(p["name"], p["version"]) for p in listed] == [(NAME, 1)]
    assert world.client().get(BASE).status_code == 401


def test_only_operators_save_and_only_supervisors_decide(world: World) -> None:
    for role in ("supervisor", "auditor", "admin"):
        refused = world.client(role).post("/api/procedures", json=_document())
        assert refused.status_code == 403, (role, refused.text)
    _save(world)
    for role in ("operator", "auditor", "admin"):
        refused = world.client(role).post(f"{BASE}/statement", json={
            "decision": "approved", "reason": "", "key_id": "0" * 64})
        assert refused.status_code == 403, (role, refused.text)


def test_cookie_sessions_need_the_csrf_header(world: World) -> None:
    client, csrf = world.browser("operator")
    refused = client.post("/api/procedures", json=_document())
    assert refused.status_code == 403 and CSRF_HEADER in refused.json()["detail"]
    assert world.client("auditor").get(BASE).status_code == 404  # nothing was saved
    saved = client.post("/api/procedures", json=_document(), headers={CSRF_HEADER: csrf})
    assert saved.status_code == 201, saved.text


def test_versions_never_change_and_come_in_order(world: World) -> None:
    _save(world)
    changed = _document()
    changed["refines"]["goals"][0]["title"] = "Something else"
    again = world.client("operator").post("/api/procedures", json=changed)
    assert again.status_code == 409 and "next version" in again.json()["detail"]
    skipped = world.client("operator").post("/api/procedures", json=changed | {"version": 3})
    assert skipped.status_code == 409 and "is 2, not 3" in skipped.json()["detail"]
    second = _save(world, changed | {"version": 2})
    assert second["digest"] != procedure_from_data(_document()).digest


def test_bad_input_is_a_4xx_that_says_what_and_where(world: World) -> None:
    operator = world.client("operator")
    cases: list[tuple[Any, int, str]] = [
        (_document() | {"format": "countersign.orders/1"}, 400, "countersign.procedure/1"),
        (_document() | {"version": "1"}, 400, "$.version"),
        (_document() | {"name": "<script>alert(1)</script>"}, 400, "$.name"),
        ([1, 2], 422, "valid dictionary"),
    ]
    looping = _document()
    del looping["refines"]["within"], looping["refines"]["on_timeout"]
    cases.append((looping, 422, "REFINE"))
    unknown = _document()
    unknown["refines"]["goals"][0]["refines"] = {"procedure": "nowhere", "version": 1}
    cases.append((unknown, 422, "PROCEDURE"))
    for body, status, says in cases:
        response = operator.post("/api/procedures", json=body)
        assert response.status_code in (status, 422), (body, response.text)
        assert says in response.text, response.text
        assert "Traceback" not in response.text
    assert operator.get("/api/procedures/bad name/versions/1").status_code == 422
    assert operator.get(f"/api/procedures/{NAME}/versions/0").status_code == 422
    assert operator.get(f"/api/procedures/{NAME}/versions/1").status_code == 404
    assert operator.get("/api/procedures", params={"name": "x" * 101}).status_code == 422


def test_orders_naming_a_procedure_get_its_body_and_the_review_says_approved(
        world: World) -> None:
    _save(world)
    draft = _mission_version(world, _orders())
    refines = next(g for g in draft["orders"]["goals"] if g["id"] == "G1")["refines"]
    assert refines["procedure"] == NAME and refines["goals"], "the body is copied in"
    report = world.client("operator").get("/api/missions/search-and-sample-procedure/report")
    assert report.status_code == 200 and report.json()["ok"], report.text
    uses = _uses(world, "search-and-sample-procedure")
    assert uses["all_approved"] is False
    assert uses["procedures"] == [{"name": NAME, "version": 1, "in_library": True,
                                   "digest": procedure_from_data(_document()).digest,
                                   "approved_by": None}]
    supervisor = world.client("supervisor")
    signer = register_key(supervisor)
    decided = _decide(world, supervisor, signer)
    assert decided.status_code == 201, decided.text
    assert decided.json()["integrity"] == [] and decided.json()["decision"] == "approved"
    uses = _uses(world, "search-and-sample-procedure")
    assert uses["all_approved"] is True
    assert uses["procedures"][0]["approved_by"] == world.usernames["supervisor"]
    assert world.client("auditor").get(BASE).json()["approved_by"] == \
        world.usernames["supervisor"]
    # One decision per version, and a signed statement is used once.
    again = supervisor.post(f"{BASE}/statement", json={
        "decision": "approved", "reason": "", "key_id": signer.key_id})
    assert again.status_code == 409 and "decision already" in again.json()["detail"]


def test_a_reference_the_library_does_not_hold_is_a_procedure_error(world: World) -> None:
    _mission_version(world, _orders())
    report = world.client("operator").get("/api/missions/search-and-sample-procedure/report")
    codes = [f["code"] for f in report.json()["findings"] if f["severity"] == "error"]
    assert "PROCEDURE" in codes
    assert _uses(world, "search-and-sample-procedure")["procedures"][0]["in_library"] is False


def test_a_decision_needs_the_password_and_the_procedure_statement_type(world: World) -> None:
    _save(world)
    supervisor = world.client("supervisor")
    signer = register_key(supervisor)
    prepared = supervisor.post(f"{BASE}/statement", json={
        "decision": "approved", "reason": "", "key_id": signer.key_id}).json()
    envelope = sign_prepared(prepared, signer)
    no_password = supervisor.post(f"{BASE}/decision", json={"envelope": envelope})
    assert no_password.status_code == 403 and "password" in no_password.json()["detail"]
    # A mission approval's statement type signed over the same subject is refused.
    statement = copy.deepcopy(prepared["statement"])
    statement["predicateType"] = "https://countersign.invalid/approval/v1"
    forged = json.dumps(dsse.sign_envelope(statement_bytes(statement), signer.key))
    refused = supervisor.post(f"{BASE}/decision", json={"envelope": forged,
                                                       "password": PASSWORD})
    assert refused.status_code == 400 and "procedure decision" in refused.json()["detail"]
    # A statement edited after it was prepared (another digest) is refused.
    statement = copy.deepcopy(prepared["statement"])
    statement["subject"][0]["digest"]["sha256"] = "0" * 64
    edited = json.dumps(dsse.sign_envelope(statement_bytes(statement), signer.key))
    refused = supervisor.post(f"{BASE}/decision", json={"envelope": edited,
                                                       "password": PASSWORD})
    assert refused.status_code == 409 and "signs sha256:000" in refused.json()["detail"]
    assert world.client("auditor").get(BASE).json()["decisions"] == []


def test_a_rejection_needs_a_reason_and_is_not_an_approval(world: World) -> None:
    _save(world)
    supervisor = world.client("supervisor")
    signer = register_key(supervisor)
    refused = supervisor.post(f"{BASE}/statement", json={
        "decision": "rejected", "reason": " ", "key_id": signer.key_id})
    assert refused.status_code == 422 and "reason" in refused.json()["detail"]
    rejected = _decide(world, supervisor, signer, "rejected", "<b>too long a loop</b>")
    assert rejected.status_code == 201, rejected.text
    got = world.client("auditor").get(BASE).json()
    assert got["approved_by"] is None
    assert got["decisions"][0]["reason"] == "<b>too long a loop</b>"  # text, kept verbatim


# --- a database writer who is not the app ----------------------------------------------------

def _sql(world: World, statement: str, **params: Any) -> None:
    with world.database.engine.begin() as connection:
        connection.execute(text(statement), params)


def test_a_procedure_body_changed_in_the_database_is_reported_and_not_used(
        world: World) -> None:
    _save(world)
    supervisor = world.client("supervisor")
    signer = register_key(supervisor)
    assert _decide(world, supervisor, signer).status_code == 201
    tampered = _document()
    tampered["refines"]["goals"][0]["envelope"]["depth_m"] = [0, 100]
    _sql(world, "UPDATE procedures SET document = :doc WHERE name = :name",
         doc=json.dumps(tampered), name=NAME)
    got = world.client("auditor").get(BASE).json()
    assert got["approved_by"] is None
    assert any("stored document has digest" in p for p in got["integrity"])
    # Orders naming it get no body from a row that disagrees with the log.
    _mission_version(world, _orders())
    uses = _uses(world, "search-and-sample-procedure")
    assert uses["all_approved"] is False and uses["procedures"][0]["in_library"] is False
    # Also rewriting the digest column: the log entry still tells.
    new_digest = procedure_from_data(tampered).digest
    _sql(world, "UPDATE procedures SET digest = :digest WHERE name = :name",
         digest=new_digest, name=NAME)
    got = world.client("auditor").get(BASE).json()
    assert got["approved_by"] is None
    assert any("log entry records" in p for p in got["integrity"]), got["integrity"]


def test_a_decision_changed_in_the_database_is_reported_and_not_an_approval(
        world: World) -> None:
    _save(world)
    supervisor = world.client("supervisor")
    signer = register_key(supervisor)
    assert _decide(world, supervisor, signer, "rejected", "no").status_code == 201
    _sql(world, "UPDATE procedure_approvals SET decision = 'approved'")
    got = world.client("auditor").get(BASE).json()
    assert got["approved_by"] is None
    problems = got["decisions"][0]["integrity"]
    assert any("decision" in p for p in problems), problems


def test_the_review_lists_a_bounded_number_of_procedures(world: World) -> None:
    from countersign.orders.model import Orders
    from countersign.store.procedures import MAX_USES, procedure_uses

    goals = [{"id": f"G{i}", "refines": {"procedure": f"p{i}", "version": 1},
              "next": {"succeed": "COMPLETE", "fail": "ABORT", "violate": "ABORT"}}
             for i in range(MAX_USES + 1)]
    orders = Orders.model_validate({"id": "many", "start": "G0", "goals": goals})
    with world.database.session() as db:
        listed, truncated = procedure_uses(db, orders)
    assert len(listed) == MAX_USES and truncated


def test_the_author_of_a_version_may_not_decide_on_it(world: World) -> None:
    _save(world)
    admin = world.client("admin")
    users = admin.get("/api/users").json()
    author = next(u for u in users if u["username"] == world.usernames["operator"])
    promoted = admin.patch(f"/api/users/{author['id']}",
                           json={"role": "supervisor", "admin_password": PASSWORD})
    assert promoted.status_code == 200, promoted.text
    client, csrf = world.browser("operator")  # the author, now a supervisor
    client.headers[CSRF_HEADER] = csrf
    signer = register_key(client)
    refused = client.post(f"{BASE}/statement", json={
        "decision": "approved", "reason": "", "key_id": signer.key_id})
    assert refused.status_code == 403 and "separation of duties" in refused.json()["detail"]


def test_cli_signs_a_procedure_decision_with_a_key_file(
        world: World, server: str, tmp_path: Path, capsys: pytest.CaptureFixture[str],
        monkeypatch: pytest.MonkeyPatch) -> None:
    from countersign.cli import main

    _save(world)
    key_file = tmp_path / "supervisor.pem"
    assert main(["keygen", "--out", str(key_file)]) == 0
    public = capsys.readouterr().out.split("public key:")[1].split()[0]
    registered = world.client("supervisor").post("/api/keys", json={
        "public_key": public, "password": PASSWORD})
    assert registered.status_code == 201, registered.text
    password_file = tmp_path / "password"
    password_file.write_text(PASSWORD + "\n")
    monkeypatch.setenv("COUNTERSIGN_TOKEN", world.tokens["supervisor"])
    argv = ["procedures", "sign", "--server", server, "--key", str(key_file), "--name", NAME,
            "--version", "1", "--decision", "approved"]
    monkeypatch.setattr("getpass.getpass", lambda prompt="": "not the password")
    assert main(argv) == 1 and "password" in capsys.readouterr().err
    assert main([*argv, "--password-file", str(password_file)]) == 0
    assert capsys.readouterr().out.startswith(f"approved: procedure {NAME} version 1 (sha256:")
    assert world.client("auditor").get(BASE).json()["approved_by"] == \
        world.usernames["supervisor"]
    assert main([*argv, "--password-file", str(password_file)]) == 1
    assert "decision already" in capsys.readouterr().err
    assert main([*argv[:-2], "--decision", "approved", "--key", str(tmp_path / "none")]) == 2


def test_a_procedure_is_checked_without_holding_the_write_lock(
        world: World, monkeypatch: pytest.MonkeyPatch) -> None:
    """Checking a procedure of up to 2,000 goals takes seconds (its solver budget alone is
    two): on SQLite, doing it inside the write transaction made every other writer, any user's
    draft edit, wait for it."""
    writable_meanwhile = probe_write_lock(world, monkeypatch, procedures_store, "check_procedure")
    _save(world)
    assert writable_meanwhile == [True]
    # The version's number is checked again under the write lock: no gap, no second 1.
    again = world.client("operator").post("/api/procedures", json=_document())
    assert again.status_code == 409 and "saved already" in again.json()["detail"], again.text
    assert writable_meanwhile == [True]  # refused before any check
