"""Benchmark of rehearsal campaigns (Speed): simulations per second on two workers,
printed beside one worker (the baseline, in this same process).

Run: .venv/bin/python -m tests.bench.bench_campaign [-n 60] [--postgres URL]

SQLite: the in-process runner with 1 and then 2 simulation processes. With --postgres (a
throw-away database: its public schema is dropped), procrastinate with 1 and then 2
`countersign campaign worker` processes. Each run is a fresh campaign of the exemplar over the
same sweep, timed from queueing to the sealed record.
"""

from __future__ import annotations

import argparse
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from sqlalchemy import text

from countersign.campaigns.spec import CampaignSpec
from countersign.jobs import CampaignRunner
from countersign.jobs.inprocess import InProcessRunner
from countersign.orders.canonical import digest, orders_to_json
from countersign.orders.examples import load_example
from countersign.store import campaigns as store
from countersign.store.db import Database

SWEEP = {"faults": ["none", "nav_drift", "leak", "low_energy"], "goals": ["start", "G2", "G4"]}


def _campaign(database: Database, n: int) -> tuple[str, list[tuple[int, int]]]:
    orders = load_example("search-and-sample")
    spec = CampaignSpec.build(simulations=n, orders=orders, chunk=5, **SWEEP)  # type: ignore[arg-type]
    with database.session() as db:
        row = store.create(db, orders=orders_to_json(orders), orders_digest=digest(orders),
                           spec=spec.to_json(), simulations=n, owner=None,
                           signer=database.log_signer)
        return row.id, spec.chunks()


def _wait(database: Database, campaign_id: str) -> None:
    while True:
        with database.session(write=False) as db:
            if store.state_of(db, campaign_id) not in store.ACTIVE_STATES:
                return
        time.sleep(0.05)


def _rate(database: Database, runner: CampaignRunner, workers: int, n: int) -> float:
    """Simulations per second of one campaign of `n`, timed from queueing to the sealed record.
    A first campaign of one simulation per worker starts the workers (imports) before the
    clock."""
    warm, _ = _campaign(database, workers)
    runner.enqueue(warm, [(i, i + 1) for i in range(workers)])
    _wait(database, warm)
    campaign_id, chunks = _campaign(database, n)
    start = time.perf_counter()
    runner.enqueue(campaign_id, chunks)
    _wait(database, campaign_id)
    return n / (time.perf_counter() - start)


def sqlite_rate(workers: int, n: int, folder: Path) -> float:
    database = Database(f"sqlite:///{folder / f'bench-{workers}.db'}")
    database.migrate()
    runner = InProcessRunner(database, workers=workers, processes=True)
    try:
        return _rate(database, runner, workers, n)
    finally:
        runner.close()


def postgres_rate(workers: int, n: int, url: str) -> float:
    database = Database(url)
    with database.engine.begin() as connection:
        connection.execute(text("DROP SCHEMA public CASCADE"))
        connection.execute(text("CREATE SCHEMA public"))
    database.migrate()
    from countersign.jobs.pg import ProcrastinateRunner

    runner = ProcrastinateRunner(database)
    env = {**os.environ, "COUNTERSIGN_DATABASE_URL": url}
    processes = [subprocess.Popen([sys.executable, "-m", "countersign.cli", "campaign",
                                   "worker", "--heartbeat", "2"], env=env,
                                  stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
                 for _ in range(workers)]
    try:
        return _rate(database, runner, workers, n)
    finally:
        for process in processes:
            process.terminate()
            process.wait(timeout=60)
        runner.close()
        database.engine.dispose()


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("-n", type=int, default=60, help="simulations per campaign")
    parser.add_argument("--postgres", default=None, metavar="URL")
    args = parser.parse_args()
    print(f"\n## Campaign: simulations per second, exemplar, sweep {SWEEP}, n={args.n}, "
          f"{os.cpu_count()} CPUs")
    print(f"{'runner':<34} {'1 worker':>10} {'2 workers':>10} {'ratio':>6}")
    with tempfile.TemporaryDirectory() as folder:
        one, two = (sqlite_rate(w, args.n, Path(folder)) for w in (1, 2))
    print(f"{'SQLite, in-process (processes)':<34} {one:>10.2f} {two:>10.2f} {two / one:>5.2f}x")
    if args.postgres:
        one, two = (postgres_rate(w, args.n, args.postgres) for w in (1, 2))
        print(f"{'PostgreSQL, procrastinate workers':<34} {one:>10.2f} {two:>10.2f} "
              f"{two / one:>5.2f}x")


if __name__ == "__main__":
    main()
