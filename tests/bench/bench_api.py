"""API benchmark ("Speed"): 50 concurrent clients against a real server process over
HTTP, mixed reads and writes, on SQLite and PostgreSQL side by side.

Targets: p99 under 100 ms for reads and under 1 s for validation of the exemplar; throughput
and the ratio PostgreSQL/SQLite are reported.

Each database gets a fresh schema and its own server, started here as `countersign serve`
(uvicorn, `--workers` processes). Two runs follow one another against it:

* "think": every client is a closed loop that waits between requests for an exponentially
  distributed think time (mean --think seconds, 1 s by default: people in the mission editor),
  so that about clients/think requests per second arrive. The targets are judged on this run.
* "saturate": the same clients without think time: the server's throughput. At saturation a
  request waits for the ones before it (Little's law: latency ~ clients / throughput), so its
  latencies measure the queue, not the service; they are printed, with PASS/MISS, for
  completeness.

The mix, per client in turn: 3 reads (GET /api/missions/{id}, one of 10 missions), 1
validation (POST /api/validate with the search-and-sample exemplar), 1 write (GET the mission,
then PUT its draft with If-Match; the GET counts as a read, the PUT as the write). Every
accepted write changes the draft, so the server validates a new draft each time. A 412 on a
write is expected (another client edited first); a 5xx fails the run. The first --warmup
seconds of each run are not counted; every request sent in the measured window counts, however
long it takes to answer (clients stop sending at the end and wait for their last answer).
After both runs the event log is checked: one draft.updated event and one log leaf per
accepted write.

Run: .venv/bin/python -m tests.bench.bench_api [--clients 50] [--seconds 30] [--workers 2]
Listening sockets side by side: gunicorn with uvicorn workers and a socket
per worker (reuse_port, what `serve --workers` runs) and the same with the master's one shared
socket (hidden `serve --shared-socket`), the same worker count and database, in turn; "requests
per process" is each server process's share of the requests, by the process holding the
connection. (Commit 1b1115e ran this against the home-made supervisor, web/workers.py, before
it was replaced, `--compare-managers`: the same throughput and spread.)
     .venv/bin/python -m tests.bench.bench_api --compare-sockets [--rounds 2] [--only ...]
PostgreSQL is used when COUNTERSIGN_TEST_POSTGRES_URL is set (scripts/postgres-for-tests).
The load generator runs in this process (asyncio + httpx) on the same machine as the server.
"""

from __future__ import annotations

import argparse
import asyncio
import gc
import os
import random
import subprocess
import sys
import tempfile
import time
from dataclasses import dataclass, field
from pathlib import Path

import httpx
from sqlalchemy import text

from countersign.orders.examples import example_bytes
from countersign.store.accounts import create_token, create_user
from countersign.store.db import Database, make_engine

from ..ports import free_port

KINDS = ("read", "validate", "write")
TARGETS_MS = {"read": 100.0, "validate": 1000.0}  # p99 goals
MISSIONS = 10


@dataclass
class Run:
    label: str
    seconds: float
    timings: dict[str, list[float]] = field(default_factory=lambda: {k: [] for k in KINDS})
    statuses: dict[int, int] = field(default_factory=dict)
    accepted_writes: int = 0
    server_cpu: float = 0.0  # CPU seconds of the server's processes during the measured part
    client_cpu: float = 0.0  # CPU seconds of this process (the load generator), same window
    machine_cpu: float = 0.0  # CPU seconds of the whole machine (database server included)
    database_cpu: float = 0.0  # CPU seconds of PostgreSQL's processes
    busiest_share: float = 0.0  # the busiest server process's share of the server's CPU
    ports: list[int] = field(default_factory=list)  # each counted request's client port
    served_by: dict[int, int] = field(default_factory=dict)  # client port -> server process
    load: tuple[float, float] = (0.0, 0.0)  # 1-minute load average before and after

    @property
    def throughput(self) -> float:
        return sum(len(v) for v in self.timings.values()) / self.seconds

    def shares(self) -> list[float]:
        """Each server process's share of the counted requests, largest first (requests on a
        connection that opened and closed between two looks are left out)."""
        counts: dict[int, int] = {}
        for port in self.ports:
            pid = self.served_by.get(port)
            if pid is not None:
                counts[pid] = counts.get(pid, 0) + 1
        total = sum(counts.values())
        return sorted((n / total for n in counts.values()), reverse=True) if total else []

    @property
    def errors(self) -> int:
        return sum(n for status, n in self.statuses.items() if status >= 500)


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
        user = create_user(db, username="bench", role="operator",
                           password="tidal orchid 79 granite", signer=database.log_signer)
        token = create_token(db, user=user, name="bench", signer=database.log_signer)[1]
    database.engine.dispose()
    return token


