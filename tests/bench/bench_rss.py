"""RSS of the server's process tree across the bad-input run (it grew 330 -> 930 MB
and stayed there). A real `countersign serve` on SQLite; the bad input of
tests/web/test_bad_input.py and test_hostile_input.py (oversized, malformed, XML entities,
bad UTF-8, deep nesting, non-finite numbers, duplicate keys, huge plan coordinates, bad
cursors and instants) plus heavy validations, sent in rounds. Printed: the tree's RSS (the
server and every descendant, from /proc) after start-up and a warm-up round, then after each
round. Validation processes keep what z3 and their caches allocate and are replaced once one's
resident memory passes MAX_PROCESS_RSS, so the RSS is a sawtooth: bounded means that once they
have been replaced it comes back to the warmed-up size (target: within 10%), whatever the
number of rounds, and the peak printed is what MAX_PROCESS_RSS allows.

Run: .venv/bin/python -m tests.bench.bench_rss [--rounds 10] [--heavy 6]   (the defaults)
"""

from __future__ import annotations

import argparse
import json
import os
import tempfile
import time
import uuid
from pathlib import Path

import httpx

from countersign.orders.examples import example_bytes
from countersign.web.validation_pool import MAX_PROCESS_RSS

from ..heavy_orders import heavy_body
from .bench_api import _serve
from .bench_fair import _users

PAGE = os.sysconf("SC_PAGE_SIZE")


def pids(root: int) -> set[str]:
    return {name.split()[0] for name in per_process_mb(root)}


def tree_rss_mb(root: int) -> float:
    """Resident memory of `root` and all its descendants (psutil-free: /proc)."""
    return sum(per_process_mb(root).values())


def per_process_mb(root: int) -> dict[str, float]:
    """RSS by process of the tree, named `pid command`."""
    parents: dict[int, int] = {}
    for name in os.listdir("/proc"):
        if name.isdigit():
            try:
                stat = Path(f"/proc/{name}/stat").read_text()
                parents[int(name)] = int(stat.rsplit(")", 1)[1].split()[1])
            except (OSError, ValueError, IndexError):
                continue
    tree, frontier = {root}, [root]
    while frontier:
        pid = frontier.pop()
        for child, parent in parents.items():
            if parent == pid and child not in tree:
                tree.add(child)
                frontier.append(child)
    sizes = {}
    for pid in tree:
        try:
            rss = int(Path(f"/proc/{pid}/statm").read_text().split()[1]) * PAGE
            command = Path(f"/proc/{pid}/cmdline").read_bytes().replace(b"\0", b" ")
        except (OSError, ValueError, IndexError):
            continue
        sizes[f"{pid} {command.decode(errors='replace')[:60]}"] = rss / 2**20
    return sizes


def bad_requests() -> list[tuple[str, str, bytes, str]]:
    """(method, path, body, content type) as the bad-input tests send them."""
    orders = json.loads(example_bytes("search-and-sample"))
    orders["id"] = "hostile"
    text = json.dumps(orders)
    out: list[tuple[str, str, bytes, str]] = [
        ("POST", "/api/import", b"{" + b" " * (10 * 1024 * 1024) + b"}", "application/json"),
        ("POST", "/api/import", b"{not json", "application/json"),
        ("POST", "/api/import", b"<AVCL><unclosed>", "application/xml"),
        ("POST", "/api/import", b"<!DOCTYPE x [<!ENTITY a 'b'>]><AVCL/>", "application/xml"),
        ("POST", "/api/import", b'{"id": "\xff\xfe"}', "application/json"),
        ("PUT", "/api/vehicles/x", b'{"a":' * 100 + b"1" + b"}" * 100, "application/json"),
        ("GET", "/api/missions/search-and-sample/paths?cursor=LTE=", b"", ""),
        ("GET", "/api/approvals?since=2020-01-01T00:00:00", b"", ""),
        ("GET", "/api/approvals?until=9999-12-31T23:59:59-05:00", b"", ""),
        ("POST", "/api/missions/search-and-sample/plan-problem",
         b'{"start": [1e300, 1e300], "recovery": [0, 0]}', "application/json"),
    ]
    for route in ("/api/validate", "/api/missions", "/api/import", "/api/read"):
        for number in ("1e999", "-Infinity", "NaN"):
            out.append(("POST", route, text.replace('"pd": 0.8', f'"pd": {number}', 1).encode(),
                        "application/json"))
        out.append(("POST", route, (text[:-1] + ', "title": "again"}').encode(),
                    "application/json"))
    return out


