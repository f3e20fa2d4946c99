"""Approved packages: the API builds one, `countersign vehicle verify` and the
standalone tools/verify_package.py accept it and refuse the same eight tamperings with the same
reason (the tampered packages are the shared test vectors)."""

from __future__ import annotations

import io
import json
import subprocess
import sys
import tarfile
from collections.abc import Callable
from datetime import UTC, datetime, timedelta
from pathlib import Path
from typing import Any

import pytest

from countersign.approvals import dsse
from countersign.approved_package.build import build_package, read_tar, write_tar
from countersign.approved_package.verify import verify_package
from countersign.cli import main
from countersign.store.packages import package_parts

from ..export.execution_logs import evidenced_log
from ..standalone_tool import TOOL, standalone_verifier
from .approval_helpers import (
    MISSION,
    PASSWORD,
    approve,
    new_version,
    register_key,
    sign_prepared,
    submit,
)
from .conftest import World

IMC = f"vehicle/{MISSION}.imc"
BHV = f"vehicle/{MISSION}.bhv"


def _package(world: World, number: int) -> bytes:
    response = world.client("auditor").get(f"/api/missions/{MISSION}/versions/{number}/package")
    assert response.status_code == 200, response.text
    assert response.headers["content-type"] == "application/x-tar"
    return response.content


def _edit(data: bytes, change: Callable[[dict[str, bytes]], None], *,
          rehash: bool = True) -> bytes:
    """The package with files changed as a careful attacker would: manifest hashes updated."""
    import hashlib

    files = read_tar(data)
    change(files)
    if rehash:
        manifest = json.loads(files["manifest.json"])
        manifest["files"] = {n: "sha256:" + hashlib.sha256(c).hexdigest()
                             for n, c in sorted(files.items()) if n != "manifest.json"}
        files["manifest.json"] = json.dumps(manifest, sort_keys=True, indent=1).encode()
    return write_tar(files)


def _without_freshness(data: bytes) -> dict[str, bytes]:
    """A package's files but the checkpoint (its cosignature names the second of the request)
    and the manifest that hashes it."""
    return {n: c for n, c in read_tar(data).items()
            if n not in ("log/checkpoint", "manifest.json")}


def _flip_b64(text: str) -> str:
    return text[:10] + ("A" if text[10] != "A" else "B") + text[11:]


