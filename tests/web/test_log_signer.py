"""The log signer vouches only for what it appended.

A database writer who is not the app (INSERTs alone, every trigger in place, but no log key)
forges a key registration and an approval the way the app would write them: the bundle does
not verify, and the CLI verifier and the app name the entries. Auditors (`audit verify
--state`, `countersign witness`) catch a rewritten, truncated or forked log, naming both
heads; the signer refuses to sign such a head."""

from __future__ import annotations

import json
import os
import stat
from pathlib import Path
from typing import Any
from unittest import mock

import pytest
from fastapi.testclient import TestClient
from sqlalchemy import select, text

from countersign.approvals import dsse
from countersign.approvals.bundle import verify_bundle
from countersign.approvals.log import entry_leaf
from countersign.approvals.note import COSIGNATURE, verifier_key
from countersign.approvals.signer import SignerError
from countersign.cli import main
from countersign.cli.witness import witness_round
from countersign.settings import Settings
from countersign.store import approvals as service
from countersign.store.approvals import decisions
from countersign.store.db import Database
from countersign.store.events import record
from countersign.store.tables import SigningKey, User
from countersign.web.app import create_app

from .approval_helpers import approve, bypass_triggers, new_version, register_key, submit
from .conftest import World


def _bundle(world: World) -> dict[str, Any]:
    response = world.client("auditor").get("/api/audit/bundle")
    assert response.status_code == 200, response.text
    data: dict[str, Any] = response.json()
    return data


def _forge_approval(world: World, submission: int) -> None:
    """What finding 2 did: INSERT a signing key, its key.registered event and log entry, a
    self-signed envelope, the approval.approved event and entry and the approvals row, with
    the app's own code but without its log signer (the attacker has no log key)."""
    attacker = Database(world.database.url)
    assert attacker.log_signer is None
    key = dsse.generate_key()
    kid = dsse.key_id(key.public_key())
    with attacker.session() as db:
        supervisor = db.scalars(select(User).where(User.role == "supervisor")).one()
        db.add(SigningKey(id=kid, user_id=supervisor.id, name="forged",
                          public_key=dsse.public_text(key)))
        db.flush()
        record(db, kind="key.registered", actor=supervisor, detail={
            "key_id": kid, "public_key": dsse.public_text(key), "user": supervisor.username,
            "name": "forged"}, signer=attacker.log_signer)
        prepared = service.prepare_decision(db, submission_id=submission, supervisor=supervisor,
                                            decision="approved", reason="", key_id=kid,
                                            reports=attacker.reports, signer=attacker.log_signer)
        envelope = json.dumps(dsse.sign_envelope(prepared.payload, key))
        # The attacker writes rows with the app's code but skips its password check.
        with mock.patch.object(decisions, "confirm_password", lambda *a, **k: None):
            service.decide(db, submission_id=submission, supervisor=supervisor,
                           envelope=envelope, password=None, reports=attacker.reports,
                           signer=attacker.log_signer)
    attacker.engine.dispose()


def _index_of(world: World, kind: str) -> int:
    with world.database.engine.connect() as connection:
        return int(connection.execute(text(
            "SELECT l.\"index\" FROM log_entries l JOIN events e ON e.id = l.event_id "
            "WHERE e.kind = :k ORDER BY l.\"index\" DESC LIMIT 1"), {"k": kind}).scalar_one())


def test_decision_returns_a_receipt_signed_by_the_log_key(world: World) -> None:
    supervisor = world.client("supervisor")
    approval = approve(world, supervisor, register_key(supervisor),
                       submit(world, new_version(world)))
    receipt = json.loads(approval["receipt"])
    assert receipt["index"] == approval["log_index"]
    bundle = _bundle(world)
    assert bundle["receipts"][approval["log_index"]] == approval["receipt"]
    report = verify_bundle(bundle, trusted_log_key=bundle["log_key"]["public_key"])
    assert report.ok, report.problems
    # The checkpoint is a C2SP signed note over an origin unique to this log.
    checkpoint = bundle["checkpoints"][-1]
    origin = bundle["log_key"]["origin"]
    assert checkpoint["signed_note"].startswith(checkpoint["note"] + "\n\u2014 " + origin + " ")
    assert checkpoint["note"] == f"{origin}\n{checkpoint['size']}\n" + \
        dsse.b64(bytes.fromhex(checkpoint["root"])) + "\n"


