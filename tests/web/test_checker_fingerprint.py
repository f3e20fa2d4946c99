"""Stored reports are keyed by the checker fingerprint (DESIGN.md, Approval record): a report made
by other checks (before an upgrade) is recomputed when read, never shown and never signed, and
the approval statement names the fingerprint of the checks whose report it signs."""

from __future__ import annotations

import json
from typing import Any

import pytest
from alembic import command
from sqlalchemy import text

from countersign.approvals.bundle import verify_bundle
from countersign.store.approvals import decisions
from countersign.store.db import Database, alembic_config
from countersign.verify import fingerprint

from .approval_helpers import (
    MISSION,
    approve,
    new_version,
    prepare,
    register_key,
    sign_prepared,
    submit,
)
from .conftest import PASSWORD, World

# The fingerprint of checks other than these: the ones before an upgrade, or after it.
OTHER = "sha256:" + "0" * 64
MARKER = {"code": "STALE_CHECK", "severity": "error", "subjects": [],
          "message": "made by the checks before the upgrade"}


def _rows(world: World, orders_digest: str) -> list[str]:
    with world.database.engine.connect() as connection:
        return sorted(connection.execute(text(
            "SELECT checker_version FROM validation_reports WHERE digest = :d"),
            {"d": orders_digest}).scalars())


def _stored_report(world: World) -> dict[str, Any]:
    response = world.client("operator").get(f"/api/missions/{MISSION}/report")
    assert response.status_code == 200, response.text
    report: dict[str, Any] = response.json()
    return report


def _upgrade(monkeypatch: pytest.MonkeyPatch, value: str = OTHER) -> None:
    """As if the server restarted on changed checks: the fingerprint is another."""
    monkeypatch.setattr(fingerprint, "checker_fingerprint", lambda: value)


def test_a_report_names_its_checks_and_is_stored_under_them(world: World) -> None:
    report = _stored_report(world)
    current = fingerprint.checker_fingerprint()
    assert report["checker"] == current
    assert _rows(world, report["digest"]) == [current]
    assert world.client().get("/api/health").json()["checker"] == current


def test_a_report_of_other_checks_in_the_table_is_recomputed_not_shown(world: World) -> None:
    report = _stored_report(world)
    number = new_version(world)  # the same orders: the review reads the same stored report
    planted = {**report, "checker": OTHER, "ok": False,
               "findings": [*report["findings"], MARKER]}
    with world.database.engine.begin() as connection:
        connection.execute(text("DELETE FROM validation_reports"))
        connection.execute(text(
            "INSERT INTO validation_reports (digest, checker_version, report, created_at) "
            "VALUES (:d, :c, :r, CURRENT_TIMESTAMP)"),
            {"d": report["digest"], "c": OTHER, "r": json.dumps(planted)})
    world.database.reports.clear()  # a new process: nothing in memory, only the table

    client = world.client("supervisor")
    mission = client.get(f"/api/missions/{MISSION}").json()
    assert mission["ok"] is True and mission["errors"] == 0
    review = client.get(f"/api/missions/{MISSION}/versions/{number}/review").json()
    shown = client.get(f"/api/missions/{MISSION}/report").json()
    current = fingerprint.checker_fingerprint()
    for findings in (review["findings"], shown["findings"]):
        assert MARKER["code"] not in {f["code"] for f in findings}
    assert shown == report and shown["checker"] == current
    # Stored again under the current fingerprint; the other one's row is gone.
    assert _rows(world, report["digest"]) == [current]


def test_a_changed_check_recomputes_the_stored_report(world: World,
                                                      monkeypatch: pytest.MonkeyPatch) -> None:
    before = _stored_report(world)
    _upgrade(monkeypatch)
    after = _stored_report(world)
    assert after["checker"] == OTHER
    assert {k: v for k, v in after.items() if k != "checker"} == {
        k: v for k, v in before.items() if k != "checker"}
    assert _rows(world, before["digest"]) == [OTHER]


