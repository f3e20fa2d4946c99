"""The cost of reading roles from the log.

Every decision, statement, key registration and review page now replays the log's account
entries (store/logged_roles.py: one LIKE scan of log_entries, then a receipt check per account
entry). Times it beside the scan each decision already made for key revocations
(decide_guard.logged_key_revocation), on a fresh SQLite database whose log holds `--accounts`
account entries among `--entries` entries in all. Prints medians and their ratio; asserts
nothing about time.

Run: .venv/bin/python -m tests.bench.bench_logged_roles [--entries 10000] [--accounts 200]
"""

from __future__ import annotations

import argparse
import statistics
import tempfile
import time
from collections.abc import Callable
from pathlib import Path

from sqlalchemy import select

from countersign.settings import Settings
from countersign.store.accounts import create_user
from countersign.store.db import Database
from countersign.store.decide_guard import logged_key_revocation
from countersign.store.events import record
from countersign.store.logged_roles import decision_refusal_from_log
from countersign.store.tables import User
from countersign.web.app import create_app

PASSWORD = "correct horse battery staple"


def _median_ms(run: Callable[[], object], rounds: int) -> float:
    times = []
    for _ in range(rounds):
        start = time.perf_counter()
        run()
        times.append((time.perf_counter() - start) * 1000)
    return statistics.median(times)


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--entries", type=int, default=10_000)
    parser.add_argument("--accounts", type=int, default=200)
    parser.add_argument("--rounds", type=int, default=15)
    args = parser.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        url = f"sqlite:///{Path(tmp) / 'bench.db'}"
        database = Database(url)
        create_app(Settings(data_dir=Path(tmp), database_url=url), database)
        with database.session() as db:
            create_user(db, username="sue", role="supervisor", password=PASSWORD,
                        signer=database.log_signer)
            for i in range(args.accounts - 1):  # the password hash is the slow part: reuse it
                record(db, kind="user.created", actor=None,
                       detail={"user": f"u{i}", "role": "operator"}, signer=database.log_signer)
            for i in range(args.entries - args.accounts):
                record(db, kind="draft.updated", actor=None, mission_id="m",
                       detail={"revision": i}, signer=database.log_signer)
        with database.session(write=False) as db:
            user = db.scalars(select(User).where(User.username == "sue")).one()
            assert decision_refusal_from_log(db, user, signer=database.log_signer) is None
            signer = database.log_signer
            roles = _median_ms(lambda: decision_refusal_from_log(db, user, signer=signer),
                               args.rounds)
            keys = _median_ms(lambda: logged_key_revocation(db, "k" * 16), args.rounds)
    print(f"log of {args.entries} entries, {args.accounts} account entries (SQLite)")
    print(f"  roles from the log:     median {roles:8.2f} ms")
    print(f"  key revocation scan:    median {keys:8.2f} ms")
    print(f"  ratio roles / key scan: {roles / keys:.1f}x")


if __name__ == "__main__":
    main()