def one_round(client: httpx.Client, admin: httpx.Client, heavy: int) -> tuple[int, int, str]:
    """Every bad request once, and `heavy` of the heavy validations: (4xx, other, the
    heavy validations' statuses)."""
    refused = other = 0
    statuses = []
    for method, path, body, kind in bad_requests():
        user = admin if path.startswith("/api/vehicles") else client
        answer = user.request(method, path, content=body or None,
                              headers={"content-type": kind} if kind else {})
        if 400 <= answer.status_code < 500:
            refused += 1
        else:
            other += 1
            print(f"  not a 4xx: {method} {path} -> {answer.status_code}")
    for _ in range(heavy):
        body = json.loads(heavy_body())
        # A checked fact changes (a description alone is answered from the last report).
        bound = uuid.uuid4().int % 10**6 + 100
        body["constraints"][-1]["expr"] = body["constraints"][-1]["expr"].rsplit(">=", 1)[0] \
            + f">= {bound}"
        answer = client.post("/api/validate", json=body)
        statuses.append(str(answer.status_code))
        if answer.status_code >= 500:
            other += 1
            print(f"  heavy validation -> {answer.status_code}")
    return refused, other, ",".join(statuses)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--rounds", type=int, default=10)
    parser.add_argument("--heavy", type=int, default=6,
                        help="heavy validations per round (each bounded by the solver budget)")
    args = parser.parse_args()
    with tempfile.TemporaryDirectory() as data:
        url = f"sqlite:///{data}/bench.db"
        tokens = _users(url)
        admin_token = _admin(url)
        server, base, _port = _serve(url, 1, data, Path(data) / "server.log")
        try:
            opts = {"base_url": base, "timeout": 300}
            with httpx.Client(**opts, headers={"Authorization": f"Bearer {tokens['heavy']}"}) \
                    as client, httpx.Client(**opts, headers={
                        "Authorization": f"Bearer {admin_token}"}) as admin:
                client.post("/api/import", content=example_bytes("search-and-sample"),
                            headers={"content-type": "application/json"}).raise_for_status()
                print(f"RSS of the server's process tree (pid {server.pid}), MB")
                print(f"  after start-up            {tree_rss_mb(server.pid):8.1f}")
                one_round(client, admin, args.heavy)
                warm = tree_rss_mb(server.pid)
                print(f"  after a warm-up round     {warm:8.1f}")
                for name, size in sorted(per_process_mb(server.pid).items()):
                    print(f"    {size:8.1f}  {name}")
                sizes = [warm]
                warm_pids = pids(server.pid)
                after_replacement: list[float] = []
                for n in range(1, args.rounds + 1):
                    start = time.perf_counter()
                    refused, other, heavy = one_round(client, admin, args.heavy)
                    sizes.append(tree_rss_mb(server.pid))
                    if after_replacement or not warm_pids <= pids(server.pid):
                        after_replacement.append(sizes[-1])
                    print(f"  after round {n:<2}            {sizes[-1]:8.1f}   "
                          f"({refused} refused 4xx, {other} other, heavy {heavy}, "
                          f"{time.perf_counter() - start:5.1f} s)")
                for name, size in sorted(per_process_mb(server.pid).items()):
                    print(f"    {size:8.1f}  {name}")
                print(f"peak {max(sizes):.1f} MB ({max(sizes) / warm - 1:+.1%} over the "
                      f"warmed-up size; a process is replaced past "
                      f"{MAX_PROCESS_RSS / 2**20:.0f} MB)")
                if not after_replacement:
                    print("INCONCLUSIVE: no validation process was replaced yet; run more "
                          "rounds or heavier ones")
                else:
                    low = min(after_replacement)
                    verdict = "PASS" if low <= 1.1 * warm else "MISS"
                    print(f"lowest after the processes were replaced {low:.1f} MB "
                          f"({low / warm - 1:+.1%} of the warmed-up size) {verdict}")
        finally:
            server.terminate()
            server.wait(timeout=30)


def _admin(url: str) -> str:
    from countersign.store.accounts import create_token, create_user
    from countersign.store.db import Database

    database = Database(url)
    with database.session() as db:
        user = create_user(db, username="bench-admin", role="admin",
                           password="Bq7-nimda-bench-Lp2-rss", signer=database.log_signer)
        token = create_token(db, user=user, name="bench", signer=database.log_signer)[1]
    database.engine.dispose()
    return token


if __name__ == "__main__":
    main()
