"""The log signer remembers every entry it appended, from the commit of its transaction until a
signed checkpoint covers it. A database writer who deletes the newest entries (a rejection, a
revocation) with their receipts, events and rows before a checkpoint covers them used to go
unnoticed: the next decision went through and the revoked approval's package verified. Now the
signer refuses to append over the erased entry, to sign a head without it, and the app refuses
to package on such a log; what was rolled back is never remembered."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

import pytest
from sqlalchemy import text

from countersign.approvals.merkle import Tree
from countersign.cli import main
from countersign.store import approvals as service
from countersign.store.approvals.log import _committed_tree, _erased_entry
from countersign.store.events import record

from .approval_helpers import (
    MISSION,
    approve,
    new_version,
    register_key,
    sign_prepared,
    submit,
)
from .conftest import PASSWORD, World


def _erase_newest(world: World, kind: str) -> int:
    """Delete the newest event of `kind` with its log entry and receipt, behind the app."""
    with world.database.engine.begin() as connection:
        postgres = connection.dialect.name == "postgresql"
        row = connection.execute(text(
            'SELECT l."index", e.id FROM log_entries l JOIN events e ON e.id = l.event_id '
            'WHERE e.kind = :k ORDER BY l."index" DESC LIMIT 1'), {"k": kind}).one()
        index, event_id = int(row[0]), int(row[1])
        for table, where, value in (("log_receipts", '"index" = :v', index),
                                    ("log_entries", '"index" = :v', index),
                                    ("approvals", "event_id = :v", event_id),
                                    ("events", "id = :v", event_id)):
            if postgres:
                connection.execute(text(f"ALTER TABLE {table} DISABLE TRIGGER USER"))
            else:
                for trigger in ("no_delete", "no_update"):
                    connection.execute(text(f"DROP TRIGGER IF EXISTS {table}_{trigger}"))
            connection.execute(text(f"DELETE FROM {table} WHERE {where}"), {"v": value})
            if postgres:
                connection.execute(text(f"ALTER TABLE {table} ENABLE TRIGGER USER"))
    world.database.log_tree_cache.clear()
    return index


@pytest.fixture
def revoked(world: World) -> tuple[World, dict[str, Any], int]:
    """An approval, checkpointed, then revoked; the revocation not yet covered."""
    supervisor = world.client("supervisor")
    signer = register_key(supervisor)
    number = new_version(world)
    approval = approve(world, supervisor, signer, submit(world, number))
    assert world.client("auditor").get(
        f"/api/missions/{MISSION}/versions/{number}/package").status_code == 200
    prepared = supervisor.post(f"/api/approvals/{approval['id']}/statement",
                               json={"reason": "lane moved", "key_id": signer.key_id}).json()
    revocation = supervisor.post(f"/api/approvals/{approval['id']}/revoke", json={
        "envelope": sign_prepared(prepared, signer), "password": PASSWORD})
    assert revocation.status_code == 201, revocation.text
    return world, revocation.json(), number


def test_an_erased_revocation_stops_the_log_and_the_package(
        revoked: tuple[World, dict[str, Any], int]) -> None:
    world, _, number = revoked
    index = _erase_newest(world, "approval.revoked")
    # The approval looks standing again in the tables, but its package is refused...
    package = world.client("auditor").get(f"/api/missions/{MISSION}/versions/{number}/package")
    assert package.status_code == 503, package.text
    assert f"log entry {index}" in package.json()["detail"]
    assert "deleted" in package.json()["detail"]
    # ...the bundle says why the signer refuses...
    bundle = world.client("auditor").get("/api/audit/bundle").json()
    assert bundle["signer_refused"] is not None and f"log entry {index}" in \
        bundle["signer_refused"]
    # ...and nothing is appended in the erased entry's place.
    refused = world.client("operator").post(f"/api/missions/{MISSION}/versions")
    assert refused.status_code == 503, refused.text
    assert f"log entry {index} was appended and committed" in refused.json()["detail"]


def test_an_entry_replaced_below_the_end_is_refused(
        revoked: tuple[World, dict[str, Any], int]) -> None:
    world, _, _ = revoked
    with world.database.session() as db:
        tree = _committed_tree(db)
        index = tree.size - 1
        forged = Tree([*tree.levels[0][:index], b"\x00" * 32])
        assert _erased_entry(db, world.database.log_signer, forged) is not None
        assert _erased_entry(db, world.database.log_signer, tree) is None


def test_a_snapshot_older_than_a_commit_is_no_loss(
        revoked: tuple[World, dict[str, Any], int]) -> None:
    """A tree read before a concurrent commit lacks that commit's entries: not an erasure."""
    world, _, _ = revoked
    with world.database.session() as db:
        tree = _committed_tree(db)
        older = Tree(tree.levels[0][:-1])
        assert world.database.log_signer.remembered_beyond(older.size)
        assert _erased_entry(db, world.database.log_signer, older) is None


