"""Tampering directly in the database (bypassing the append-only triggers) is caught by the
offline verifier, which names what changed; a log that forks from a published checkpoint
fails too."""

from __future__ import annotations

import json
from typing import Any

import pytest
from sqlalchemy import text

from countersign.approvals import dsse
from countersign.approvals.bundle import from_problem, verify_bundle

from .approval_helpers import approve, bypass_triggers, new_version, register_key, submit
from .conftest import World


@pytest.fixture
def approved(world: World) -> tuple[World, dict[str, Any], dict[str, Any]]:
    supervisor = world.client("supervisor")
    signer = register_key(supervisor)
    approval = approve(world, supervisor, signer, submit(world, new_version(world)))
    bundle = world.client("auditor").get("/api/audit/bundle").json()
    assert verify_bundle(bundle).ok
    return world, approval, bundle


def _problems(world: World) -> list[str]:
    # A log with deleted entries answers 409 with the bundle inside (store/log_gaps.py).
    bundle, _ = from_problem(world.client("auditor").get("/api/audit/bundle").json())
    report = verify_bundle(bundle, trusted_log_key=bundle["log_key"]["public_key"])
    assert not report.ok
    return report.problems


def _scalar(world: World, sql: str, **params: Any) -> Any:
    with world.database.engine.connect() as connection:
        return connection.execute(text(sql), params).scalar_one()


def test_changed_version_orders(approved: tuple[World, dict[str, Any], dict[str, Any]]) -> None:
    world, approval, _ = approved
    orders = _scalar(world, "SELECT orders FROM mission_versions WHERE number = :n",
                     n=approval["version"])
    data = json.loads(orders) if isinstance(orders, str) else orders
    data["goals"][0]["title"] = "Search Area Z"
    cast = "CAST(:o AS json)" if world.database.engine.dialect.name == "postgresql" else ":o"
    bypass_triggers(world.database, "mission_versions",
                    f"UPDATE mission_versions SET orders = {cast} WHERE number = :n",
                    o=json.dumps(data), n=approval["version"])
    problems = _problems(world)
    assert any(f"approval {approval['id']}: the stored orders of search-and-sample@v1 do not "
               "hash to the signed digest" in p for p in problems), problems


def test_changed_envelope(approved: tuple[World, dict[str, Any], dict[str, Any]]) -> None:
    world, approval, _ = approved
    envelope = json.loads(_scalar(world, "SELECT envelope FROM approvals WHERE id = :i",
                                  i=approval["id"]))
    payload = json.loads(dsse.unb64(envelope["payload"], "p"))
    payload["predicate"]["reason"] = "approved with reservations"
    envelope["payload"] = dsse.b64(json.dumps(payload).encode())
    bypass_triggers(world.database, "approvals", "UPDATE approvals SET envelope = :e WHERE id = :i",
                    e=json.dumps(envelope), i=approval["id"])
    problems = _problems(world)
    name = f"approval {approval['id']}"
    assert f"{name}: the envelope differs from the one logged in entry " \
           f"{approval['log_index']}" in problems, problems
    assert any(p.startswith(f"{name}: the signature does not verify") for p in problems)


def test_changed_key(approved: tuple[World, dict[str, Any], dict[str, Any]]) -> None:
    world, approval, _ = approved
    forged = dsse.public_text(dsse.generate_key())
    with world.database.engine.begin() as connection:
        connection.execute(text("UPDATE signing_keys SET public_key = :p"), {"p": forged})
    problems = _problems(world)
    assert any(p.startswith(f"key {approval['key_id']} differs from its registration in log "
                            "entry") for p in problems), problems


def test_changed_log_entry(approved: tuple[World, dict[str, Any], dict[str, Any]]) -> None:
    world, approval, _ = approved
    index = approval["log_index"] - 2  # the submission event, say
    entry = _scalar(world, 'SELECT entry FROM log_entries WHERE "index" = :i', i=index)
    changed = entry.replace('"actor":"operator1"', '"actor":"admin1"')
    assert changed != entry
    bypass_triggers(world.database, "log_entries",
                    'UPDATE log_entries SET entry = :e WHERE "index" = :i', e=changed, i=index)
    problems = _problems(world)
    assert any(f"log entry {index + 1} does not chain to entry {index}" in p
               for p in problems), problems
    assert any("differ from what the checkpoint at size" in p for p in problems), problems


def test_changed_last_log_entry(approved: tuple[World, dict[str, Any], dict[str, Any]]) -> None:
    world, approval, _ = approved
    last = approval["log_index"]
    entry = _scalar(world, 'SELECT entry FROM log_entries WHERE "index" = :i', i=last)
    bypass_triggers(world.database, "log_entries",
                    'UPDATE log_entries SET entry = :e WHERE "index" = :i',
                    e=entry.replace("approval.approved", "approval.rejected"), i=last)
    problems = _problems(world)
    assert any(f"log entries 0..{last} differ from what the checkpoint at size {last + 1} "
               "signed" in p for p in problems), problems


def test_removed_log_entry(approved: tuple[World, dict[str, Any], dict[str, Any]]) -> None:
    world, approval, _ = approved
    last = approval["log_index"]
    with world.database.engine.begin() as connection:
        if connection.dialect.name == "postgresql":
            connection.execute(text("ALTER TABLE log_entries DISABLE TRIGGER USER"))
            connection.execute(text("ALTER TABLE approvals DISABLE TRIGGER USER"))
        else:
            connection.execute(text("DROP TRIGGER log_entries_no_delete"))
            connection.execute(text("DROP TRIGGER approvals_no_delete"))
        connection.execute(text("DELETE FROM approvals"))
        connection.execute(text('DELETE FROM log_entries WHERE "index" = :i'), {"i": last})
    problems = _problems(world)
    assert any(f"covers {last + 1} entries but the bundle holds {last}: entries were removed"
               in p for p in problems), problems


def test_bundle_edited_after_export(approved: tuple[World, dict[str, Any], dict[str, Any]]
                                    ) -> None:
    _, _, bundle = approved
    digest = next(iter(bundle["orders"]))
    bundle["orders"][digest]["goals"][1]["title"] = "Take no sample"
    bundle["checkpoints"][-1]["root"] = "00" * 32
    report = verify_bundle(bundle)
    assert any("do not hash to the signed digest" in p for p in report.problems)
    assert any("checkpoint note does not state" in p for p in report.problems)
