"""Upgrading a deployment from before the log signer had receipts and its own key directory:
its legacy log key is imported (auditors' pinned key stays valid), and its receipt-less log is
adopted once, only when nothing else can explain the missing receipts."""

from __future__ import annotations

import json
import os
import stat
from pathlib import Path
from typing import Any

import pytest
from cryptography.hazmat.primitives.asymmetric.ed25519 import Ed25519PrivateKey
from sqlalchemy import select

from countersign.approvals import dsse
from countersign.approvals.note import checkpoint_body
from countersign.approvals.signer import LEGACY_ORIGIN, LogSigner
from countersign.cli import main
from countersign.services.log_signer import LEGACY_KEY_ENV, LEGACY_KEY_FILE, LOG_KEY_DIR_ENV
from countersign.settings import Settings
from countersign.store.accounts import create_user
from countersign.store.approvals import log_tree
from countersign.store.db import Database
from countersign.store.events import record
from countersign.store.tables import Checkpoint, User
from countersign.web.app import create_app

from .approval_helpers import approve, new_version, register_key, submit
from .conftest import PASSWORD, World, count_rows, seed_users


def _old_deployment(url: str, data_dir: Path) -> tuple[Ed25519PrivateKey, dict[str, str],
                                                        dict[str, str]]:
    """A database as the code before receipts left it: entries appended without a log signer,
    a checkpoint signed (old format: body only) with the key it kept in the data directory."""
    old = Database(url)
    assert old.log_signer is None
    old.migrate()
    tokens, usernames = seed_users(old)
    key = dsse.generate_key()
    dsse.write_private_key(data_dir / LEGACY_KEY_FILE, key)
    with old.session() as db:
        tree = log_tree(db)
        note = checkpoint_body(LEGACY_ORIGIN, tree.size, tree.root())
        db.add(Checkpoint(tree_size=tree.size, root_hash=tree.root().hex(),
                          key_id=dsse.key_id(key.public_key()), public_key=dsse.public_text(key),
                          note=note, signature=dsse.b64(key.sign(note.encode()))))
    old.engine.dispose()
    return key, tokens, usernames


def _start(url: str, data_dir: Path, tokens: dict[str, str],
           usernames: dict[str, str]) -> World:
    database = Database(url)
    return World(create_app(Settings(data_dir=data_dir, database_url=url), database), database,
                 tokens, usernames)


def _bundle(world: World) -> dict[str, Any]:
    response = world.client("auditor").get("/api/audit/bundle")
    assert response.status_code == 200, response.text
    data: dict[str, Any] = response.json()
    return data


def _forge_entry(url: str) -> None:
    """A database writer who is not the app appends an entry (it has no log key)."""
    attacker = Database(url)
    with attacker.session() as db:
        admin = db.scalars(select(User).where(User.role == "admin")).one()
        record(db, kind="user.created", actor=admin, detail={"username": "mallory"},
               signer=attacker.log_signer)
    attacker.engine.dispose()


def _adoptions(world: World) -> int:
    return count_rows(world.database, "SELECT count(*) FROM events WHERE kind = 'log.adopted'")


