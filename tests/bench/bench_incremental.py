"""Validation that scales.

Run: nice .venv/bin/python -m tests.bench.bench_incremental [--quick] [--only NAME]

Every figure is printed beside its baseline measured in this same process:

- whole: the report of a 10,000-goal mission from scratch (fresh caches), split by check,
  beside the MEO route the report used before (`meo_check`, graph + owlrl + shapes) for the
  four codes it now takes from `meo.direct`;
- edit: a one-goal edit (a goal's cost) and a description edit of a 1,000-goal mission,
  in-process (validate with the parts and logic caches warm) beside the same orders validated
  from scratch;
- api: one-goal edits of a 1,000-goal mission with constraints, norms and an energy bound
  through the API (PUT the draft, GET the report; the app's pool of validation processes
  when `--pool`): the first edit and the median, beside a new mission validated in full;
- pirates: the NPS Pirates mission (../shared/reference/nps-ethical-control/) in-process,
  from scratch and again, beside the MEO route on it.

Every input is checked before it is timed: no error from validate, and the incremental
report equal to the one from scratch.
"""

from __future__ import annotations

import argparse
import copy
import gc
import os
import tempfile
import time
from collections.abc import Callable
from pathlib import Path
from typing import Any

from countersign.orders.model import Orders
from countersign.verify import properties as properties_module
from countersign.verify import report as report_module
from countersign.verify.logic import LogicCache
from countersign.verify.parts import PartsCache, part_keys
from countersign.verify.report import validate

from ..oracles.meo_route import meo_check
from .bench_meo import meo_mission

PIRATES = Path(__file__).resolve().parents[2] / "../shared/reference/nps-ethical-control"


def process_cpu(pid: int) -> float:
    """CPU seconds (user and system) another process has used, from /proc."""
    try:
        with open(f"/proc/{pid}/stat") as stat:
            fields = stat.read().rsplit(")", 1)[1].split()
    except OSError:
        return 0.0
    return (int(fields[11]) + int(fields[12])) / os.sysconf("SC_CLK_TCK")


def best(runs: int, action: Callable[[], object]) -> float:
    times = []
    for _ in range(runs):
        gc.collect()
        start = time.perf_counter()
        action()
        times.append(time.perf_counter() - start)
    return min(times)


def scratch(orders: Orders) -> dict[str, Any]:
    return validate(orders, logic_cache=LogicCache(), parts=PartsCache()).to_json()


def valid(orders: Orders) -> Orders:
    report = scratch(orders)
    errors = [f"{f['code']}: {f['message'][:100]}" for f in report["findings"]
              if f["severity"] == "error"]
    if errors:
        raise SystemExit(f"benchmark input {orders.id} is invalid: {errors[:3]}")
    return orders


# (module, function) of each stage: validate imports check_properties from its own module at
# the call (only orders with path properties load it), so it is timed there.
STAGES = [(report_module, name) for name in ("part_keys", "build_graph", "_core",
                                             "meo_only_findings", "check_logic", "digest")]
STAGES.append((properties_module, "check_properties"))


def split(orders: Orders) -> dict[str, float]:
    """Seconds per stage of one validation from scratch."""
    times: dict[str, float] = {}
    saved = {(module, name): getattr(module, name) for module, name in STAGES}

    def timed(name: str, function: Callable[..., Any]) -> Callable[..., Any]:
        def run(*args: Any, **kwargs: Any) -> Any:
            start = time.perf_counter()
            try:
                return function(*args, **kwargs)
            finally:
                times[name] = times.get(name, 0.0) + time.perf_counter() - start
        return run

    for (module, name), function in saved.items():
        setattr(module, name, timed(name, function))
    try:
        gc.collect()
        start = time.perf_counter()
        validate(orders, logic_cache=LogicCache(), parts=PartsCache())
        times["total"] = time.perf_counter() - start
    finally:
        for (module, name), function in saved.items():
            setattr(module, name, function)
    return times


def bench_whole(quick: bool) -> None:
    goals = 2_000 if quick else 10_000
    print(f"## Whole report of a {goals:,}-goal mission, from scratch (fresh caches)")
    orders = valid(meo_mission(goals))
    stages = split(orders)
    route = best(1, lambda: meo_check(orders))
    print(f"  validate, total                              {stages.pop('total'):8.3f} s"
          f"   | before: the MEO route alone took {route:8.3f} s")
    for name, seconds in sorted(stages.items(), key=lambda kv: -kv[1]):
        print(f"    {name:<42} {seconds:8.3f} s")
    direct = max(stages.get("meo_only_findings", 0.0), 1e-9)
    print(f"    (C1, C2, M6, M7 by meo.direct {direct:.3f} s, by the MEO route {route:.3f} s: "
          f"{route / direct:.0f}x)")


