"""The audit bundle after a database writer that is not the app deleted log entries:
a 409 problem naming the missing entries, never a server error; the offline verifier of the
bundle the app can still give names the gap."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

import pytest
from sqlalchemy import text

from countersign.cli import main

from .approval_helpers import approve, bypass_triggers, new_version, register_key, submit
from .conftest import World


@pytest.fixture
def approved(world: World) -> tuple[World, dict[str, Any]]:
    supervisor = world.client("supervisor")
    signer = register_key(supervisor)
    approval = approve(world, supervisor, signer, submit(world, new_version(world)))
    assert world.client("auditor").get("/api/audit/bundle").status_code == 200
    return world, approval


def _delete_entries(world: World, where: str, **params: Any) -> None:
    """Delete log rows behind the app's back (the append-only triggers bypassed)."""
    with world.database.engine.begin() as connection:
        if connection.dialect.name == "postgresql":
            connection.execute(text("ALTER TABLE log_entries DISABLE TRIGGER USER"))
            connection.execute(text(f"DELETE FROM log_entries WHERE {where}"), params)
            connection.execute(text("ALTER TABLE log_entries ENABLE TRIGGER USER"))
        else:
            connection.execute(text("DROP TRIGGER IF EXISTS log_entries_no_delete"))
            connection.execute(text(f"DELETE FROM log_entries WHERE {where}"), params)


def test_bundle_names_the_deleted_entry_of_an_approval(
        approved: tuple[World, dict[str, Any]]) -> None:
    world, approval = approved
    index = approval["log_index"]
    _delete_entries(world, '"index" = :i', i=index)
    answer = world.client("auditor").get("/api/audit/bundle")
    assert answer.status_code == 409, answer.text
    problem = answer.json()
    assert answer.headers["content-type"].startswith("application/problem+json")
    assert f"log entry {index} is missing" in problem["detail"], problem
    assert f"approval {approval['id']}" in problem["detail"], problem
    assert problem["missing_entries"] == [{"first": index, "last": index}]
    assert problem["approvals_without_entry"] == [approval["id"]]


def test_bundle_names_entries_deleted_from_the_middle(
        approved: tuple[World, dict[str, Any]]) -> None:
    world, _ = approved
    _delete_entries(world, '"index" IN (1, 2)')
    answer = world.client("auditor").get("/api/audit/bundle")
    assert answer.status_code == 409, answer.text
    assert "log entries 1..2 are missing" in answer.json()["detail"], answer.json()


def test_audit_verify_names_the_missing_entries(
        approved: tuple[World, dict[str, Any]], tmp_path: Path,
        capsys: pytest.CaptureFixture[str]) -> None:
    world, approval = approved
    last = approval["log_index"]
    _delete_entries(world, '"index" = :i', i=last)
    saved = tmp_path / "bundle.json"
    saved.write_text(world.client("auditor").get("/api/audit/bundle").text)
    bundle = json.loads(saved.read_text())["bundle"]
    code = main(["audit", "verify", str(saved), "--log-key", bundle["log_key"]["public_key"]])
    out = capsys.readouterr().out
    assert code == 1, out
    assert f"log entry {last} is missing" in out, out
    assert f"covers {last + 1} entries but the bundle holds {last}: entries were removed" \
        in out, out
    assert f"approval {approval['id']}: its log entry is missing" in out, out


@pytest.mark.parametrize("leaf", ["zz", "ab" * 31])
def test_a_malformed_leaf_hash_is_a_conflict_not_a_500(
        approved: tuple[World, dict[str, Any]], leaf: str) -> None:
    world, approval = approved
    index = approval["log_index"]
    bypass_triggers(world.database, "log_entries",
                    'UPDATE log_entries SET leaf_hash = :h WHERE "index" = :i', h=leaf, i=index)
    # A fresh process: nothing of the log cached.
    world.database.log_tree_cache.tree = None
    for route, params in (("/api/audit/bundle", {}),
                          ("/api/log/inclusion", {"index": index})):
        answer = world.client("auditor").get(route, params=params)
        assert answer.status_code == 409, (route, answer.text)
        assert f"log entry {index} has a malformed leaf hash" in answer.json()["detail"]


def test_no_proofs_over_a_log_with_deleted_entries(
        approved: tuple[World, dict[str, Any]]) -> None:
    # The remaining leaves would sit at the wrong positions: a 200 "proof" over them matches
    # no signed checkpoint.
    world, approval = approved
    _delete_entries(world, '"index" = 1')
    auditor = world.client("auditor")
    for route, params in (("/api/log/inclusion", {"index": approval["log_index"]}),
                          ("/api/log/consistency", {"first": 1})):
        answer = auditor.get(route, params=params)
        assert answer.status_code == 409, (route, answer.text)
        assert "log entry 1 missing" in answer.json()["detail"], answer.text
