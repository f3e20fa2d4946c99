"""Audit benchmark.

1. Offline verification of a bundle with a 10,000-event log and 1,000 signed approvals (each
   over its own orders), target < 3 s, against a naive verifier that rebuilds the whole Merkle
   tree (RFC 6962 recursion) to check each approval's inclusion.
2. Server-side inclusion proofs for random entries of a 10,000-event log stored in the database
   (SQLite, and PostgreSQL when COUNTERSIGN_TEST_POSTGRES_URL is set), target < 10 ms, against
   a naive server that loads every leaf and recomputes the tree for each proof.

3.: the same bundle verified with every entry's receipt, 10 checkpoints and a state
   file (consistency from a head seen before); a witness round (fetch, consistency proof,
   cosign, post) against an in-process server with a 10,000-event log; and the latency of a
   signed decision with its receipt (POST /decision, median and p95).

Run: .venv/bin/python -m tests.bench.bench_audit [--events 10000] [--approvals 1000]
"""

from __future__ import annotations

import argparse
import gc
import json
import os
import random
import statistics
import tempfile
import time
from collections.abc import Callable
from datetime import UTC, datetime, timedelta
from pathlib import Path
from typing import Any

from sqlalchemy import select, text

from countersign.approvals import dsse
from countersign.approvals.bundle import BUNDLE_FORMAT, verify_bundle
from countersign.approvals.log import GENESIS, entry_bytes, entry_leaf, event_data, sign_checkpoint
from countersign.approvals.merkle import Tree, leaf_hash, node_hash, verify_inclusion
from countersign.approvals.note import Head
from countersign.approvals.receipt import make_receipt
from countersign.approvals.statement import build_statement, json_digest, statement_bytes
from countersign.approvals.statement import json_digest as orders_digest
from countersign.orders.examples import example_bytes
from countersign.store import approvals as service
from countersign.store.db import Database, make_engine
from countersign.store.events import record
from countersign.store.tables import LogEntry

SUPERVISORS = 5
ORIGIN = "countersign.bench/0000000000000000"


def timed(action: Callable[[], Any]) -> tuple[float, Any]:
    gc.collect()
    start = time.perf_counter()
    result = action()
    return time.perf_counter() - start, result