def test_a_forged_approval_by_inserts_does_not_verify(world: World, tmp_path: Path,
                                                      capsys: pytest.CaptureFixture[str]
                                                      ) -> None:
    supervisor = world.client("supervisor")
    approve(world, supervisor, register_key(supervisor), submit(world, new_version(world)))
    published = world.client("auditor").get("/api/log/checkpoint").json()
    _forge_approval(world, submit(world, new_version(world)))
    registered, approved = _index_of(world, "key.registered"), _index_of(world, "approval.approved")

    bundle = _bundle(world)
    log_key = bundle["log_key"]["public_key"]
    report = verify_bundle(bundle, trusted_log_key=log_key, published=[published])
    assert not report.ok
    for index, kind in ((registered, "key.registered"), (approved, "approval.approved")):
        assert any(p.startswith(f"log entry {index} ({kind}) carries no receipt from the log "
                                "signer") for p in report.problems), report.problems
    # The app names the first entry it will not vouch for (and signs no checkpoint over it).
    assert bundle["signer_refused"].startswith(
        f"log entry {registered} carries no receipt from the log signer")
    assert bundle["checkpoints"][-1]["size"] == published["size"]
    # So does the CLI verifier, pinned to the log key, with the earlier checkpoint.
    path, checkpoint = tmp_path / "bundle.json", tmp_path / "checkpoint.json"
    path.write_text(json.dumps(bundle))
    checkpoint.write_text(json.dumps(published))
    code = main(["audit", "verify", str(path), "--log-key", log_key, "--checkpoint",
                 str(checkpoint)])
    out = capsys.readouterr().out
    assert code == 1
    assert f"error: log entry {approved} (approval.approved) carries no receipt" in out, out


def test_receipts_cannot_be_inserted_for_forged_entries(world: World) -> None:
    """A receipt row for a forged entry, signed with any key but the log key, fails too."""
    supervisor = world.client("supervisor")
    approve(world, supervisor, register_key(supervisor), submit(world, new_version(world)))
    _forge_approval(world, submit(world, new_version(world)))
    index = _index_of(world, "key.registered")
    fake = json.loads(_bundle(world)["receipts"][0])
    fake["index"] = index
    with world.database.engine.begin() as connection:
        connection.execute(text('INSERT INTO log_receipts ("index", receipt) VALUES (:i, :r)'),
                           {"i": index, "r": json.dumps(fake)})
    bundle = _bundle(world)
    report = verify_bundle(bundle, trusted_log_key=bundle["log_key"]["public_key"])
    assert any(p.startswith(f"log entry {index} (key.registered) has a receipt for another "
                            "entry") for p in report.problems), report.problems


def _rewrite_last_entry(world: World) -> None:
    """A writer with the triggers dropped edits the newest entry's reason."""
    with world.database.engine.connect() as connection:
        index, entry = connection.execute(text(
            'SELECT "index", entry FROM log_entries ORDER BY "index" DESC LIMIT 1')).one()
    data = json.loads(entry)
    data["event"]["detail"]["forged"] = True
    forged = json.dumps(data, sort_keys=True, separators=(",", ":"))
    bypass_triggers(world.database, "log_entries",
                    'UPDATE log_entries SET entry = :e, leaf_hash = :h WHERE "index" = :i',
                    e=forged, h=entry_leaf(forged.encode()), i=index)


def test_the_signer_refuses_a_rewritten_log(world: World) -> None:
    supervisor = world.client("supervisor")
    approve(world, supervisor, register_key(supervisor), submit(world, new_version(world)))
    before = world.client("auditor").get("/api/log/checkpoint").json()
    _rewrite_last_entry(world)
    new_version(world)  # grows the log past the rewritten entry
    world.database.log_tree_cache.clear()  # a fresh process: no cached tree
    bundle = _bundle(world)
    refusal = bundle["signer_refused"]
    assert refusal.startswith("the new head is not a consistent extension of the last: the "
                              f"signer's last head is size {before['size']}, root "
                              f"{before['root']}, the new head is size ")
    assert bundle["checkpoints"][-1]["size"] == before["size"]


def _auditor_round(world: World, tmp_path: Path, state: Path,
                   capsys: pytest.CaptureFixture[str]) -> tuple[int, str]:
    bundle = _bundle(world)
    path = tmp_path / "bundle.json"
    path.write_text(json.dumps(bundle))
    code = main(["audit", "verify", str(path), "--log-key", bundle["log_key"]["public_key"],
                 "--state", str(state)])
    return code, capsys.readouterr().out


