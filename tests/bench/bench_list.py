"""The mission list with large stored reports: 50 readers, 20 stored
1,000-goal missions, a real `countersign serve --workers 2` on SQLite. Target: p99 < 100 ms.

Run: .venv/bin/python -m tests.bench.bench_list [--missions 20] [--goals 1000] [--readers 50]
     [--seconds 20] [--workers 2]

Every reader is a closed loop: GET /api/missions, then an exponentially distributed think time
(mean 1 s, people looking at the list). Baseline, measured in this same process on the same
database: what one list cost before the summary columns (each mission's stored report loaded
and decoded to count its errors and warnings) beside what it costs now (one query of the
summary columns).
"""

from __future__ import annotations

import argparse
import asyncio
import os
import random
import statistics
import tempfile
import time
from pathlib import Path

import httpx
from sqlalchemy import select

from countersign.orders.canonical import orders_to_json
from countersign.orders.model import Orders
from countersign.store.accounts import create_token, create_user
from countersign.store.db import Database
from countersign.store.missions import create_mission, report_for
from countersign.store.tables import Mission, ValidationReport
from countersign.verify import fingerprint

from .bench_api import _serve, percentile
from .generated import random_dag
from .timing import best_of


def _populate(url: str, missions: int, goals: int) -> str:
    database = Database(url)
    database.migrate()
    with database.session() as db:
        operator = create_user(db, username="op", role="operator",
                               password="tidal orchid 79 granite", signer=database.log_signer)
        reader = create_user(db, username="reader", role="auditor",
                             password="tidal orchid 79 granite", signer=database.log_signer)
        token = create_token(db, user=reader, name="bench", signer=database.log_signer)[1]
    base = orders_to_json(random_dag(goals))
    for index in range(missions):
        orders = Orders.model_validate({**base, "id": f"large-{index:02d}"})
        with database.session() as db:
            mission = create_mission(db, orders=orders, author=operator, signer=database.log_signer)
            # Stored with the mission.
            report_for(db, orders, mission.draft_digest, reports=database.reports)
    database.engine.dispose()
    return token


def _in_process(url: str) -> tuple[float, float]:
    """Seconds of one list's database work: decoding every report (before) and the columns."""
    database = Database(url)
    checker = fingerprint.checker_fingerprint()

    def decoded() -> None:
        with database.session(write=False) as db:
            for mission in db.scalars(select(Mission).order_by(Mission.id)):
                row = db.get(ValidationReport, (mission.draft_digest, checker))
                assert row is not None
                sum(f["severity"] == "error" for f in row.report["findings"])

    def columns() -> None:
        with database.session(write=False) as db:
            db.execute(select(Mission.id, ValidationReport.errors, ValidationReport.warnings)
                       .outerjoin(ValidationReport,
                                  (ValidationReport.digest == Mission.draft_digest)
                                  & (ValidationReport.checker_version == checker))
                       .order_by(Mission.id)).all()

    before, after = best_of(5, decoded), best_of(5, columns)
    database.engine.dispose()
    return before, after


def _cpu_per_list(url: str, data: str, token: str, rounds: int = 20) -> float:
    """CPU seconds of one GET /api/missions answered in this process (a figure the machine's
    load does not move, unlike the latencies over HTTP)."""
    from fastapi.testclient import TestClient

    from countersign.settings import Settings
    from countersign.web.app import create_app

    database = Database(url)
    # Started as a server starts it (its lifespan: the start-up objects left out of garbage
    # collection, which otherwise walked them all within the lists measured), without
    # validation processes, which a list does not use.
    app = create_app(Settings(data_dir=Path(data), database_url=url, validation_processes=0),
                     database)
    with TestClient(app, headers={"Authorization": f"Bearer {token}"}) as client:
        assert client.get("/api/missions").status_code == 200  # warm: caches, connection
        start = time.process_time()
        for _ in range(rounds):
            assert client.get("/api/missions").status_code == 200
        seconds = (time.process_time() - start) / rounds
    database.engine.dispose()
    return seconds


async def _readers(base: str, token: str, readers: int, seconds: float) -> list[float]:
    timings: list[float] = []
    start = time.perf_counter() + 2.0  # the first 2 s warm the connections, uncounted
    until = start + seconds

    async def reader(number: int) -> None:
        rng = random.Random(number)
        async with httpx.AsyncClient(base_url=base, timeout=120,
                                     headers={"Authorization": f"Bearer {token}"}) as client:
            while time.perf_counter() < until:
                await asyncio.sleep(rng.expovariate(1.0))
                began = time.perf_counter()
                answer = await client.get("/api/missions")
                assert answer.status_code == 200, answer.text
                if start <= began < until:
                    timings.append(time.perf_counter() - began)

    await asyncio.gather(*(reader(n) for n in range(readers)))
    return timings


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--missions", type=int, default=20)
    parser.add_argument("--goals", type=int, default=1_000)
    parser.add_argument("--readers", type=int, default=50)
    parser.add_argument("--seconds", type=float, default=20.0)
    parser.add_argument("--workers", type=int, default=2)
    parser.add_argument("--http-only", action="store_true",
                        help="skip the in-process figures (e.g. to time an older checkout's "
                        "server, PYTHONPATH=its backend, which has no summary columns)")
    args = parser.parse_args()
    print(f"cores {os.cpu_count()}, load {os.getloadavg()[0]:.1f}; {args.missions} stored "
          f"{args.goals:,}-goal missions, {args.readers} readers, {args.workers} workers")
    with tempfile.TemporaryDirectory() as data:
        url = f"sqlite:///{Path(data) / 'bench.db'}"
        began = time.perf_counter()
        token = _populate(url, args.missions, args.goals)
        print(f"stored in {time.perf_counter() - began:.1f} s")
        if not args.http_only:
            before, after = _in_process(url)
            print(f"{'one list, database work: reports decoded (before)':<56} "
                  f"{before * 1000:8.1f} ms")
            print(f"{'one list, database work: summary columns (now)':<56} "
                  f"{after * 1000:8.1f} ms   ratio {before / after:.0f}x")
        cpu = _cpu_per_list(url, data, token)
        print(f"{'GET /api/missions in process, CPU per request':<56} {cpu * 1000:8.1f} ms")
        server, base, _port = _serve(url, args.workers, data, Path(data) / "server.log")
        try:
            timings = asyncio.run(_readers(base, token, args.readers, args.seconds))
        finally:
            server.terminate()
            server.wait(30)
    p99 = percentile(timings, 0.99) * 1000
    print(f"{'GET /api/missions over HTTP':<56} n={len(timings)}  p50 "
          f"{statistics.median(timings) * 1000:.1f} ms  p99 {p99:.1f} ms  "
          f"goal < 100 ms: {'PASS' if p99 < 100 else 'MISS'}")


if __name__ == "__main__":
    main()