def test_packages_verify_and_eight_tamperings_are_refused_alike(world: World,
                                                                tmp_path: Path) -> None:
    supervisor = world.client("supervisor")
    signer = register_key(supervisor)
    first = new_version(world)
    approve(world, supervisor, signer, submit(world, first))
    second = new_version(world)
    approval = approve(world, supervisor, signer, submit(world, second))
    log_key = world.client("auditor").get("/api/log/checkpoint").json()["public_key"]
    good, other = _package(world, second), _package(world, first)
    # The checkpoint's freshness cosignature carries the second it was asked for; all else,
    # and everything at one given time, is byte for byte the same.
    assert _without_freshness(good) == _without_freshness(_package(world, second))
    at = datetime(2026, 1, 2, 3, 4, 5, tzinfo=UTC)
    with world.database.session() as db:
        twice = [build_package(package_parts(db, mission_id=MISSION, number=second,
                                             signer=world.database.log_signer, now=at))
                 for _ in range(2)]
    assert twice[0] == twice[1]  # deterministic
    with tarfile.open(fileobj=io.BytesIO(good)) as tar:
        assert all(m.mtime == 0 for m in tar.getmembers())

    # Revoke the second approval and package it anyway (the API refuses to).
    prepared = supervisor.post(f"/api/approvals/{approval['id']}/statement",
                               json={"reason": "lane moved", "key_id": signer.key_id}).json()
    assert supervisor.post(f"/api/approvals/{approval['id']}/revoke", json={
        "envelope": sign_prepared(prepared, signer), "password": PASSWORD}).status_code == 201
    refused = world.client("auditor").get(f"/api/missions/{MISSION}/versions/{second}/package")
    assert refused.status_code == 409 and "no standing approval" in refused.json()["detail"]
    with world.database.session() as db:
        revoked = build_package(package_parts(db, mission_id=MISSION, number=second,
                                              signer=world.database.log_signer,
                                              standing_only=False))

    def orders_byte(files: dict[str, bytes]) -> None:
        files["orders.json"] = files["orders.json"].replace(b"Search Area A", b"Search Area B", 1)

    def receipt(files: dict[str, bytes]) -> None:
        data = json.loads(files["log/receipt.json"])
        data["signature"] = _flip_b64(data["signature"])
        files["log/receipt.json"] = json.dumps(data).encode()

    def forged_bhv(files: dict[str, bytes]) -> None:
        # Header lines kept (orders digest, plan id, approval), the behaviours changed.
        text = files[BHV].decode()
        head, _, body = text.partition("\n\n")
        files[BHV] = (head + "\n\n" + body.replace("succeed", "fail", 1)
                      .replace("depth", "altitude", 1)).encode()
        assert files[BHV] != read_tar(good)[BHV] and head in files[BHV].decode()

    def proof(files: dict[str, bytes]) -> None:
        data = json.loads(files["log/inclusion.json"])
        data["hashes"][0] = "00" * 32
        files["log/inclusion.json"] = json.dumps(data).encode()

    def strip_stamp(files: dict[str, bytes]) -> None:
        files["log/checkpoint"] = b"\n".join(files["log/checkpoint"].split(b"\n")[:-2]) + b"\n"

    later = datetime.now(UTC) + timedelta(days=30)
    wrong_key = dsse.public_text(dsse.generate_key())
    vectors: list[tuple[str, bytes, str, datetime | None, str]] = [
        ("good", good, log_key, None, "OK"),
        ("export swapped", _edit(good, lambda f: f.update({IMC: read_tar(other)[IMC]})),
         log_key, None, "EXPORT"),
        ("forged export, header kept", _edit(good, forged_bhv), log_key, None, "EXPORT"),
        ("export removed", _edit(good, lambda f: f.pop(IMC)), log_key, None, "EXPORT"),
        ("orders byte changed", _edit(good, orders_byte), log_key, None, "ORDERS"),
        ("envelope from another version", _edit(good, lambda f: f.update(
            {"approval.dsse.json": read_tar(other)["approval.dsse.json"]})),
         log_key, None, "ENVELOPE"),
        ("revoked approval", revoked, log_key, None, "REVOKED"),
        ("wrong log key", good, wrong_key, None, "CHECKPOINT"),
        ("bad receipt", _edit(good, receipt), log_key, None, "RECEIPT"),
        ("bad proof", _edit(good, proof), log_key, None, "PROOF"),
        ("expired checkpoint", good, log_key, later, "EXPIRED"),
        ("checkpoint timestamped in the future", good, log_key,
         datetime.now(UTC) - timedelta(hours=1), "EXPIRED"),
        ("timestamp stripped, receipts old", _edit(good, strip_stamp), log_key, later,
         "EXPIRED"),
        ("not a package", b"hello", log_key, None, "FORMAT"),
    ]
    tool = standalone_verifier()
    verdicts = {}
    for name, data, key, now, expected in vectors:
        main_verdict = verify_package(data, log_key=key, now=now)
        ok, code, message = tool.verify(data, key, now)
        assert ok == main_verdict.ok
        verdicts[name] = (expected, main_verdict.code, code)
        assert main_verdict.message and message
    assert all(e == m == s for e, m, s in verdicts.values()), verdicts

    # The command lines: countersign vehicle verify, and the tool as a vehicle runs it.
    path = tmp_path / "good.tar"
    path.write_bytes(good)
    bad = tmp_path / "swapped.tar"
    bad.write_bytes(vectors[1][1])
    assert main(["vehicle", "verify", str(path), "--log-key", log_key]) == 0
    assert main(["vehicle", "verify", str(bad), "--log-key", log_key]) == 1
    run = subprocess.run([sys.executable, str(TOOL), str(bad), "--log-key", log_key],
                         capture_output=True, text=True, timeout=120, check=False)
    assert run.returncode == 1 and run.stdout.startswith("REFUSED EXPORT:"), run.stdout