def test_a_rolled_back_append_is_not_remembered(world: World) -> None:
    signer = world.database.log_signer
    before = dict(signer.remembered_beyond(0))
    with pytest.raises(RuntimeError), world.database.session() as db:
        record(db, kind="mission.created", actor=None, mission_id=MISSION, detail={},
               signer=world.database.log_signer)
        raise RuntimeError("the request failed after appending")
    assert signer.remembered_beyond(0) == before
    # The index the rolled-back append took is free for the next one.
    assert world.client("operator").post(f"/api/missions/{MISSION}/versions").status_code \
        == 201
    assert world.client("auditor").get("/api/audit/bundle").json()["signer_refused"] is None


def test_a_checkpoint_forgets_what_it_covers(
        revoked: tuple[World, dict[str, Any], int]) -> None:
    world, _, _ = revoked
    signer = world.database.log_signer
    assert signer.remembered_beyond(0)
    with world.database.session() as db:
        service.latest_checkpoint(db, signer=signer)
    assert signer.remembered_beyond(0) == {}


def test_the_cli_verifier_fails_on_the_signers_refusal(
        revoked: tuple[World, dict[str, Any], int], tmp_path: Path,
        capsys: pytest.CaptureFixture[str]) -> None:
    world, _, _ = revoked
    index = _erase_newest(world, "approval.revoked")
    answer = world.client("auditor").get("/api/audit/bundle")
    assert answer.status_code == 200, answer.text[:500]
    log_key = answer.json()["log_key"]["public_key"]
    path = tmp_path / "bundle.json"
    path.write_text(answer.text)
    assert main(["audit", "verify", str(path), "--log-key", log_key]) == 1
    out = capsys.readouterr().out
    assert f"the log signer refuses the log: log entry {index}" in out, out


def test_a_verifier_holding_the_receipt_refuses_a_log_without_its_entry(
        revoked: tuple[World, dict[str, Any], int], tmp_path: Path,
        capsys: pytest.CaptureFixture[str]) -> None:
    """The supervisor keeps the receipt returned with the revocation; a log without that entry
    fails `audit verify --receipt`, whatever the server says of its signer."""
    world, revocation, _ = revoked
    receipt = tmp_path / "receipt.json"
    receipt.write_text(revocation["receipt"])
    index = _erase_newest(world, "approval.revoked")
    bundle = world.client("auditor").get("/api/audit/bundle").json()
    bundle["signer_refused"] = None  # a server that does not say so
    path = tmp_path / "bundle.json"
    path.write_text(json.dumps(bundle))
    assert main(["audit", "verify", str(path), "--log-key", bundle["log_key"]["public_key"],
                 "--receipt", str(receipt)]) == 1
    out = capsys.readouterr().out
    assert f"log entry {index} has a receipt from the log signer, but the log ends at " \
        f"{index} entries: the entry was erased" in out, out