def _count_log(url: str) -> tuple[int, int, int]:
    database = Database(url)
    with database.engine.connect() as connection:
        updates = connection.execute(
            text("SELECT count(*) FROM events WHERE kind = 'draft.updated'")).scalar_one()
        events = connection.execute(text("SELECT count(*) FROM events")).scalar_one()
        leaves = connection.execute(text("SELECT count(*) FROM log_entries")).scalar_one()
    database.engine.dispose()
    return int(updates), int(events), int(leaves)


def _cpu_by_process(pid: int) -> dict[int, float]:
    """User + system CPU seconds of a process's own threads, and of each of its children with
    all their descendants (a worker with its validation processes), by process id."""
    tick = os.sysconf("SC_CLK_TCK")
    parents: dict[int, int] = {}
    seconds: dict[int, float] = {}
    for entry in Path("/proc").iterdir():
        if entry.name.isdigit():
            try:
                fields = (entry / "stat").read_text().rsplit(")", 1)[1].split()
            except OSError:
                continue
            parents[int(entry.name)] = int(fields[1])
            seconds[int(entry.name)] = (int(fields[11]) + int(fields[12])) / tick
    totals = {pid: seconds.get(pid, 0.0)}
    for one, used in seconds.items():
        ancestor, chain = one, []
        while ancestor in parents and ancestor != pid:
            chain.append(ancestor)
            ancestor = parents[ancestor]
        if ancestor == pid and chain:
            top = chain[-1]  # the child of the server under which this process runs
            totals[top] = totals.get(top, 0.0) + used
    return totals


def _machine_busy() -> float:
    """CPU seconds the whole machine spent busy so far (all cores, /proc/stat)."""
    values = [int(v) for v in Path("/proc/stat").read_text().split("\n", 1)[0].split()[1:]]
    idle = values[3] + values[4]  # idle + iowait
    return (sum(values[:8]) - idle) / os.sysconf("SC_CLK_TCK")


def _postgres_cpu() -> float:
    """CPU seconds of the PostgreSQL server's processes on this machine, exited ones aside."""
    tick, total = os.sysconf("SC_CLK_TCK"), 0.0
    for entry in Path("/proc").iterdir():
        if entry.name.isdigit():
            try:
                if not (entry / "cmdline").read_bytes().startswith(b"postgres"):
                    continue
                fields = (entry / "stat").read_text().rsplit(")", 1)[1].split()
            except OSError:
                continue
            # own time + waited-for children's (backends that ended are counted by the server)
            total += sum(int(v) for v in fields[11:15]) / tick
    return total


def _listening(port: int) -> int:
    """How many sockets listen on this TCP port (one per server process)."""
    count = 0
    for table in ("/proc/net/tcp", "/proc/net/tcp6"):
        try:
            lines = Path(table).read_text().splitlines()[1:]
        except OSError:
            continue
        for line in lines:
            local, state = line.split()[1], line.split()[3]
            if state == "0A" and int(local.rsplit(":", 1)[1], 16) == port:
                count += 1
    return count


