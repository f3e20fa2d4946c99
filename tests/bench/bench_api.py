"""API benchmark (issue 5): 50 concurrent clients against a real server process, mixed reads
and writes, on SQLite and PostgreSQL side by side.

Run: .venv/bin/python -m tests.bench.bench_api [--clients 50] [--seconds 20]
PostgreSQL is used when COUNTERSIGN_TEST_POSTGRES_URL is set (scripts/postgres-for-tests).
"""

from __future__ import annotations

import argparse
import asyncio
import os
import socket
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import httpx
from sqlalchemy import text

from countersign.orders.examples import example_bytes
from countersign.store.accounts import create_token, create_user
from countersign.store.db import Database, make_engine


def _free_port() -> int:
    with socket.socket() as sock:
        sock.bind(("127.0.0.1", 0))
        return int(sock.getsockname()[1])


def _prepare(url: str) -> str:
    if url.startswith("postgresql"):
        engine = make_engine(url)
        with engine.begin() as connection:
            connection.execute(text("DROP SCHEMA public CASCADE"))
            connection.execute(text("CREATE SCHEMA public"))
        engine.dispose()
    database = Database(url)
    database.migrate()
    with database.session() as db:
        user = create_user(db, username="bench", role="operator", password="benchmark password")
        token = create_token(db, user=user, name="bench")[1]
    database.engine.dispose()
    return token


def _percentile(values: list[float], q: float) -> float:
    ordered = sorted(values)
    return ordered[min(len(ordered) - 1, int(q * len(ordered)))] if ordered else float("nan")


async def _client(base: str, token: str, number: int, until: float,
                  timings: dict[str, list[float]], statuses: dict[int, int]) -> None:
    headers = {"Authorization": f"Bearer {token}"}
    mission = f"bench-{number % 10}"
    async with httpx.AsyncClient(base_url=base, headers=headers, timeout=60) as client:
        step = 0
        while time.perf_counter() < until:
            step += 1
            kind = "write" if step % 5 == 0 else ("validate" if step % 5 == 1 else "read")
            start = time.perf_counter()
            if kind == "read":
                response = await client.get(f"/api/missions/{mission}")
            elif kind == "validate":
                response = await client.post("/api/validate", content=example_bytes(
                    "search-and-sample"), headers={"Content-Type": "application/json"})
            else:
                current = await client.get(f"/api/missions/{mission}")
                if current.status_code != 200:
                    statuses[current.status_code] = statuses.get(current.status_code, 0) + 1
                    continue
                orders = current.json()["orders"]
                orders["description"] = f"edit {number}.{step}"
                response = await client.put(
                    f"/api/missions/{mission}/draft", json={"orders": orders},
                    headers={"If-Match": current.headers["etag"]})
            timings[kind].append(time.perf_counter() - start)
            statuses[response.status_code] = statuses.get(response.status_code, 0) + 1


async def _load(base: str, token: str, clients: int, seconds: float) -> dict[str, object]:
    async with httpx.AsyncClient(base_url=base, headers={"Authorization": f"Bearer {token}"},
                                 timeout=60) as setup:
        for i in range(10):
            data = example_bytes("search-and-sample").replace(
                b'"id": "search-and-sample"', f'"id": "bench-{i}"'.encode())
            await setup.post("/api/import", content=data)
    timings: dict[str, list[float]] = {"read": [], "validate": [], "write": []}
    statuses: dict[int, int] = {}
    until = time.perf_counter() + seconds
    await asyncio.gather(*(_client(base, token, n, until, timings, statuses)
                           for n in range(clients)))
    total = sum(len(v) for v in timings.values())
    return {"timings": timings, "statuses": statuses, "throughput": total / seconds}


def run(url: str, label: str, clients: int, seconds: float) -> dict[str, object]:
    token = _prepare(url)
    port = _free_port()
    env = {**os.environ, "COUNTERSIGN_DATABASE_URL": url}
    with tempfile.TemporaryDirectory() as data, open(Path(data) / "server.log", "w") as log:
        server = subprocess.Popen(
            [sys.executable, "-m", "countersign.cli", "serve", "--port", str(port),
             "--data-dir", data], env=env, stdout=subprocess.DEVNULL, stderr=log)
        try:
            base = f"http://127.0.0.1:{port}"
            deadline = time.monotonic() + 30
            while True:
                try:
                    httpx.get(f"{base}/api/health")
                    break
                except httpx.HTTPError:
                    if time.monotonic() > deadline:
                        raise
                    time.sleep(0.2)
            result = asyncio.run(_load(base, token, clients, seconds))
            errors = int(sum(n for s, n in result["statuses"].items() if s >= 500))  # type: ignore[attr-defined]
            if errors:
                log.flush()
                print(Path(log.name).read_text()[-3000:])
        finally:
            server.terminate()
            server.wait(timeout=20)
    timings = result["timings"]
    assert isinstance(timings, dict)
    print(f"\n## {label}: {clients} clients for {seconds:.0f} s")
    print(f"statuses: {result['statuses']}")
    print(f"throughput: {result['throughput']:.0f} requests/s")
    for kind, values in timings.items():
        print(f"{kind:<9} n={len(values):>6}  p50 {statistics.median(values) * 1000:7.1f} ms  "
              f"p99 {_percentile(values, 0.99) * 1000:7.1f} ms")
    return result


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--clients", type=int, default=50)
    parser.add_argument("--seconds", type=float, default=20)
    args = parser.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        sqlite = run(f"sqlite:///{Path(tmp) / 'bench.db'}", "SQLite", args.clients, args.seconds)
    pg_url = os.environ.get("COUNTERSIGN_TEST_POSTGRES_URL")
    if not pg_url:
        print("\nPostgreSQL skipped: set COUNTERSIGN_TEST_POSTGRES_URL "
              "(export COUNTERSIGN_TEST_POSTGRES_URL=$(scripts/postgres-for-tests))")
        return
    postgres = run(pg_url, "PostgreSQL", args.clients, args.seconds)
    ratio = float(postgres["throughput"]) / float(sqlite["throughput"])  # type: ignore[arg-type]
    print(f"\nthroughput ratio PostgreSQL/SQLite: {ratio:.2f}")


if __name__ == "__main__":
    main()