def test_an_old_deployment_upgrades_and_keeps_its_log_key(
        database_url: str, tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    old_key, tokens, usernames = _old_deployment(database_url, tmp_path)
    old_public = dsse.public_text(old_key)
    entries = count_rows(Database(database_url), "SELECT count(*) FROM log_entries")
    world = _start(database_url, tmp_path, tokens, usernames)
    err = capsys.readouterr().err
    signer: LogSigner = world.database.log_signer

    # The key moved into the signer's directory (0600), the log keeps its public key.
    assert not (tmp_path / LEGACY_KEY_FILE).exists()
    assert stat.S_IMODE((signer.directory / "log-key.pem").stat().st_mode) == 0o600
    assert signer.public_text == old_public
    assert f"log key from {tmp_path / LEGACY_KEY_FILE} was moved" in err, err
    assert f"adopted the {entries} log entries" in err, err
    assert signer.adopted() == entries
    assert json.loads((signer.directory / "state.json").read_text())["adopted"] == entries

    # From then on the log grows with receipts and its checkpoints are signed.
    supervisor = world.client("supervisor")
    approve(world, supervisor, register_key(supervisor), submit(world, new_version(world)))
    bundle = _bundle(world)
    assert bundle["signer_refused"] is None
    assert bundle["checkpoints"][-1]["size"] == len(bundle["entries"])
    assert bundle["checkpoints"][0]["size"] == entries  # the old checkpoint, still valid
    path = tmp_path / "bundle.json"
    path.write_text(json.dumps(bundle))
    capsys.readouterr()
    code = main(["audit", "verify", str(path), "--log-key", old_public])
    out = capsys.readouterr().out
    assert code == 0, out
    assert f"log entries 0..{entries - 1} were appended before the log signer" in out, out
    assert _adoptions(world) == 1


def test_adoption_happens_once_and_a_later_forgery_is_refused(
        database_url: str, tmp_path: Path) -> None:
    _, tokens, usernames = _old_deployment(database_url, tmp_path)
    world = _start(database_url, tmp_path, tokens, usernames)
    assert _adoptions(world) == 1
    _forge_entry(database_url)
    forged = count_rows(world.database, "SELECT count(*) FROM log_entries") - 1
    for _ in range(2):  # and again after a restart: nothing is adopted twice
        assert _bundle(world)["signer_refused"].startswith(
            f"log entry {forged} carries no receipt from the log signer")
        world.database.engine.dispose()
        world = _start(database_url, tmp_path, tokens, usernames)
        assert _adoptions(world) == 1


def test_a_forged_row_is_not_adopted_by_a_fresh_key_directory(
        world: World, tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    """Receipts exist (the app appended with its signer), a row is inserted behind its back,
    and the server restarts with a new, empty key directory: still no adoption."""
    _forge_entry(world.database.url)
    monkeypatch.setenv(LOG_KEY_DIR_ENV, str(tmp_path / "new-log-signer"))
    restarted = _start(world.database.url, tmp_path, world.tokens, world.usernames)
    assert restarted.database.log_signer.fresh
    assert _adoptions(restarted) == 0
    # Nothing was receipted anew: the old receipts are not the new key's, and the refusal
    # stands (a key directory lost with its key is no way to launder a forged row).
    refused = _bundle(restarted)["signer_refused"]
    assert refused is not None and refused.startswith("log entry 0 has a receipt for another")
    assert count_rows(restarted.database, "SELECT count(*) FROM log_receipts") == \
        count_rows(restarted.database, "SELECT count(*) FROM log_entries") - 1


def test_no_adoption_when_the_key_directory_was_not_made_by_this_start(
        database_url: str, tmp_path: Path) -> None:
    _, tokens, usernames = _old_deployment(database_url, tmp_path)
    os.unlink(tmp_path / LEGACY_KEY_FILE)
    LogSigner(tmp_path / "log-signer")  # an earlier start made the directory, adopted nothing
    world = _start(database_url, tmp_path, tokens, usernames)
    assert not world.database.log_signer.fresh
    assert _adoptions(world) == 0
    with world.database.session() as db:  # a new entry, receipted: the log needs a new head
        create_user(db, username="newcomer", role="operator", password=PASSWORD,
                    signer=world.database.log_signer)
    refused = _bundle(world)["signer_refused"]
    assert refused is not None and refused.startswith("log entry 0 carries no receipt")


def test_the_legacy_key_from_the_environment_is_imported(
        tmp_path: Path, monkeypatch: pytest.MonkeyPatch,
        capsys: pytest.CaptureFixture[str]) -> None:
    key = dsse.generate_key()
    monkeypatch.setenv(LEGACY_KEY_ENV, dsse.private_pem(key).decode())
    settings = Settings(data_dir=tmp_path, database_url=f"sqlite:///{tmp_path / 'x.db'}")
    app = create_app(settings, Database(settings.database_url))
    assert app.state.database.log_signer.public_text == dsse.public_text(key)
    assert "COUNTERSIGN_LOG_KEY is no longer read" in capsys.readouterr().err
    assert stat.S_IMODE((tmp_path / "log-signer" / "log-key.pem").stat().st_mode) == 0o600
    monkeypatch.setenv(LEGACY_KEY_ENV, "not a key")  # read only when the key is made
    create_app(settings, Database(settings.database_url))


def test_no_adoption_when_the_signer_has_state(database_url: str, tmp_path: Path) -> None:
    """A state file (a head signed before, here restored without its key) means the signer
    already vouched for a history: a receipt-less log is not adopted, even with a new key."""
    _, tokens, usernames = _old_deployment(database_url, tmp_path)
    directory = tmp_path / "log-signer"
    directory.mkdir(mode=0o700)
    (directory / "state.json").write_text(json.dumps({"size": 0, "root": "00" * 32,
                                                      "frontier": []}))
    world = _start(database_url, tmp_path, tokens, usernames)
    assert world.database.log_signer.fresh
    assert _adoptions(world) == 0
    assert count_rows(world.database, "SELECT count(*) FROM log_receipts") == 0