def _connections(port: int, pids: set[int]) -> dict[int, int]:
    """Established connections to the server's `port`: client port -> the process holding the
    server's end (the worker serving the connection)."""
    by_inode: dict[str, int] = {}
    for table in ("/proc/net/tcp", "/proc/net/tcp6"):
        try:
            lines = Path(table).read_text().splitlines()[1:]
        except OSError:
            continue
        for line in lines:
            fields = line.split()
            if fields[3] == "01" and int(fields[1].rsplit(":", 1)[1], 16) == port:
                by_inode[fields[9]] = int(fields[2].rsplit(":", 1)[1], 16)
    found: dict[int, int] = {}
    for pid in pids:
        try:
            for fd in Path(f"/proc/{pid}/fd").iterdir():
                target = os.readlink(fd)
                if target.startswith("socket:[") and target[8:-1] in by_inode:
                    found[by_inode[target[8:-1]]] = pid
        except OSError:
            continue
    return found


def percentile(values: list[float], q: float) -> float:
    """Nearest-rank percentile (q in 0..1) of the values, in their unit."""
    if not values:
        return float("nan")
    ordered = sorted(values)
    return ordered[min(len(ordered) - 1, max(0, int(q * len(ordered) + 0.999999) - 1))]


async def _client(client: httpx.AsyncClient, number: int, think: float, start: float,
                  until: float, run: Run, all_writes: list[int]) -> None:
    rng = random.Random(number)
    exemplar = example_bytes("search-and-sample")
    step = rng.randrange(5)  # clients start at different points of the mix

    def note(kind: str, began: float, response: httpx.Response) -> None:
        # Every request sent during the measured window counts, however long it takes.
        if start <= began < until:
            run.timings[kind].append(time.perf_counter() - began)
            stream = response.extensions.get("network_stream")
            address = stream.get_extra_info("client_addr") if stream is not None else None
            if address:
                run.ports.append(int(address[1]))
            run.statuses[response.status_code] = run.statuses.get(
                response.status_code, 0) + 1
            if kind == "write" and response.status_code == 200:
                run.accepted_writes += 1

    while time.perf_counter() < until:
        if think > 0:
            await asyncio.sleep(rng.expovariate(1 / think))
        step += 1
        mission = f"bench-{rng.randrange(MISSIONS)}"
        kind = "write" if step % 5 == 0 else ("validate" if step % 5 == 1 else "read")
        began = time.perf_counter()
        if kind == "read":
            response = await client.get(f"/api/missions/{mission}")
            note("read", began, response)
        elif kind == "validate":
            response = await client.post("/api/validate", content=exemplar,
                                         headers={"Content-Type": "application/json"})
            note("validate", began, response)
        else:
            current = await client.get(f"/api/missions/{mission}")
            note("read", began, current)
            if current.status_code != 200:
                continue
            orders = current.json()["orders"]
            orders["description"] = f"edit {number}.{step}"
            began = time.perf_counter()
            response = await client.put(
                f"/api/missions/{mission}/draft", json={"orders": orders},
                headers={"If-Match": current.headers["etag"]})
            note("write", began, response)
            if response.status_code == 200:
                all_writes[0] += 1


async def _seed(base: str, token: str) -> None:
    async with httpx.AsyncClient(base_url=base, headers={"Authorization": f"Bearer {token}"},
                                 timeout=60) as setup:
        for i in range(MISSIONS):
            data = example_bytes("search-and-sample").replace(
                b'"id": "search-and-sample"', f'"id": "bench-{i}"'.encode())
            response = await setup.post("/api/import", content=data)
            assert response.status_code == 201, response.text