def edited(data: dict[str, Any], field: str, value: Any, goal: int = 500) -> Orders:
    changed = copy.deepcopy(data)
    if field == "description":
        changed["description"] = value
    else:
        changed["goals"][goal][field] = value
    return Orders.model_validate(changed)


def bench_edit(quick: bool) -> None:
    goals = 300 if quick else 1_000
    print(f"## One-goal edit of a {goals:,}-goal mission, in-process: incremental vs scratch")
    base = valid(meo_mission(goals))
    data = base.model_dump(mode="json", exclude_unset=True)
    cases = [
        ("goal cost", "cost", lambda i: {"energy_wh": 10 + i}),
        ("goal title (logic quotes titles)", "title", lambda i: f"Goal edited {i}"),
        ("description", "description", lambda i: f"Edited {i}"),
    ]
    for label, field, value in cases:
        parts, logic = PartsCache(), LogicCache()
        validate(base, logic_cache=logic, parts=parts)
        versions = [edited(data, field, value(i), goal=goals // 2) for i in range(4)]
        for orders in versions[:1]:
            if validate(orders, logic_cache=logic, parts=parts).to_json() != scratch(orders):
                raise SystemExit(f"incremental report of the {label} edit differs from scratch")
        counter = iter(versions[1:])
        ours = best(3, lambda c=counter, lc=logic, pc=parts: validate(  # type: ignore[misc]
            next(c), logic_cache=lc, parts=pc))
        full = best(2, lambda o=versions[0]: scratch(o))  # type: ignore[misc]
        print(f"  {label:<40} {ours * 1000:8.1f} ms   | from scratch {full * 1000:8.1f} ms"
              f"  ({full / max(ours, 1e-9):.0f}x)", flush=True)
    orders = versions[0]
    print(f"    of which part keys {best(3, lambda: part_keys(orders)) * 1000:.1f} ms, "
          f"Orders.model_validate {best(3, lambda: Orders.model_validate(data)) * 1000:.1f} ms")


EDIT_GOAL_MS = {"median": 300.0, "first": 1000.0}  # one-goal edit through the API


def bench_api(quick: bool, pool: bool) -> None:
    """One-goal edits of a 1,000-goal mission with constraints, norms and an energy bound
    (tests.bench.bench_logic), each a draft PUT and a report GET as the editor's autosave
    does: the first edit after the mission was created on a server just started, then the
    median of the edits after it, beside a new mission validated in full in the same run."""
    from fastapi.testclient import TestClient

    from countersign.settings import Settings
    from countersign.store.accounts import create_token, create_user
    from countersign.store.db import Database
    from countersign.web.app import create_app
    from countersign.web.validation_pool import ValidationPool

    from .bench_logic import logic_orders

    goals = 300 if quick else 1_000
    where = "the app's validation processes" if pool else "the server's threads"
    print(f"## One-goal edits of a {goals:,}-goal mission through the API ({where})")
    # Its findings (CONTRADICTION, NORM, PROPERTY, ...) are the work measured: not valid().
    base = logic_orders(goals, 50, 20)
    with tempfile.TemporaryDirectory() as folder:
        url = f"sqlite:///{Path(folder) / 'bench.db'}"
        database = Database(url)
        app = create_app(Settings(data_dir=Path(folder), database_url=url,
                                  validation_processes=2 if pool else 0), database)
        with database.session() as db:
            user = create_user(db, username="bench", role="operator",
                               password="a long harbour passphrase 1", signer=database.log_signer)
            token = create_token(db, user=user, name="bench", signer=database.log_signer)[1]
        started = time.perf_counter()
        with TestClient(app) as client:
            client.headers["Authorization"] = f"Bearer {token}"
            orders: dict[str, Any] = base.model_dump(mode="json", exclude_unset=True)
            orders["id"] = "bench"
            counter = iter(range(10**6))

            def create(mission: dict[str, Any]) -> tuple[float, float]:
                begin, cpu = time.perf_counter(), cpu_now()
                assert client.post("/api/missions", json=mission).status_code in (200, 201)
                assert client.get(f"/api/missions/{mission['id']}/report").status_code == 200
                return time.perf_counter() - begin, cpu_now() - cpu

            processes: ValidationPool | None = app.state.validation_pool if pool else None

            pool_cpu: list[float] = []

            def cpu_now() -> float:
                """CPU seconds of this process and the validation processes: on a machine
                shared with others, the figure that does not measure their load."""
                pids = processes.wait_warm() if processes is not None else []
                pool_cpu.append(sum(process_cpu(pid) for pid in pids))
                return time.process_time() + pool_cpu[-1]

            etags: list[str] = []

            def edit(field: str) -> tuple[float, float]:
                i = next(counter)
                goal = orders["goals"][goals // 2 + i % 7]
                if field == "envelope":
                    goal["envelope"]["depth_m"][1] += 1
                elif field == "cost":
                    goal["cost"] = {"energy_wh": 10 + i % 40, "duration_s": 600}
                else:
                    goal["title"] = f"Goal edited {i}"
                begin, cpu = time.perf_counter(), cpu_now()
                # As the editor's autosave: If-Match the ETag of the last save's answer.
                etag = etags[-1] if etags else client.get("/api/missions/bench").headers["etag"]
                done = client.put("/api/missions/bench/draft", json={"orders": orders},
                                  headers={"If-Match": etag})
                assert done.status_code == 200, done.text
                etags.append(done.headers["etag"])
                assert client.get("/api/missions/bench/report").status_code == 200
                return time.perf_counter() - begin, cpu_now() - cpu

            if processes is not None:
                processes.wait_warm()
            up = time.perf_counter() - started
            created = create(orders)
            first = edit("envelope")
            fresh = copy.deepcopy(orders)
            fresh["id"] = "fresh"
            full = create(fresh)
            print(f"  server start (validation processes warm) {up * 1000:.0f} ms; the mission "
                  f"created (validated in full) {created[0] * 1000:.0f} ms, "
                  f"CPU {created[1] * 1000:.0f} ms")
            print(f"  {'':<28}{'wall ms':>9} {'CPU ms':>8}  goal (wall) | a new mission "
                  "validated in full, wall / CPU ms")
            print(f"  {'first edit':<28}{first[0] * 1000:9.1f} {first[1] * 1000:8.1f}  "
                  f"< {EDIT_GOAL_MS['first']:.0f}  | {full[0] * 1000:8.1f} / "
                  f"{full[1] * 1000:.1f}", flush=True)
            for label, field in (("goal envelope", "envelope"), ("goal cost", "cost"),
                                 ("goal title", "title")):
                runs, in_pool = [], []
                for _ in range(5 if quick else 9):
                    runs.append(edit(field))
                    in_pool.append(pool_cpu[-1] - pool_cpu[-2])
                wall = sorted(r[0] for r in runs)[len(runs) // 2]
                cpu = sorted(r[1] for r in runs)[len(runs) // 2]
                print(f"  {label + ' edit, median':<28}{wall * 1000:9.1f} {cpu * 1000:8.1f}  "
                      f"< {EDIT_GOAL_MS['median']:.0f}   | {full[0] * 1000:8.1f} / "
                      f"{full[1] * 1000:.1f} ({full[0] / wall:.1f}x wall); CPU in the "
                      f"validation processes {sorted(in_pool)[len(in_pool) // 2] * 1000:.0f} ms",
                      flush=True)
        database.engine.dispose()


def bench_pirates() -> None:
    from countersign.orders.reader import read_file

    print("## Pirates (NPS AVCL), in-process")
    path = PIRATES / "missions" / "avcl" / "PiratesSeizingMerchantDefense.xml"
    if not path.exists():
        print(f"  no Pirates mission at {path}")
        return
    read = read_file(path)
    orders, given = read.orders, read.findings
    parts, logic = PartsCache(), LogicCache()
    validate(orders, given, logic_cache=logic, parts=parts)
    cold = best(5, lambda: validate(orders, given, logic_cache=LogicCache(), parts=PartsCache()))
    warm = best(5, lambda: validate(orders, given, logic_cache=logic, parts=parts))
    route = best(5, lambda: meo_check(orders))
    print(f"  validate from scratch {cold * 1000:.1f} ms, again (parts cached) {warm * 1000:.1f} ms"
          f"   | the MEO route the report ran before, alone: {route * 1000:.1f} ms", flush=True)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--quick", action="store_true", help="smaller missions")
    parser.add_argument("--pool", action="store_true", help="API through validation processes")
    parser.add_argument("--only", choices=["whole", "edit", "api", "pirates"])
    args = parser.parse_args()
    if args.only in (None, "pirates"):
        bench_pirates()
    if args.only in (None, "edit"):
        bench_edit(args.quick)
    if args.only in (None, "api"):
        bench_api(args.quick, args.pool)
    if args.only in (None, "whole"):
        bench_whole(args.quick)


if __name__ == "__main__":
    main()
