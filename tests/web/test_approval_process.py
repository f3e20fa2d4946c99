"""Against a real server process: `countersign keygen | sign | audit verify` end to end, and
crash safety (killing the server's processes during approvals leaves each approval complete
with its log entry, or absent)."""

from __future__ import annotations

import argparse
import json
import os
import random
import signal
import subprocess
import sys
import threading
import time
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import Any

import httpx
import pytest
from sqlalchemy import text

from countersign.approvals import dsse
from countersign.cli import approvals as cli_approvals

from ..ports import free_port
from ..processes import children
from .approval_helpers import MISSION, sign_prepared
from .conftest import PASSWORD, World


def _parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(prog="countersign")
    cli_approvals.add_commands(parser.add_subparsers(dest="command", required=True))
    return parser


def run_cli(*argv: str) -> int:
    args = _parser().parse_args(list(argv))
    code: int = args.handler(args)
    return code


@contextmanager
def server_process(database_url: str, data_dir: Path, *,
                   workers: int = 1) -> Iterator[tuple[str, subprocess.Popen[bytes]]]:
    port = free_port()
    # One log has one signer: the server shares the log key directory of the `world` fixture's
    # app (tmp_path/log-signer), which receipted the entries the fixture appended.
    env = {**os.environ, "COUNTERSIGN_DATABASE_URL": database_url,
           "COUNTERSIGN_LOG_KEY_DIR": str(data_dir.parent / "log-signer")}
    several = ["--workers", str(workers), "--shared-socket"] if workers > 1 else []
    process = subprocess.Popen(
        [sys.executable, "-m", "countersign.cli", "serve", "--port", str(port), "--data-dir",
         str(data_dir), *several], env=env, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    url = f"http://127.0.0.1:{port}"
    try:
        _wait_answering(url, process)
        yield url, process
    finally:
        if process.poll() is None:
            process.send_signal(signal.SIGTERM)
            try:
                process.wait(timeout=15)
            except subprocess.TimeoutExpired:
                process.kill()
                process.wait()


def _wait_answering(url: str, process: subprocess.Popen[bytes]) -> None:
    deadline = time.monotonic() + 180  # a loaded machine starts a server slowly
    while True:
        try:
            if httpx.get(f"{url}/api/health", timeout=1).status_code == 200:
                return
        except httpx.HTTPError:
            pass
        assert process.poll() is None, "the server exited"
        assert time.monotonic() < deadline, "the server did not start"
        time.sleep(0.1)


def _app_processes(master: int) -> list[int]:
    """The server processes gunicorn forked from `master`: its children other than the
    validation host and its helpers (started by multiprocessing)."""
    found = []
    for pid in children(master):
        try:
            if b"multiprocessing" not in Path(f"/proc/{pid}/cmdline").read_bytes():
                found.append(pid)
        except OSError:
            continue
    return found


def _client(url: str, token: str) -> httpx.Client:
    return httpx.Client(base_url=url, headers={"Authorization": f"Bearer {token}"}, timeout=60)


def _submission(operator: httpx.Client) -> int:
    number = operator.post(f"/api/missions/{MISSION}/versions").json()["number"]
    response = operator.post(f"/api/missions/{MISSION}/versions/{number}/submit")
    assert response.status_code == 201, response.text
    return int(response.json()["id"])


def test_keygen_sign_and_audit_verify(world: World, database_url: str, tmp_path: Path,
                                      capsys: pytest.CaptureFixture[str],
                                      monkeypatch: pytest.MonkeyPatch) -> None:
    key_file = tmp_path / "supervisor.pem"
    assert run_cli("keygen", "--out", str(key_file)) == 0
    assert key_file.stat().st_mode & 0o777 == 0o600
    printed = capsys.readouterr().out
    public = printed.split("public key:")[1].split()[0]
    assert run_cli("keygen", "--out", str(key_file)) == 2  # never overwritten
    assert "exists" in capsys.readouterr().err

    with server_process(database_url, tmp_path / "server") as (url, _):
        supervisor = _client(url, world.tokens["supervisor"])
        response = supervisor.post("/api/keys", json={"public_key": public,
                                                      "password": PASSWORD})
        assert response.status_code == 201, response.text
        submission = _submission(_client(url, world.tokens["operator"]))
        monkeypatch.setenv("COUNTERSIGN_TOKEN", world.tokens["supervisor"])
        password_file = tmp_path / "password"
        password_file.write_text(PASSWORD + "\n")
        monkeypatch.setattr("getpass.getpass", lambda prompt="": "not the password")
        # Without the right password a validly signed decision is refused.
        assert run_cli("sign", "--server", url, "--key", str(key_file), "--submission",
                       str(submission), "--decision", "approved") == 1
        assert "password is wrong" in capsys.readouterr().err
        monkeypatch.setattr("getpass.getpass", lambda prompt="": PASSWORD)
        assert run_cli("sign", "--server", url, "--key", str(key_file), "--submission",
                       str(submission), "--decision", "approved", "--password-file",
                       str(password_file)) == 0
        out = capsys.readouterr().out
        assert out.startswith(f"approved: {MISSION} version 1 (sha256:")
        # The same decision again: refused, with the server's reason.
        assert run_cli("sign", "--server", url, "--key", str(key_file), "--submission",
                       str(submission), "--decision", "approved") == 1
        assert "is approved" in capsys.readouterr().err
        auditor = _client(url, world.tokens["auditor"])
        bundle = auditor.get("/api/audit/bundle").json()
        checkpoint = auditor.get("/api/log/checkpoint").json()

    path = tmp_path / "bundle.json"
    path.write_text(json.dumps(bundle))
    published = tmp_path / "checkpoint.json"
    published.write_text(json.dumps(checkpoint))
    assert run_cli("audit", "verify", str(path), "--log-key", checkpoint["public_key"],
                   "--checkpoint", str(published)) == 0
    assert capsys.readouterr().out.startswith("OK: ")
    digest = next(iter(bundle["orders"]))
    bundle["orders"][digest]["goals"][0]["title"] = "Search Area B"
    path.write_text(json.dumps(bundle))
    assert run_cli("audit", "verify", str(path), "--format", "json") == 1
    report = json.loads(capsys.readouterr().out)
    assert not report["ok"] and "do not hash to the signed digest" in report["problems"][0]
    path.write_text("{not json")
    assert run_cli("audit", "verify", str(path)) == 2


def _invariants(world: World) -> dict[str, int]:
    with world.database.engine.connect() as connection:
        def one(sql: str) -> int:
            return int(connection.execute(text(sql)).scalar_one())

        approvals = one("SELECT count(*) FROM approvals")
        assert approvals == one("SELECT count(*) FROM events WHERE kind LIKE 'approval.%'")
        assert one("SELECT count(*) FROM events") == one("SELECT count(*) FROM log_entries")
        assert one("SELECT count(*) FROM approvals a JOIN log_entries l ON "
                   "l.event_id = a.event_id") == approvals
        assert one("SELECT count(*) FROM submissions WHERE state = 'approved'") == approvals
        assert one("SELECT coalesce(max(tree_size), 0) FROM checkpoints") <= one(
            "SELECT count(*) FROM log_entries")
        return {"approvals": approvals}


def test_killing_the_server_during_approvals(world: World, database_url: str,
                                             tmp_path: Path) -> None:
    """Eight approvals, each but the first with every server process killed (SIGKILL: no
    shutdown, no cleanup) at a random moment from before the request arrives to just after it
    would finish. The processes that serve the app are gunicorn's workers; its master, which
    holds no database connection, forks new ones, so that a round costs a fork, not the start
    of a Python server (9 starts made this the suite's third-longest test)."""
    data_dir = tmp_path / "server"
    key = dsse.generate_key()
    outcomes: list[str] = []
    rng = random.Random(6)
    duration = 0.0
    with server_process(database_url, data_dir, workers=2) as (url, master):
        for round_number in range(8):
            supervisor = _client(url, world.tokens["supervisor"])
            if round_number == 0:
                assert supervisor.post("/api/keys", json={
                    "public_key": dsse.public_text(key), "password": PASSWORD}).status_code == 201
            submission = _submission(_client(url, world.tokens["operator"]))
            prepared = supervisor.post(f"/api/submissions/{submission}/statement", json={
                "decision": "approved", "key_id": dsse.key_id(key.public_key())}).json()
            envelope = sign_prepared(prepared, _Signer(key))
            result: dict[str, Any] = {}

            def send(envelope: str = envelope, submission: int = submission,
                     result: dict[str, Any] = result,
                     supervisor: httpx.Client = supervisor) -> None:
                try:
                    result["status"] = supervisor.post(
                        f"/api/submissions/{submission}/decision",
                        json={"envelope": envelope, "password": PASSWORD}).status_code
                except httpx.HTTPError as exc:
                    result["error"] = type(exc).__name__

            if round_number == 0:  # calibrate: how long does an approval take here?
                started = time.monotonic()
                send()
                duration = time.monotonic() - started
                assert result["status"] == 201
                outcomes.append("201 (not killed)")
                _invariants(world)
                continue
            serving = _app_processes(master.pid)
            assert len(serving) == 2, serving
            sender = threading.Thread(target=send)
            sender.start()
            time.sleep(rng.uniform(0, 1.3 * duration))
            for pid in serving:
                os.kill(pid, signal.SIGKILL)
            sender.join(timeout=30)
            outcomes.append(str(result.get("status", result.get("error"))))
            _invariants(world)
            # The master forks new server processes; the next round waits for them.
            deadline = time.monotonic() + 180
            while set(_app_processes(master.pid)) & set(serving) or len(
                    _app_processes(master.pid)) < 2:
                assert time.monotonic() < deadline, "gunicorn forked no new server processes"
                time.sleep(0.05)
            _wait_answering(url, master)
        # Server processes started after the crashes serve a bundle that verifies.
        bundle = _client(url, world.tokens["auditor"]).get("/api/audit/bundle").json()
    from countersign.approvals.bundle import verify_bundle

    report = verify_bundle(bundle)
    assert report.ok, (report.problems, outcomes)
    assert report.approvals == _invariants(world)["approvals"]
    # Every acknowledged approval survived; the others are complete or absent (checked above).
    assert report.approvals >= sum(o.startswith("201") for o in outcomes)
    print("decisions during kills:", outcomes, "stored:", report.approvals)


class _Signer:
    def __init__(self, key: Any) -> None:
        self.key = key
        self.key_id = dsse.key_id(key.public_key())