def _resigned_world(world: World, tmp_path: Path, keep: int) -> World:
    """The server's history replaced: the first `keep` entries of the log re-signed by the same
    log key into a new database, with a fresh signer state (state file deleted), as a server
    operator could do. The log key and its directory are kept."""
    url = f"sqlite:///{tmp_path / f'resigned-{keep}.db'}"
    database = Database(url)
    database.migrate()
    with world.database.engine.connect() as source, database.engine.begin() as target:
        for table in ("users", "api_tokens", "vehicles", "missions", "mission_versions",
                      "events", "log_entries", "log_receipts"):
            rows = source.execute(text(f"SELECT * FROM {table}")).mappings().all()
            if table in ("log_entries", "log_receipts"):
                rows = [r for r in rows if r["index"] < keep]
            for row in rows:
                columns = ", ".join(f'"{c}"' for c in row)
                values = ", ".join(f":{c}" for c in row)
                target.execute(text(f"INSERT INTO {table} ({columns}) VALUES ({values})"),
                               dict(row))
    directory = world.app.state.database.log_signer.directory
    (directory / "state.json").unlink()
    database.log_signer = world.app.state.database.log_signer
    app = create_app(Settings(data_dir=tmp_path / f"data-{keep}", database_url=url), database)
    database.log_tree_cache.clear()
    return World(app, database, world.tokens, world.usernames)


@pytest.mark.parametrize("how", ["truncated", "forked"])
def test_audit_verify_with_state_catches_a_replaced_history(
        world: World, tmp_path: Path, capsys: pytest.CaptureFixture[str], how: str) -> None:
    if world.database.engine.dialect.name != "sqlite":
        pytest.skip("the replaced history is built in SQLite")
    supervisor = world.client("supervisor")
    approve(world, supervisor, register_key(supervisor), submit(world, new_version(world)))
    state = tmp_path / "auditor.json"
    code, out = _auditor_round(world, tmp_path, state, capsys)
    assert code == 0, out
    seen = world.client("auditor").get("/api/log/checkpoint").json()
    size = seen["size"]
    replaced = _resigned_world(world, tmp_path, size - 2)
    if how == "forked":  # a different entry where the history had another
        new_version(replaced)
        new_version(replaced)
        new_version(replaced)
    current = replaced.client("auditor").get("/api/log/checkpoint").json()
    # On its own, pinned to the log key, the replaced history verifies...
    alone = verify_bundle(_bundle(replaced), trusted_log_key=seen["public_key"])
    assert alone.ok, alone.problems
    # ...but not against the auditor's state, which names both heads.
    code, out = _auditor_round(replaced, tmp_path, state, capsys)
    assert code == 1
    seen_head = f"size {size}, root {seen['root']}"
    now_head = f"size {current['size']}, root {current['root']}"
    if how == "truncated":
        assert ("the log was rolled back (truncated): a checkpoint seen before has "
                f"{seen_head}; the log now has {now_head}") in out, out
    else:
        assert (f"the log forks from the checkpoint seen before ({seen_head}); the log now has "
                f"{now_head}") in out, out


def _witness(world: World, state: Path, key: Any = None) -> Any:
    client = world.client("auditor")

    def get(path: str) -> dict[str, Any]:
        response = client.get(path)
        assert response.status_code == 200, response.text
        data: dict[str, Any] = response.json()
        return data

    def post(path: str, body: dict[str, Any]) -> dict[str, Any]:
        response = client.post(path, json=body)
        assert response.status_code == 201, response.text
        data: dict[str, Any] = response.json()
        return data

    log_key = get("/api/log/checkpoint")["public_key"]
    return witness_round(get, post, log_key=log_key, state=state, key=key, name="witness.test")


@pytest.mark.parametrize("how", ["truncated", "forked"])
def test_the_witness_catches_a_replaced_history(world: World, tmp_path: Path, how: str) -> None:
    if world.database.engine.dialect.name != "sqlite":
        pytest.skip("the replaced history is built in SQLite")
    supervisor = world.client("supervisor")
    approve(world, supervisor, register_key(supervisor), submit(world, new_version(world)))
    state = tmp_path / "witness.json"
    first = _witness(world, state)
    assert first.ok, first.lines
    seen = world.client("auditor").get("/api/log/checkpoint").json()
    replaced = _resigned_world(world, tmp_path, seen["size"] - 2)
    if how == "forked":
        for _ in range(3):
            new_version(replaced)
    current = replaced.client("auditor").get("/api/log/checkpoint").json()
    result = _witness(replaced, state)
    assert not result.ok
    seen_head = f"size {seen['size']}, root {seen['root']}"
    now_head = f"size {current['size']}, root {current['root']}"
    text_ = "\n".join(result.lines)
    if how == "truncated":
        assert f"a checkpoint seen before has {seen_head}; the server now presents " \
               f"{now_head}" in text_, text_
    else:
        assert f"the checkpoint seen before ({seen_head}): no valid consistency proof to " \
               f"{now_head}" in text_, text_