@pytest.mark.parametrize("role", ["operator", "auditor"])
def test_an_unapproved_version_has_no_package(world: World, role: str) -> None:
    number = new_version(world)
    response = world.client(role).get(f"/api/missions/{MISSION}/versions/{number}/package")
    assert response.status_code == 409


def test_executions_are_checked_and_recorded_in_the_log(world: World) -> None:
    supervisor = world.client("supervisor")
    signer = register_key(supervisor)
    number = new_version(world)
    base = f"/api/missions/{MISSION}/versions/{number}/executions"
    steps = [("G1", "violate"), ("G4", "succeed"), ("G5", "succeed")]
    log = evidenced_log(steps)  # times and readings: the evidence "no deviation" needs
    operator = world.client("operator")
    assert operator.post(base, json={"log": log}).status_code == 409  # not approved yet
    approve(world, supervisor, signer, submit(world, number))
    response = operator.post(base, json={"log": log})
    assert response.status_code == 201, response.text
    body = response.json()
    assert body["ok"] and body["terminal"] == "COMPLETE"
    assert body["summary"] == f"executed as path {body['path']} to COMPLETE, no deviation"
    last = json.loads(log.splitlines()[-1])
    last["readings"]["depth_m"] = 12
    bad = "".join(line + "\n" for line in [*log.splitlines()[:-1], json.dumps(last)])
    deviated = supervisor.post(base, json={"log": bad}).json()
    assert deviated["deviations"][0]["code"] == "CONSTRAINT"
    entries = world.client("auditor").get("/api/log/entries").json()
    recorded = [json.loads(e["entry"])["event"] for e in entries
                if json.loads(e["entry"])["event"]["kind"] == "execution.recorded"]
    assert [r["detail"]["ok"] for r in recorded] == [True, False]
    assert recorded[0]["detail"]["path"] == body["path"]
    assert world.client("auditor").post(base, json={"log": log}).status_code == 403
    assert operator.post(base, json={"log": "nonsense"}).status_code == 422


def test_freshness_is_the_checkpoints_timestamp_not_the_logs_last_entry(world: World) -> None:
    """A log quiet for a month does not expire a package made today; a package made a month
    ago expires, whatever the log did since."""
    supervisor = world.client("supervisor")
    signer = register_key(supervisor)
    number = new_version(world)
    approve(world, supervisor, signer, submit(world, number))
    log_key = world.client("auditor").get("/api/log/checkpoint").json()["public_key"]
    month = datetime.now(UTC) + timedelta(days=30)
    with world.database.session() as db:
        quiet = build_package(package_parts(db, mission_id=MISSION, number=number,
                                            signer=world.database.log_signer, now=month))
    tool = standalone_verifier()
    for data, now, expected in ((quiet, month, "OK"), (_package(world, number), month,
                                                       "EXPIRED")):
        assert verify_package(data, log_key=log_key, now=now).code == expected
        assert tool.verify(data, log_key, now)[1] == expected
    short = verify_package(quiet, log_key=log_key, now=month + timedelta(hours=2),
                           max_age=timedelta(hours=1))
    assert short.code == "EXPIRED" and "window of 0.0416667 day(s)" in short.message


def test_a_forged_stamp_is_a_bad_checkpoint(world: World) -> None:
    supervisor = world.client("supervisor")
    signer = register_key(supervisor)
    number = new_version(world)
    approve(world, supervisor, signer, submit(world, number))
    log_key = world.client("auditor").get("/api/log/checkpoint").json()["public_key"]
    good = _package(world, number)

    def bump(files: dict[str, bytes]) -> None:
        note = files["log/checkpoint"].decode().split("\n")
        name, blob = note[-2].rsplit(" ", 1)
        raw = bytearray(dsse.unb64(blob, "stamp"))
        raw[11] ^= 1  # one second later, same signature
        note[-2] = f"{name} {dsse.b64(bytes(raw))}"
        files["log/checkpoint"] = "\n".join(note).encode()

    forged = _edit(good, bump)
    assert verify_package(forged, log_key=log_key).code == "CHECKPOINT"
    assert standalone_verifier().verify(forged, log_key)[1] == "CHECKPOINT"