async def _load(base: str, token: str, label: str, clients: int, seconds: float, warmup: float,
                think: float, all_writes: list[int], server: int, port: int) -> Run:
    run = Run(label, seconds)
    # Each client has a connection of its own, as each person's browser does (one shared pool
    # hands the few requests in flight to its most recently used connections, all served by
    # the same server process). All are made up front: building a client (its TLS context)
    # costs tens of milliseconds of the event loop, which must not fall into the measured
    # window. uvicorn closes idle connections after 5 s: let the clients drop them first.
    limits = httpx.Limits(max_connections=1, max_keepalive_connections=1, keepalive_expiry=3.0)
    pool = [httpx.AsyncClient(base_url=base, headers={"Authorization": f"Bearer {token}"},
                              timeout=120, limits=limits) for _ in range(clients)]
    await asyncio.gather(*(one.get("/api/health") for one in pool))
    start = time.perf_counter() + warmup
    until = start + seconds

    async def meter() -> None:
        await asyncio.sleep(max(0.0, start - time.perf_counter()))
        cpu, load, mine = _cpu_by_process(server), os.getloadavg()[0], time.process_time()
        machine, database = _machine_busy(), _postgres_cpu()
        await asyncio.sleep(max(0.0, until - time.perf_counter()))
        used = {pid: seconds - cpu.get(pid, 0.0)
                for pid, seconds in _cpu_by_process(server).items()}
        run.server_cpu = sum(used.values())
        run.busiest_share = max(used.values()) / run.server_cpu if run.server_cpu else 0.0
        run.client_cpu = time.process_time() - mine
        run.machine_cpu = _machine_busy() - machine
        run.database_cpu = _postgres_cpu() - database
        run.load = (load, os.getloadavg()[0])

    async def watch() -> None:
        # Which process serves each client connection, looked at every 0.2 s (this process's
        # own sockets to the port are seen from the server's side only).
        while time.perf_counter() < until + 1:
            pids = set(_cpu_by_process(server)) | {server}  # the server and its children
            run.served_by.update(await asyncio.to_thread(_connections, port, pids))
            await asyncio.sleep(0.2)

    # The load generator's own garbage collection would stop every client at once (a full
    # collection of this process took up to 370 ms) and count as server latency: reference
    # counting frees the responses; cycles wait until the run is over.
    gc.collect()
    gc.disable()
    try:
        await asyncio.gather(meter(), watch(), *(_client(pool[n], n, think, start, until, run,
                                                all_writes) for n in range(clients)))
    finally:
        gc.enable()
        await asyncio.gather(*(one.aclose() for one in pool))
    return run


def _serve(url: str, workers: int, data: str, log_path: Path, shared: bool = False,
           extra: tuple[str, ...] = ()) -> tuple[subprocess.Popen[bytes], str, int]:
    port = free_port()
    env = {**os.environ, "COUNTERSIGN_DATABASE_URL": url}
    with open(log_path, "w") as log:
        server = subprocess.Popen(
            [sys.executable, "-m", "countersign.cli", "serve", "--port", str(port),
             "--data-dir", data, *(["--workers", str(workers)] if workers != 1 else []),
             *(["--shared-socket"] if shared else []), *extra],
            env=env, stdout=subprocess.DEVNULL, stderr=log)
    base = f"http://127.0.0.1:{port}"
    deadline = time.monotonic() + 60
    while True:
        try:
            # Every process listening before the clients connect: the kernel spreads
            # connections over the sockets that listen when they arrive (a shared socket:
            # every worker's app started, by its log line).
            ready = (log_path.read_text().count("Application startup complete") >= workers
                     if shared else _listening(port) >= workers)
            if httpx.get(f"{base}/api/health").status_code == 200 and ready:
                return server, base, port
        except httpx.HTTPError:
            pass
        if time.monotonic() > deadline or server.poll() is not None:
            server.terminate()
            raise RuntimeError(f"the server did not start:\n{log_path.read_text()[-3000:]}")
        time.sleep(0.2)