def test_the_statement_names_the_checker_of_the_report_it_signs(world: World) -> None:
    number = new_version(world)
    submission = submit(world, number)
    supervisor = world.client("supervisor")
    predicate = prepare(supervisor, submission, register_key(supervisor))["statement"][
        "predicate"]
    assert predicate["checker"] == fingerprint.checker_fingerprint()
    assert predicate["checker"] == _stored_report(world)["checker"]
    # The review the supervisor reads names it too, so the browser can compare before signing.
    review = supervisor.get(f"/api/missions/{MISSION}/versions/{number}/review").json()
    assert review["checker"] == predicate["checker"]


def test_a_statement_prepared_before_an_upgrade_is_not_signed(
        world: World, monkeypatch: pytest.MonkeyPatch) -> None:
    submission = submit(world, new_version(world))
    supervisor = world.client("supervisor")
    signer = register_key(supervisor)
    before = prepare(supervisor, submission, signer)
    _upgrade(monkeypatch)
    response = supervisor.post(f"/api/submissions/{submission}/decision",
                               json={"envelope": sign_prepared(before, signer),
                                     "password": PASSWORD})
    assert response.status_code == 409, response.text
    assert "checker" in response.text
    # Prepared again, it names the new checks and their report, and is accepted.
    again = prepare(supervisor, submission, signer)
    assert again["statement"]["predicate"]["checker"] == OTHER
    response = supervisor.post(f"/api/submissions/{submission}/decision",
                               json={"envelope": sign_prepared(again, signer),
                                     "password": PASSWORD})
    assert response.status_code == 201, response.text


def test_a_report_of_other_checks_is_never_signed(world: World,
                                                  monkeypatch: pytest.MonkeyPatch) -> None:
    """The decision path itself refuses a report whose fingerprint is not the current one,
    whatever the store hands it."""
    submission = submit(world, new_version(world))
    supervisor = world.client("supervisor")
    signer = register_key(supervisor)
    real = decisions._report
    monkeypatch.setattr(decisions, "_report",
                        lambda db, version, reports: {**real(db, version, reports),
                                                      "checker": OTHER})
    response = supervisor.post(f"/api/submissions/{submission}/statement",
                               json={"decision": "approved", "reason": "",
                                     "key_id": signer.key_id})
    assert response.status_code == 409, response.text
    assert "other checks" in response.text


def test_statements_signed_without_a_checker_still_verify(
        world: World, monkeypatch: pytest.MonkeyPatch) -> None:
    submission = submit(world, new_version(world))
    supervisor = world.client("supervisor")
    signer = register_key(supervisor)
    real = decisions._statement

    def before_fingerprints(*args: Any, **kwargs: Any) -> dict[str, Any]:
        statement = real(*args, **kwargs)
        del statement["predicate"]["checker"]
        return statement

    monkeypatch.setattr(decisions, "_statement", before_fingerprints)
    approval = approve(world, supervisor, signer, submission)
    monkeypatch.undo()
    auditor = world.client("auditor")
    detail = auditor.get(f"/api/approvals/{approval['id']}")
    assert detail.status_code == 200, detail.text
    assert "checker" not in detail.json()["statement"]["predicate"]
    report = verify_bundle(auditor.get("/api/audit/bundle").json())
    assert report.ok, report.problems
    assert report.approvals == 1


def test_the_upgrade_drops_reports_kept_under_the_package_version(database_url: str) -> None:
    database = Database(database_url)
    config = alembic_config(database_url)
    with database.engine.begin() as connection:
        config.attributes["connection"] = connection
        command.upgrade(config, "0010")
        connection.execute(text(
            "INSERT INTO validation_reports (digest, checker_version, report, created_at) "
            "VALUES (:d, '0.1.0', '{}', CURRENT_TIMESTAMP)"), {"d": "sha256:" + "a" * 64})
    database.migrate()
    with database.engine.begin() as connection:
        assert connection.execute(text("SELECT count(*) FROM validation_reports")).scalar() == 0
        # A fingerprint fits the key (PostgreSQL refused 71 characters in the old column).
        connection.execute(text(
            "INSERT INTO validation_reports (digest, checker_version, report, created_at) "
            "VALUES (:d, :c, '{}', CURRENT_TIMESTAMP)"),
            {"d": "sha256:" + "a" * 64, "c": fingerprint.checker_fingerprint()})
    database.engine.dispose()