def test_the_witness_cosigns_and_the_server_publishes(world: World, tmp_path: Path) -> None:
    supervisor = world.client("supervisor")
    approve(world, supervisor, register_key(supervisor), submit(world, new_version(world)))
    key = dsse.generate_key()
    state = tmp_path / "witness.json"
    client = world.client("auditor")
    checkpoint = client.get("/api/log/checkpoint").json()
    # Not registered yet: refused with a problem naming the witnesses file.
    from countersign.approvals.note import cosign
    refused = client.post("/api/log/cosignatures", json={
        "checkpoint": checkpoint["note"], "cosignature": cosign(checkpoint["note"],
                                                                "witness.test", key, 1)})
    assert refused.status_code == 400
    assert "not a registered witness" in refused.json()["detail"]
    directory = world.app.state.database.log_signer.directory
    (directory / "witnesses").write_text(
        verifier_key("witness.test", dsse.raw_public(key.public_key()), COSIGNATURE) + "\n")
    result = _witness(world, state, key)
    assert result.ok, result.lines
    new_version(world)
    second = _witness(world, state, key)  # a consistency proof from the kept checkpoint
    assert second.ok and "extends" in second.lines[0], second.lines
    published = client.get("/api/log/cosigned").json()
    assert len(published["cosignatures"]) == 1
    assert published["signed_note"].endswith(published["cosignatures"][0])


def test_cosignatures_only_move_forward_and_not_beyond_the_clock(world: World) -> None:
    import time

    from countersign.approvals.note import cosign
    supervisor = world.client("supervisor")
    approve(world, supervisor, register_key(supervisor), submit(world, new_version(world)))
    key = dsse.generate_key()
    directory = world.app.state.database.log_signer.directory
    (directory / "witnesses").write_text(
        verifier_key("witness.test", dsse.raw_public(key.public_key()), COSIGNATURE) + "\n")
    client = world.client("auditor")
    body = client.get("/api/log/checkpoint").json()["note"]
    now = int(time.time())

    def post(timestamp: int) -> Any:
        return client.post("/api/log/cosignatures", json={
            "checkpoint": body, "cosignature": cosign(body, "witness.test", key, timestamp)})

    future = post(now + 75 * 365 * 86400)  # dated about 2100
    assert future.status_code == 400 and "later than" in future.json()["detail"], future.text
    assert post(now - 60).status_code < 300
    newer = cosign(body, "witness.test", key, now)
    assert client.post("/api/log/cosignatures", json={
        "checkpoint": body, "cosignature": newer}).status_code < 300
    replayed = post(now - 60)  # the older, still valid cosignature sent again
    assert replayed.status_code == 400 and "already cosigned" in replayed.json()["detail"]
    published = client.get("/api/log/cosigned").json()["cosignatures"]
    assert [line.rstrip("\n") for line in published] == [newer.rstrip("\n")]


def test_the_server_refuses_a_log_key_readable_by_others(tmp_path: Path) -> None:
    settings = Settings(data_dir=tmp_path, database_url=f"sqlite:///{tmp_path / 'x.db'}")
    create_app(settings, Database(settings.database_url))
    key = tmp_path / "log-signer" / "log-key.pem"
    assert stat.S_IMODE(key.stat().st_mode) == 0o600
    assert "log-key" not in json.dumps(os.listdir(tmp_path))  # not beside the database
    os.chmod(key, 0o644)
    with pytest.raises(SignerError, match="may be read by others"):
        create_app(settings, Database(settings.database_url))


def test_no_log_key_in_the_database(world: World) -> None:
    supervisor = world.client("supervisor")
    approve(world, supervisor, register_key(supervisor), submit(world, new_version(world)))
    signer = world.app.state.database.log_signer
    pem = dsse.private_pem(signer.key).decode()
    body = pem.split("-----")[2].strip().replace("\n", "")
    with world.database.engine.connect() as connection:
        for table in connection.execute(text(
                "SELECT name FROM sqlite_master WHERE type = 'table'")).scalars() \
                if connection.dialect.name == "sqlite" else []:
            dump = json.dumps([list(r) for r in connection.execute(
                text(f'SELECT * FROM "{table}"')).all()], default=str)
            assert body not in dump, table


__all__ = ["TestClient"]