def test_an_approval_signed_without_export_digests_still_verifies(
        world: World, monkeypatch: pytest.MonkeyPatch, tmp_path: Path) -> None:
    """Statements signed before they carried export digests: the main verifier rebuilds the
    exports as before; the standalone one refuses unless told to trust the manifest."""
    from countersign.store.approvals import decisions

    monkeypatch.setattr(decisions, "export_digests", lambda *a, **k: None)
    supervisor = world.client("supervisor")
    signer = register_key(supervisor)
    number = new_version(world)
    approve(world, supervisor, signer, submit(world, number))
    log_key = world.client("auditor").get("/api/log/checkpoint").json()["public_key"]
    old = _package(world, number)
    envelope = json.loads(read_tar(old)["approval.dsse.json"])
    assert "exports" not in json.loads(dsse.unb64(envelope["payload"], "p"))["predicate"]
    assert verify_package(old, log_key=log_key).code == "OK"
    tool = standalone_verifier()
    refused = tool.verify(old, log_key)
    assert refused[1] == "EXPORT" and "signs no export digests" in refused[2]
    assert tool.verify(old, log_key, trust_manifest=True)[1] == "OK"
    forged = _edit(old, lambda f: f.update({IMC: read_tar(old)[IMC] + b"x"}))
    assert verify_package(forged, log_key=log_key).code == "EXPORT"
    assert tool.verify(forged, log_key, trust_manifest=True)[1] == "OK"  # why it is refused


def test_new_statements_sign_every_export(world: World) -> None:
    supervisor = world.client("supervisor")
    signer = register_key(supervisor)
    number = new_version(world)
    approve(world, supervisor, signer, submit(world, number))
    files = read_tar(_package(world, number))
    payload = dsse.unb64(json.loads(files["approval.dsse.json"])["payload"], "p")
    signed = json.loads(payload)["predicate"]["exports"]
    import hashlib

    assert signed == {n: "sha256:" + hashlib.sha256(c).hexdigest()
                      for n, c in files.items() if n.startswith("vehicle/")}
    assert set(signed) == {IMC, BHV, f"vehicle/{MISSION}.moos"}


@pytest.mark.parametrize("exports", [["sha256:" + "0" * 64], {IMC: 1}, None])
def test_a_signed_statement_with_malformed_export_digests_is_refused_alike(
        world: World, monkeypatch: pytest.MonkeyPatch, exports: object) -> None:
    """A statement whose signature holds but whose export digests are not a name -> digest
    map (a server that stored it unchecked): both verifiers name the same fault."""
    from countersign.approvals.statement import _statement_json
    from countersign.store.approvals import decisions

    monkeypatch.setattr(decisions, "export_digests", lambda *a, **k: exports)
    if exports is None:  # the field present and null, not absent
        monkeypatch.setattr(decisions, "build_statement", _with_null_exports(
            decisions.build_statement))
    monkeypatch.setattr(decisions, "parse_statement", _statement_json)
    supervisor = world.client("supervisor")
    signer = register_key(supervisor)
    number = new_version(world)
    approve(world, supervisor, signer, submit(world, number))
    log_key = world.client("auditor").get("/api/log/checkpoint").json()["public_key"]
    package = _package(world, number)
    payload = dsse.unb64(json.loads(read_tar(package)["approval.dsse.json"])["payload"], "p")
    assert json.loads(payload)["predicate"]["exports"] == exports
    main_verdict = verify_package(package, log_key=log_key)
    ok, code, _ = standalone_verifier().verify(package, log_key)
    assert (main_verdict.ok, main_verdict.code) == (ok, code) == (False, "SIGNATURE")
    assert standalone_verifier().verify(package, log_key, trust_manifest=True)[1] == "SIGNATURE"


def _with_null_exports(build: Callable[..., dict[str, Any]]) -> Callable[..., dict[str, Any]]:
    def build_with_null(**fields: Any) -> dict[str, Any]:
        statement = build(**fields)
        if fields.get("decision") == "approved":
            statement["predicate"]["exports"] = None
        return statement
    return build_with_null