def bench_database(url: str, label: str, args: argparse.Namespace,
                   shared: bool = False) -> dict[str, Run]:
    token = _prepare(url)
    runs: dict[str, Run] = {}
    all_writes = [0]
    with tempfile.TemporaryDirectory() as data:
        log_path = Path(data) / "server.log"
        server, base, port = _serve(url, args.workers, data, log_path, shared)
        try:
            asyncio.run(_seed(base, token))
            if args.think > 0:
                runs["think"] = asyncio.run(_load(base, token, label, args.clients, args.seconds,
                                                  args.warmup, args.think, all_writes,
                                                  server.pid, port))
            runs["saturate"] = asyncio.run(_load(base, token, label, args.clients,
                                                 args.seconds, args.warmup, 0, all_writes,
                                                 server.pid, port))
        finally:
            server.terminate()
            server.wait(timeout=30)
        if any(run.errors for run in runs.values()):
            print(log_path.read_text()[-3000:])
    updates, events, leaves = _count_log(url)
    complete = updates == all_writes[0] and leaves == events
    print(f"\n{label}: event log {'complete' if complete else 'INCOMPLETE'}: {updates} "
          f"draft.updated events for {all_writes[0]} accepted writes, {leaves} log leaves for "
          f"{events} events")
    return runs


def _cell(run: Run | None, kind: str, q: float) -> str:
    if run is None or not run.timings[kind]:
        return "-"
    return f"{percentile(run.timings[kind], q) * 1000:.1f}"


