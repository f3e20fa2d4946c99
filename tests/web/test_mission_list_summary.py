"""The mission list reads the summary columns written with each report, never the reports
, and those columns are display only: nothing that is submitted or signed reads them."""

from __future__ import annotations

from alembic import command
from sqlalchemy import inspect, text

from countersign.store.db import Database, alembic_config
from countersign.verify import fingerprint

from .conftest import World

EXAMPLE = "search-and-sample"


def _with_errors(world: World, new_id: str) -> str:
    """A copy of the example whose first goal's success leads nowhere (an error finding)."""
    client = world.client("operator")
    orders = client.get(f"/api/missions/{EXAMPLE}").json()["orders"]
    orders["id"] = new_id
    orders["goals"][0]["next"]["succeed"] = "NOWHERE"
    created = client.post("/api/missions", json=orders)
    assert created.status_code == 201, created.text
    assert created.json()["errors"] > 0
    return new_id


def _listed(world: World) -> dict[str, dict[str, object]]:
    response = world.client("auditor").get("/api/missions")
    assert response.status_code == 200, response.text
    return {item["id"]: item for item in response.json()["items"]}


def _execute(world: World, sql: str, **values: object) -> None:
    with world.database.engine.begin() as connection:
        connection.execute(text(sql), values)


def test_the_columns_are_written_with_the_report(world: World) -> None:
    _with_errors(world, "broken")
    detail = world.client("auditor").get("/api/missions/broken").json()
    with world.database.engine.connect() as connection:
        row = connection.execute(text(
            "SELECT ok, errors, warnings FROM validation_reports WHERE digest = :d "
            "AND checker_version = :c"),
            {"d": detail["draft_digest"], "c": fingerprint.checker_fingerprint()}).one()
    assert (bool(row.ok), row.errors, row.warnings) == (
        detail["ok"], detail["errors"], detail["warnings"])
    assert row.errors > 0 and row.ok is not None and not row.ok


def test_the_list_shows_counts_without_decoding_reports(world: World) -> None:
    _with_errors(world, "broken")
    before = _listed(world)
    # Every stored report made unusable: a list that decoded one would fail (KeyError: 500).
    _execute(world, "UPDATE validation_reports SET report = '{\"corrupted\": true}'")
    after = _listed(world)
    assert after == before
    assert after["broken"]["errors"] and after["broken"]["ok"] is False
    assert after[EXAMPLE]["errors"] == 0 and after[EXAMPLE]["ok"] is True


def test_a_changed_count_changes_the_list_and_nothing_that_is_signed(world: World) -> None:
    _with_errors(world, "broken")
    operator = world.client("operator")
    number = operator.post("/api/missions/broken/versions").json()["number"]
    # A database writer makes the erroneous orders look clean in the summary columns.
    _execute(world, "UPDATE validation_reports SET ok = :t, errors = 0, warnings = 0", t=True)
    assert _listed(world)["broken"]["errors"] == 0  # a number on a list: display only
    refused = operator.post(f"/api/missions/broken/versions/{number}/submit")
    assert refused.status_code == 409, refused.text
    assert "error finding" in refused.json()["detail"]
    report = world.client("auditor").get("/api/missions/broken/report").json()
    assert report["ok"] is False
    assert any(f["severity"] == "error" for f in report["findings"])


def test_the_revision_fills_the_columns_of_reports_stored_before_it(database_url: str) -> None:
    database = Database(database_url)
    config = alembic_config(database_url)
    stored = ('{"ok": false, "findings": [{"severity": "error"}, {"severity": "warning"},'
              ' {"severity": "error"}]}')
    with database.engine.begin() as connection:
        config.attributes["connection"] = connection
        command.upgrade(config, "0011")
        connection.execute(text(
            "INSERT INTO validation_reports (digest, checker_version, report, created_at) "
            f"VALUES (:d, :c, '{stored}', CURRENT_TIMESTAMP)"),
            {"d": "sha256:" + "a" * 64, "c": "sha256:" + "b" * 64})
    database.migrate()
    with database.engine.connect() as connection:
        row = connection.execute(text("SELECT ok, errors, warnings FROM validation_reports")).one()
        indexes = {index["name"] for index in inspect(connection).get_indexes("missions")}
    assert (bool(row.ok), row.errors, row.warnings) == (False, 2, 1)
    assert {"ix_missions_status_id", "ix_missions_vehicle_id"} <= indexes
    database.engine.dispose()