def build_bundle(events: int, approvals: int) -> dict[str, Any]:
    """A realistic bundle made with the same pure functions as the server."""
    log_key = dsse.generate_key()
    keys = [dsse.generate_key() for _ in range(SUPERVISORS)]
    base = json.loads(example_bytes("search-and-sample"))
    start = datetime(2026, 1, 1, tzinfo=UTC)
    # The log first creates the supervisors (the system, as `countersign users create` does:
    # a decision by someone the log never made a supervisor is a problem), then their keys.
    accounts = 2 * SUPERVISORS
    every = max(1, (events - accounts) // approvals)
    texts: list[str] = []
    orders: dict[str, Any] = {}
    bundled: list[dict[str, Any]] = []
    prev = GENESIS
    made = 0
    for index in range(events):
        at = start + timedelta(seconds=index)
        kind, detail, actor, mission = "draft.updated", {"revision": index}, "operator1", None
        envelope_text = None
        if index < SUPERVISORS:
            kind, actor = "user.created", None
            detail = {"user": f"supervisor{index}", "role": "supervisor"}
        elif index < accounts:
            public = dsse.public_text(keys[index - SUPERVISORS])
            kind, actor = "key.registered", f"supervisor{index - SUPERVISORS}"
            detail = {"key_id": dsse.key_id(public), "public_key": public, "user": actor}
        elif (index - accounts) % every == every - 1 and made < approvals:
            data = dict(base, title=f"Search and sample, version {made}")
            digest = orders_digest(data)
            orders[digest] = data
            signer = made % SUPERVISORS
            statement = build_statement(
                mission="search-and-sample", version=made + 1, orders_digest=digest,
                decision="approved", reason="", submission=made + 1,
                report_digest="sha256:" + "0" * 64, paths={"count": 75}, vehicle="remus-100",
                author="operator1", supervisor=f"supervisor{signer}",
                key_id=dsse.key_id(keys[signer].public_key()), time=at.isoformat(),
                nonce=f"{made:032x}")
            envelope_text = json.dumps(dsse.sign_envelope(statement_bytes(statement),
                                                          keys[signer]))
            kind, actor, mission = "approval.approved", f"supervisor{signer}", "search-and-sample"
            detail = {"decision": "approved", "envelope_digest": dsse.envelope_digest(
                envelope_text), "payload_digest": json_digest(statement), "orders_digest": digest}
            made += 1
        data_bytes = entry_bytes(index, prev, event_data(
            id=index + 1, at=at, actor=actor, kind=kind, mission=mission, before=None,
            after=None, detail=detail))
        texts.append(data_bytes.decode())
        prev = entry_leaf(data_bytes)
        if envelope_text is not None:
            bundled.append({"id": made, "log_index": index, "envelope": envelope_text})
    tree = Tree(leaf_hash(t.encode()) for t in texts)
    checkpoint = sign_checkpoint(log_key, tree.size, tree.root(), origin=ORIGIN)
    # Ten checkpoints along the log, as the signer publishes them while it grows.
    checkpoints = [sign_checkpoint(log_key, size, tree.root(size), origin=ORIGIN)
                   for size in range(events // 10, events, events // 10)] + [checkpoint]
    receipts = [make_receipt(log_key, ORIGIN, i, tree.levels[0][i].hex(), "2026-01-01T00:00:00Z")
                for i in range(tree.size)]
    for approval in bundled:
        approval["inclusion"] = {"index": approval["log_index"], "size": tree.size, "hashes": [
            h.hex() for h in tree.inclusion_proof(approval["log_index"])]}
    return {"format": BUNDLE_FORMAT, "log_key": {"public_key": checkpoint["public_key"],
                                                 "origin": ORIGIN},
            "entries": texts, "checkpoints": checkpoints, "receipts": receipts, "keys": [],
            "orders": orders, "approvals": bundled}


def _naive_root(leaves: list[bytes]) -> bytes:
    if len(leaves) == 1:
        return leaves[0]
    k = 1
    while k * 2 < len(leaves):
        k *= 2
    return node_hash(_naive_root(leaves[:k]), _naive_root(leaves[k:]))


def _naive_proof(leaves: list[bytes], index: int) -> list[bytes]:
    if len(leaves) == 1:
        return []
    k = 1
    while k * 2 < len(leaves):
        k *= 2
    if index < k:
        return [*_naive_proof(leaves[:k], index), _naive_root(leaves[k:])]
    return [*_naive_proof(leaves[k:], index - k), _naive_root(leaves[:k])]


def naive_inclusion_checks(bundle: dict[str, Any], count: int) -> None:
    """What a verifier without a tree does: rehash every entry and rebuild the whole tree for
    each approval it checks."""
    root = bytes.fromhex(bundle["checkpoints"][-1]["root"])
    for approval in bundle["approvals"][:count]:
        leaves = [leaf_hash(t.encode()) for t in bundle["entries"]]
        assert _naive_root(leaves) == root
        index = approval["log_index"]
        assert verify_inclusion(leaves[index], index, len(leaves),
                                _naive_proof(leaves, index), root)


def bench_offline(events: int, approvals: int) -> None:
    print(f"\n## Offline verification: {events:,} events, {approvals:,} approvals")
    made, bundle = timed(lambda: build_bundle(events, approvals))
    size = len(json.dumps(bundle)) / 1e6
    print(f"bundle built in {made:.1f} s ({size:.1f} MB JSON)")
    with tempfile.TemporaryDirectory() as folder:
        path = Path(folder) / "bundle.json"
        path.write_text(json.dumps(bundle))
        seconds, report = timed(lambda: verify_bundle(json.loads(path.read_bytes())))
        middle = bundle["checkpoints"][4]
        seen = {ORIGIN: Head(ORIGIN, middle["size"], bytes.fromhex(middle["root"]))}
        with_state, stated = timed(lambda: verify_bundle(
            json.loads(path.read_bytes()), trusted_log_key=bundle["log_key"]["public_key"],
            published=bundle["checkpoints"][:-1], seen=seen))
    assert report.ok, report.problems[:5]
    assert stated.ok, stated.problems[:5]
    print(f"{'verify + receipts + 10 checkpoints + state':<44} {with_state:8.2f} s   (every "
          f"entry's receipt, consistency from 9 published heads and the state's)")
    assert report.approvals == approvals and report.entries == events
    sample = min(20, approvals)
    naive_sample, _ = timed(lambda: naive_inclusion_checks(bundle, sample))
    naive = naive_sample / sample * approvals
    print(f"{'verify (read + parse + every check)':<44} {seconds:8.2f} s   target < 3 s: "
          f"{'PASS' if seconds < 3 else 'FAIL'}")
    print(f"{'naive: rebuild tree per approval':<44} {naive:8.2f} s   (measured on {sample}, "
          f"scaled to {approvals:,}; inclusion checks only)")
    print(f"{'ratio naive / ours':<44} {naive / seconds:8.1f} x")


def _populate(url: str, events: int) -> Database:
    if url.startswith("postgresql"):
        engine = make_engine(url)
        with engine.begin() as connection:
            connection.execute(text("DROP SCHEMA public CASCADE"))
            connection.execute(text("CREATE SCHEMA public"))
        engine.dispose()
    database = Database(url)
    database.migrate()
    with database.session() as db:
        for index in range(events):
            record(db, kind="draft.updated", actor=None, mission_id="bench",
                   detail={"revision": index}, signer=database.log_signer)
    return database


def bench_server(url: str, label: str, events: int) -> None:
    print(f"\n## Server inclusion proofs, {label}, {events:,} events")
    populate, database = timed(lambda: _populate(url, events))
    print(f"log written through record() in {populate:.1f} s "
          f"({populate / events * 1000:.2f} ms per event)")
    rng = random.Random(6)
    indexes = [rng.randrange(events) for _ in range(200)]
    with database.session(write=False) as db:
        cold, _ = timed(lambda: service.inclusion_proof(db, index=indexes[0]))
        times = []
        for index in indexes:
            seconds, proof = timed(lambda index=index: service.inclusion_proof(db, index=index))
            times.append(seconds)
        assert verify_inclusion(bytes.fromhex(proof["leaf_hash"]), proof["index"],
                                proof["size"], [bytes.fromhex(h) for h in proof["hashes"]],
                                bytes.fromhex(proof["root"]))

        def naive(index: int) -> None:
            leaves = [bytes.fromhex(h) for h in db.scalars(
                select(LogEntry.leaf_hash).order_by(LogEntry.index))]
            _naive_proof(leaves, index)
            _naive_root(leaves)

        naive_times = [timed(lambda index=index: naive(index))[0] for index in indexes[:10]]
    database.engine.dispose()
    ours = statistics.median(times)
    worst = max(times)
    baseline = statistics.median(naive_times)
    print(f"{'first proof (builds the tree cache)':<44} {cold * 1000:8.2f} ms")
    print(f"{'proof, median of 200 random entries':<44} {ours * 1000:8.2f} ms   target < 10 ms: "
          f"{'PASS' if worst < 0.010 else 'FAIL'} (max {worst * 1000:.2f} ms)")
    print(f"{'naive: load all leaves, rebuild per proof':<44} {baseline * 1000:8.2f} ms")
    print(f"{'ratio naive / ours':<44} {baseline / ours:8.1f} x")


def bench_witness_and_decisions(rounds: int, events: int) -> None:
    """A witness round and decision latency against an in-process server (SQLite)."""
    from fastapi.testclient import TestClient

    from countersign.cli.witness import witness_round
    from countersign.orders.examples import load_example
    from countersign.settings import Settings
    from countersign.store.accounts import create_token, create_user
    from countersign.store.missions import create_mission
    from countersign.web.app import create_app

    print(f"\n## Witness round and decision latency with receipt (SQLite, {events:,} events)")
    with tempfile.TemporaryDirectory() as folder:
        url = f"sqlite:///{folder}/bench.db"
        database = Database(url)
        app = create_app(Settings(data_dir=Path(folder), database_url=url), database)
        tokens = {}
        with database.session() as db:
            for role in ("operator", "supervisor", "auditor"):
                user = create_user(db, username=f"{role}1", role=role,
                                   password="benchmark password", signer=database.log_signer)
                tokens[role] = create_token(db, user=user, name="bench",
                                            signer=database.log_signer)[1]
                if role == "operator":
                    create_mission(db, orders=load_example("search-and-sample"), author=user,
                                   signer=database.log_signer)
            for index in range(events):
                record(db, kind="draft.updated", actor=None, mission_id="bench",
                       detail={"revision": index}, signer=database.log_signer)

        def client(role: str) -> TestClient:
            return TestClient(app, headers={"Authorization": f"Bearer {tokens[role]}"})

        operator, supervisor, auditor = client("operator"), client("supervisor"), client("auditor")
        key = dsse.generate_key()
        kid = supervisor.post("/api/keys", json={"public_key": dsse.public_text(key),
                                                 "password": "benchmark password"}
                              ).json()["key_id"]
        decisions: list[float] = []
        for _ in range(rounds):
            number = operator.post("/api/missions/search-and-sample/versions").json()["number"]
            sub = operator.post(f"/api/missions/search-and-sample/versions/{number}/submit"
                                ).json()["id"]
            prepared = supervisor.post(f"/api/submissions/{sub}/statement", json={
                "decision": "approved", "reason": "", "key_id": kid}).json()
            envelope = json.dumps(dsse.sign_envelope(dsse.unb64(prepared["payload"], "p"), key))
            began = time.perf_counter()
            # A decision needs the supervisor's password again.
            stored = supervisor.post(f"/api/submissions/{sub}/decision",
                                     json={"envelope": envelope,
                                           "password": "benchmark password"})
            decisions.append(time.perf_counter() - began)
            assert stored.status_code == 201 and stored.json()["receipt"], stored.text

        def get(path: str) -> dict[str, Any]:
            data: dict[str, Any] = auditor.get(path).json()
            return data

        def post(path: str, body: dict[str, Any]) -> dict[str, Any]:
            data: dict[str, Any] = auditor.post(path, json=body).json()
            return data

        witness_key = dsse.generate_key()
        from countersign.approvals.note import COSIGNATURE, verifier_key
        (database.log_signer.directory / "witnesses").write_text(verifier_key(  # type: ignore[union-attr]
            "witness.bench", dsse.raw_public(witness_key.public_key()), COSIGNATURE) + "\n")
        log_key = get("/api/log/checkpoint")["public_key"]
        state = Path(folder) / "witness.json"
        witness_round(get, post, log_key=log_key, state=state, key=witness_key,
                      name="witness.bench")
        times = []
        for _ in range(rounds):
            operator.post("/api/missions/search-and-sample/versions")  # the log grows
            seconds, result = timed(lambda: witness_round(
                get, post, log_key=log_key, state=state, key=witness_key, name="witness.bench"))
            assert result.ok, result.lines
            times.append(seconds)
        app.state.rehearsals.shutdown()
        database.engine.dispose()
    print(f"{'witness round (checkpoint, proof, cosign)':<44} "
          f"{statistics.median(times) * 1000:8.1f} ms median, p95 "
          f"{percentile(times, 0.95) * 1000:.1f} ms ({rounds} rounds)")
    print(f"{'decision with receipt (POST /decision)':<44} "
          f"{statistics.median(decisions) * 1000:8.1f} ms median, p95 "
          f"{percentile(decisions, 0.95) * 1000:.1f} ms ({rounds} decisions)")


def percentile(values: list[float], q: float) -> float:
    ordered = sorted(values)
    return ordered[min(len(ordered) - 1, int(q * len(ordered)))]


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--events", type=int, default=10_000)
    parser.add_argument("--approvals", type=int, default=1_000)
    parser.add_argument("--rounds", type=int, default=40)
    args = parser.parse_args()
    bench_offline(args.events, args.approvals)
    bench_witness_and_decisions(args.rounds, args.events)
    with tempfile.TemporaryDirectory() as folder:
        bench_server(f"sqlite:///{folder}/bench.db", "SQLite", args.events)
    postgres = os.environ.get("COUNTERSIGN_TEST_POSTGRES_URL")
    if postgres:
        bench_server(postgres, "PostgreSQL", args.events)
    else:
        print("\n(PostgreSQL skipped: set COUNTERSIGN_TEST_POSTGRES_URL)")


if __name__ == "__main__":
    main()
