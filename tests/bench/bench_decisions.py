"""Decision latency with the fresh-password check.

Times `POST /api/submissions/{id}/decision` (envelope + password: argon2 verify, signature
check, row lock, log append, checkpoint) against the same request's work without the password
check, over N submissions on a fresh SQLite database (PostgreSQL when
COUNTERSIGN_TEST_POSTGRES_URL is set). Prints median and p95; asserts nothing about time.

Run: .venv/bin/python -m tests.bench.bench_decisions [--rounds 40]
"""

from __future__ import annotations

import argparse
import os
import statistics
import tempfile
import time
from pathlib import Path

from fastapi.testclient import TestClient

from countersign.orders.examples import load_example
from countersign.settings import MAX_PASSWORD_CHECKS, Settings
from countersign.store import login_throttle
from countersign.store.accounts import create_token, create_user
from countersign.store.db import Database
from countersign.store.hashing import HASHER
from countersign.store.missions import create_mission
from countersign.web.app import create_app
from tests.web.approval_helpers import Signer, prepare, register_key, sign_prepared

PASSWORD = "correct horse battery staple"
MISSION = "search-and-sample"


def _no_hash(_hash: str | bytes, _password: str | bytes) -> bool:
    return True


def _percentile(values: list[float], fraction: float) -> float:
    ordered = sorted(values)
    return ordered[min(len(ordered) - 1, round(fraction * (len(ordered) - 1)))]


def run(rounds: int, skip_password: bool, url: str | None, data_dir: Path) -> list[float]:
    url = url or f"sqlite:///{data_dir / 'bench.sqlite'}"
    database = Database(url)
    app = create_app(Settings(data_dir=data_dir, database_url=url), database)
    with database.session() as db:
        operator = create_user(db, username="op", role="operator", password=PASSWORD,
                               signer=database.log_signer)
        supervisor = create_user(db, username="sup", role="supervisor", password=PASSWORD,
                                 signer=database.log_signer)
        create_mission(db, orders=load_example(MISSION), author=operator,
                       signer=database.log_signer)
        tokens = {"op": create_token(db, user=operator, name="b", signer=database.log_signer)[1],
                  "sup": create_token(db, user=supervisor, name="b", signer=database.log_signer)[1]}
    op, sup = TestClient(app), TestClient(app)
    op.headers["Authorization"] = f"Bearer {tokens['op']}"
    sup.headers["Authorization"] = f"Bearer {tokens['sup']}"
    # One supervisor decides every round: past the default 10 password checks a minute the
    # account throttle answers 429. This measures a decision's latency, not the throttle, so
    # at the limit a deployment may set (COUNTERSIGN_PASSWORD_CHECKS_PER_MINUTE).
    login_throttle.ACCOUNT_HASHES_PER_MINUTE = MAX_PASSWORD_CHECKS
    signer: Signer = register_key(sup)
    if skip_password:  # the same request without the argon2 check, for comparison
        HASHER.verify = _no_hash  # type: ignore[method-assign]
    times: list[float] = []
    try:
        for _ in range(rounds):
            number = op.post(f"/api/missions/{MISSION}/versions").json()["number"]
            submission = op.post(f"/api/missions/{MISSION}/versions/{number}/submit").json()["id"]
            envelope = sign_prepared(prepare(sup, submission, signer), signer)
            start = time.perf_counter()
            response = sup.post(f"/api/submissions/{submission}/decision",
                                json={"envelope": envelope, "password": PASSWORD})
            times.append(time.perf_counter() - start)
            assert response.status_code == 201, response.text
    finally:
        if skip_password:
            del HASHER.verify  # the class's method again
        app.state.rehearsals.shutdown()
        database.engine.dispose()
    return times


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--rounds", type=int, default=40)
    args = parser.parse_args()
    url = os.environ.get("COUNTERSIGN_TEST_POSTGRES_URL") or None
    engine = "PostgreSQL" if url else "SQLite"
    for label, skip in (("with password check", False), ("without (comparison)", True)):
        with tempfile.TemporaryDirectory() as tmp:
            times = run(args.rounds, skip, url, Path(tmp))
        print(f"decision latency {label} on {engine}, {args.rounds} decisions: "
              f"median {statistics.median(times) * 1000:.1f} ms, "
              f"p95 {_percentile(times, 0.95) * 1000:.1f} ms")


if __name__ == "__main__":
    main()