def report(results: dict[str, dict[str, Run]], args: argparse.Namespace) -> None:
    labels = list(results)
    served = (f"one database, `countersign serve --workers {args.workers}` (gunicorn, uvicorn "
              "workers) with a socket per worker (reuse_port) or one shared socket, in turn"
              if args.compare_sockets
              else f"server `countersign serve --workers {args.workers}`")
    print(f"\n# API benchmark: {args.clients} clients, {args.seconds:.0f} s per run after "
          f"{args.warmup:.0f} s warm-up, {served}, "
          f"think time exponential mean {args.think:g} s")
    for mode in ("think", "saturate"):
        if not any(mode in runs for runs in results.values()):
            continue
        title = (f"closed loop with think time (mean {args.think:g} s): targets judged here"
                 if mode == "think" else "saturation (no think time): throughput")
        print(f"\n## {title}")
        header = f"{'':<22}" + "".join(f"{label:>14}" for label in labels) + f"{'target':>10}"
        print(header + "  verdict")
        for kind in KINDS:
            for q, name in ((0.5, "p50"), (0.95, "p95"), (0.99, "p99")):
                cells = [_cell(results[label].get(mode), kind, q) for label in labels]
                line = f"{kind + ' ' + name + ' ms':<22}" + "".join(f"{c:>14}" for c in cells)
                target = TARGETS_MS.get(kind) if name == "p99" else None
                if target is not None:
                    verdicts = []
                    for label, cell in zip(labels, cells, strict=True):
                        ok = cell != "-" and float(cell) < target
                        verdicts.append(f"{label} {'PASS' if ok else 'MISS'}")
                    line += f"{'< ' + format(target, 'g'):>10}  " + ", ".join(verdicts)
                print(line)
        for name, value in (
            ("requests", lambda r: str(sum(len(v) for v in r.timings.values()))),
            ("throughput req/s", lambda r: f"{r.throughput:.1f}"),
            ("accepted writes/s", lambda r: f"{r.accepted_writes / r.seconds:.1f}"),
            ("412 (stale edit)", lambda r: str(r.statuses.get(412, 0))),
            ("5xx", lambda r: str(r.errors)),
            ("server CPU ms/request", lambda r: (
                f"{r.server_cpu * 1000 / sum(map(len, r.timings.values())):.1f}"
                if any(r.timings.values()) else "-")),
            ("server CPU cores", lambda r: f"{r.server_cpu / r.seconds:.2f}"),
            ("busiest process share", lambda r: f"{r.busiest_share:.0%}"),
            ("requests per process", lambda r: "/".join(f"{x:.0%}" for x in r.shares())),
            ("client CPU cores", lambda r: f"{r.client_cpu / r.seconds:.2f}"),
            ("PostgreSQL CPU cores", lambda r: f"{r.database_cpu / r.seconds:.2f}"),
            ("machine busy cores", lambda r: f"{r.machine_cpu / r.seconds:.2f}"),
            ("load avg before/after", lambda r: f"{r.load[0]:.1f}/{r.load[1]:.1f}"),
        ):
            cells = [value(results[label][mode]) if mode in results[label] else "-"
                     for label in labels]
            print(f"{name:<22}" + "".join(f"{c:>14}" for c in cells))
        if labels == ["SQLite", "PostgreSQL"] and all(mode in results[label]
                                                       for label in labels):
            sqlite, postgres = (results[label][mode] for label in labels)
            ratio = (f"{postgres.throughput / sqlite.throughput:.2f}" if sqlite.throughput
                     else "-")
            print(f"{'ratio PG/SQLite':<22}{ratio:>14}  (throughput)")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--clients", type=int, default=50)
    parser.add_argument("--seconds", type=float, default=30, help="measured seconds per run")
    parser.add_argument("--warmup", type=float, default=5, help="uncounted seconds per run")
    parser.add_argument("--think", type=float, default=1.0,
                        help="mean think time in seconds (0: only the saturation run)")
    parser.add_argument("--workers", type=int, default=2, help="server processes")
    parser.add_argument("--only", choices=["sqlite", "postgresql"], default=None)
    parser.add_argument(
        "--compare-sockets", action="store_true",
        help="run the --workers processes with a socket each (reuse_port) and with one shared "
        "socket in turn, on SQLite (or --only postgresql), side by side")
    parser.add_argument("--rounds", type=int, default=1,
                        help="with --compare-sockets: how many times each, alternating")
    args = parser.parse_args()
    results: dict[str, dict[str, Run]] = {}
    if args.compare_sockets:
        pg_url = os.environ.get("COUNTERSIGN_TEST_POSTGRES_URL")
        if args.only == "postgresql" and not pg_url:
            sys.exit("--only postgresql needs COUNTERSIGN_TEST_POSTGRES_URL")
        for round_ in range(1, args.rounds + 1):
            for name, shared in (("reuse_port", False), ("shared", True)):
                label = name if args.rounds == 1 else f"{name} #{round_}"
                if args.only == "postgresql":
                    results[label] = bench_database(pg_url or "", label, args, shared)
                else:
                    with tempfile.TemporaryDirectory() as tmp:
                        results[label] = bench_database(
                            f"sqlite:///{Path(tmp) / 'bench.db'}", label, args, shared)
        report(results, args)
        if any(run.errors for runs in results.values() for run in runs.values()):
            sys.exit(1)
        return
    if args.only != "postgresql":
        with tempfile.TemporaryDirectory() as tmp:
            results["SQLite"] = bench_database(f"sqlite:///{Path(tmp) / 'bench.db'}", "SQLite",
                                               args)
    pg_url = os.environ.get("COUNTERSIGN_TEST_POSTGRES_URL")
    if args.only != "sqlite":
        if pg_url:
            results["PostgreSQL"] = bench_database(pg_url, "PostgreSQL", args)
        else:
            print("\nPostgreSQL skipped: set COUNTERSIGN_TEST_POSTGRES_URL "
                  "(export COUNTERSIGN_TEST_POSTGRES_URL=$(scripts/postgres-for-tests))")
    report(results, args)
    print(f"\nmachine: {os.cpu_count()} CPUs, shared; the load average includes this "
          "benchmark's own client and server.")
    if any(run.errors for runs in results.values() for run in runs.values()):
        sys.exit(1)


if __name__ == "__main__":
    main()
