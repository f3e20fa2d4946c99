"""`countersign campaign run|status|cancel|worker`: rehearsal campaigns.

On the embedded SQLite database `run` simulates in this process (--workers processes) and
shows a progress bar; on PostgreSQL (COUNTERSIGN_DATABASE_URL) it queues procrastinate jobs
that `countersign campaign worker` processes run, and shows their progress.
"""

from __future__ import annotations

import argparse
import json
import sys
import time
from collections.abc import Callable
from pathlib import Path
from typing import TYPE_CHECKING, Any, TextIO

from .common import EXIT_OK, FILE_HELP, UsageError

if TYPE_CHECKING:
    from ..store.db import Database

# rehearse.sim.FAULTS and campaigns.spec limits, named here so that help does not import the
# simulation (tests/campaigns/test_campaign_units.py holds them equal).
FAULTS = ("gps_loss", "nav_drift", "leak", "low_energy", "contact_close")
MAX_SIMULATIONS = 10_000
EXIT_NOT_FINISHED = 1

DESCRIPTION = f"""\
Rehearsal campaigns: N seeded headless simulations of one set of orders over a
sweep of faults and the goals at which they are injected. The results estimate each
terminal's probability and that of any violation (95% Wilson intervals), each goal's outcome
probabilities (offered for the orders' `p`), which paths were covered (numbered as
`countersign paths`) and the energy used. Each simulation is stored once per index: a run
killed part-way is resumed with `run --resume ID` (SQLite) or by the other workers
(PostgreSQL) without counting anything twice.

Orders with a team: each simulation runs every member in one world clock, as `rehearse`
does (FAULT is injected into every member, VEHICLE:FAULT into one; simulations x members at
most {MAX_SIMULATIONS}). The results are the joint ends as `validate` names them
(`remus-100:waiting + vehicle-2:ABORT`) with their counts, the meetings completed and
deadlocked, each member's terminals, and the joint ends the verifier counts that no run
reached; a run ending where the verifier says no joint execution can is a TEAM finding."""

EPILOG = f"""\
examples:
  countersign campaign run example:search-and-sample -n 1000 --fault none --fault nav_drift \\
      --goal start --goal G3
  countersign campaign status ID
  countersign campaign cancel ID
  countersign campaign run --resume ID        (finish a campaign whose process was killed)
  countersign campaign run example:search-and-sample-team -n 50 --fault none \\
      --fault vehicle-2:nav_drift                (a team: joint ends and meetings)
  COUNTERSIGN_DATABASE_URL=postgresql://... countersign campaign worker   (PostgreSQL)

faults: none, {', '.join(FAULTS)}; at most {MAX_SIMULATIONS} simulations.
exit codes: 0 finished (or queued with --detach), 1 cancelled or not finished, 2 bad usage."""


def add_commands(commands: Any) -> None:
    cmd = commands.add_parser(
        "campaign", help="run many seeded simulations and estimate outcome probabilities",
        description=DESCRIPTION, epilog=EPILOG,
        formatter_class=argparse.RawDescriptionHelpFormatter)
    verbs = cmd.add_subparsers(dest="verb", required=True, metavar="VERB")

    run = verbs.add_parser("run", help="start (or resume) a campaign and show its progress",
                           description=DESCRIPTION, epilog=EPILOG,
                           formatter_class=argparse.RawDescriptionHelpFormatter)
    run.add_argument("file", metavar="FILE", nargs="?", help=FILE_HELP)
    run.add_argument("--mission", default=None, help="a stored mission instead of FILE")
    run.add_argument("--version", type=int, default=None, help="its version (with --mission)")
    run.add_argument("--resume", default=None, metavar="ID",
                     help="run what an unfinished campaign still lacks")
    run.add_argument("-n", "--simulations", type=int, default=100,
                     help=f"how many simulations (1 to {MAX_SIMULATIONS}; default 100)")
    run.add_argument("--fault", action="append", default=[], metavar="FAULT",
                     help="a fault of the sweep, or 'none' (repeatable; default none); a fault "
                          "no constraint, rule or vehicle reaction reads is named first; a "
                          "team's may be VEHICLE:FAULT (one member)")
    run.add_argument("--goal", action="append", default=[], metavar="GOAL",
                     help="inject the faults when this goal starts, or 'start' (repeatable; "
                          "a goal inside a refined goal reads G1/G1.2)")
    run.add_argument("--seed", type=int, default=0, help="first seed (default 0)")
    run.add_argument("--chunk", type=int, default=10,
                     help="simulations per job (default 10)")
    run.add_argument("--workers", type=int, default=1,
                     help="SQLite: simulation processes beside this one (default 1)")
    run.add_argument("--detach", action="store_true",
                     help="queue and exit (PostgreSQL: the workers run it)")
    _common(run)
    run.set_defaults(handler=cmd_run)

    status = verbs.add_parser("status", help="a campaign's progress and results")
    status.add_argument("id", metavar="ID")
    status.add_argument("--watch", action="store_true", help="follow until it ends")
    _common(status)
    status.set_defaults(handler=cmd_status)

    cancel = verbs.add_parser("cancel", help="stop a queued or running campaign")
    cancel.add_argument("id", metavar="ID")
    _common(cancel)
    cancel.set_defaults(handler=cmd_cancel)

    worker = verbs.add_parser("worker", help="run campaign jobs (PostgreSQL, procrastinate)")
    worker.add_argument("--concurrency", type=int, default=1)
    worker.add_argument("--name", default=None)
    worker.add_argument("--heartbeat", type=float, default=5.0, metavar="SECONDS",
                        help="heartbeat interval (default 5)")
    worker.add_argument("--stalled-after", type=float, default=30.0, metavar="SECONDS",
                        help="requeue jobs of workers silent this long (default 30)")
    worker.add_argument("--once", action="store_true", help="exit when the queue is empty")
    _common(worker)
    worker.set_defaults(handler=cmd_worker)


def _common(cmd: argparse.ArgumentParser) -> None:
    cmd.add_argument("--data-dir", type=Path, default=None,
                     help="the app's data directory (default as `countersign serve`)")
    if cmd.prog.split()[-1] != "worker":
        cmd.add_argument("--format", choices=("text", "json"), default="text")


def _database(args: argparse.Namespace, *, appends: bool = False) -> Database:
    """The app's database; a command that `appends` to the log (run, cancel) opens the log
    signer as the server does, so its entries carry receipts."""
    from .server import open_database

    return open_database(args, log_signer=appends)[1]


def cmd_run(args: argparse.Namespace) -> int:
    from ..errors import DomainError
    from ..jobs import is_postgres
    from ..jobs.tasks import missing_chunks

    database = _database(args, appends=True)
    if args.resume is not None:
        if args.file is not None or args.mission is not None:
            raise UsageError("--resume takes no FILE or --mission")
        campaign_id = args.resume
        try:
            chunks = missing_chunks(database, campaign_id)
        except DomainError as exc:
            raise UsageError(str(exc)) from None
    else:
        campaign_id, chunks = _create(database, args)
    if not 1 <= args.workers <= 8:
        raise UsageError("--workers must be from 1 to 8")
    if is_postgres(database):
        from ..jobs.pg import ProcrastinateRunner

        pg_runner = ProcrastinateRunner(database)
        try:
            pg_runner.enqueue(campaign_id, chunks)
        finally:
            pg_runner.close()
        sys.stderr.write(f"campaign {campaign_id}: {len(chunks)} jobs queued for "
                         "`countersign campaign worker`\n")
        if args.detach:
            sys.stdout.write(campaign_id + "\n")
            return EXIT_OK
        return _watch(database, campaign_id, args.format, sys.stdout)
    if args.detach:
        raise UsageError("--detach needs PostgreSQL workers; on SQLite the campaign runs here")
    from ..jobs.inprocess import InProcessRunner

    runner = InProcessRunner(database, workers=args.workers, processes=args.workers > 1)
    sys.stderr.write(f"campaign {campaign_id}\n")
    try:
        runner.enqueue(campaign_id, chunks)
        if not chunks:
            from ..jobs.tasks import finish_if_complete

            finish_if_complete(database, campaign_id)
        return _watch(database, campaign_id, args.format, sys.stdout, runner.idle)
    except KeyboardInterrupt:
        sys.stderr.write(f"\nstopped; resume with `countersign campaign run --resume "
                         f"{campaign_id}`\n")
        return 130
    finally:
        runner.close()


def _create(database: Database, args: argparse.Namespace) -> tuple[str, list[tuple[int, int]]]:
    from ..campaigns.spec import AT_START, NO_FAULT, CampaignSpec
    from ..errors import DomainError
    from ..orders.canonical import digest as orders_digest
    from ..orders.canonical import orders_to_json
    from ..orders.reader import orders_from_data
    from ..store import campaigns as store
    from ..store.missions import get_version
    from .common import load_orders

    if (args.file is None) == (args.mission is None):
        raise UsageError("give FILE or --mission ID --version N (or --resume ID)")
    mission_id = version = None
    if args.mission is not None:
        if args.version is None:
            raise UsageError("--mission needs --version N")
        with database.session(write=False) as db:
            try:
                stored = get_version(db, args.mission, args.version)
            except DomainError as exc:
                raise UsageError(str(exc)) from None
            data = stored.orders
        orders = orders_from_data(data)
        mission_id, version = args.mission, args.version
    else:
        orders = load_orders(args.file, teams=True).orders
        data = orders_to_json(orders)
    try:
        spec = CampaignSpec.build(simulations=args.simulations,
                                  faults=args.fault or [NO_FAULT],
                                  goals=args.goal or [AT_START], seed=args.seed,
                                  chunk=args.chunk, orders=orders)
    except DomainError as exc:
        raise UsageError(str(exc)) from None
    from ..campaigns.team import sweep_fault_reach

    # Said before the run: a fault nothing reacts to only repeats the runs without it.
    for idle in (r for r in sweep_fault_reach(orders, spec.faults) if not r.reacts):
        sys.stderr.write(f"warning: {idle.because}\n")
    with database.session() as db:
        row = store.create(db, orders=data, orders_digest=orders_digest(orders),
                           spec=spec.to_json(), simulations=spec.simulations, owner=None,
                           mission_id=mission_id, version=version,
                           signer=database.log_signer)
        campaign_id = row.id
    return campaign_id, spec.chunks()


def _watch(database: Database, campaign_id: str, fmt: str, out: TextIO,
           idle: Callable[[], bool] | None = None) -> int:
    """Progress until the campaign ends; with `idle` (this process runs the jobs), also
    when the jobs have all ended and the campaign is still active, rather than wait forever."""
    from tqdm import tqdm

    from ..store import campaigns as store

    with database.session(write=False) as db:
        total = store.get(db, campaign_id).simulations
    with tqdm(total=total, unit="sim", file=sys.stderr, dynamic_ncols=True,
              desc=f"campaign {campaign_id}") as bar:
        while True:
            # Read before the campaign's state: a job that finishes it ends after sealing it.
            ended = idle is not None and idle()
            with database.session(write=False) as db:
                row = store.get(db, campaign_id)
                state = row.state
                done = store.count_done(db, campaign_id)
            bar.update(done - bar.n)
            if state not in store.ACTIVE_STATES:
                break
            if ended:
                sys.stderr.write(f"\ncampaign {campaign_id}: its jobs ended with {done} of "
                                 f"{total} simulations stored (see the errors above); resume "
                                 f"with `countersign campaign run --resume {campaign_id}`\n")
                return EXIT_NOT_FINISHED
            time.sleep(0.5)
    return _print_status(database, campaign_id, fmt, out)


def _print_status(database: Database, campaign_id: str, fmt: str, out: TextIO) -> int:
    from ..store import campaigns as store

    with database.session(write=False) as db:
        data = store.summary(db, store.get(db, campaign_id))
    if fmt == "json":
        out.write(json.dumps(data, indent=1, default=str) + "\n")
    else:
        out.write(status_text(data))
    return EXIT_OK if data["state"] == "finished" else EXIT_NOT_FINISHED


def status_text(data: dict[str, Any]) -> str:
    lines = [f"Campaign {data['id']}: {data['state']}, {data['done']} of "
             f"{data['simulations']} simulations."]
    results = data.get("results")
    if not results:
        return "\n".join(lines) + "\n"
    if "team" in results:
        return "\n".join(lines + team_lines(results["team"])) + "\n"

    def line(name: str, e: dict[str, Any]) -> str:
        low, high = e["ci"]
        return f"  {name:<16} {e['p']:.3f}  [{low:.3f}, {high:.3f}]  ({e['count']})"

    lines.append("Estimated probabilities (95% Wilson intervals):")
    for terminal, estimate in results["terminals"].items():
        lines.append(line(terminal, estimate))
    lines.append(line("any violation", results["any_violation"]))
    coverage = results["coverage"]
    covered = ", ".join(f"#{p['path']}" for p in coverage["paths"])
    lines.append(f"Paths covered: {coverage['covered']} of {coverage['total_paths']}"
                 + (f": {covered}" if covered else ""))
    energy = results["energy_wh"]
    lines.append(f"Energy used: mean {energy['mean']} Wh, min {energy['min']}, "
                 f"max {energy['max']}")
    hist = energy["histogram"]
    peak = max(hist["counts"], default=0) or 1
    for i, count in enumerate(hist["counts"]):
        lines.append(f"  {hist['edges'][i]:>9.1f} Wh {'#' * round(40 * count / peak)} {count}")
    lines.append("Per-goal outcome estimates (offered for the orders' p):")
    for goal, g in results["goals"].items():
        if g["visits"]:
            parts = ", ".join(f"{o} {g[o]['p']:.3f}" for o in ("succeed", "fail", "violate"))
            lines.append(f"  {goal}: {parts} ({g['visits']} visits)")
    return "\n".join(lines) + "\n"


def team_lines(team: dict[str, Any]) -> list[str]:
    """A team campaign's joint table, meetings, member terminals, coverage and findings."""
    lines = ["Joint ends (runs, estimated probability [95% Wilson], joint executions the "
             "verifier counts):"]
    for row in team["joint"]:
        low, high = row["ci"]
        verifier = "impossible" if row["possible"] is False else row["executions"]
        lines.append(f"  {row['count']:>6}  {row['p']:.3f} [{low:.3f}, {high:.3f}]  "
                     f"{verifier!s:>10}  {row['end']}")
    if team["unfinished"]["count"]:
        lines.append(f"  {team['unfinished']['count']:>6}  stopped by a bound (no joint end)")
    for meeting in team["meetings"]:
        outcomes = ", ".join(f"{o} {n}" for o, n in meeting["outcomes"].items() if n)
        lines.append(f"Meeting {meeting['meet']} ({', '.join(meeting['vehicles'])}): completed "
                     f"{meeting['completed']['count']}" + (f" ({outcomes})" if outcomes else "")
                     + f", deadlocked {meeting['deadlocked']['count']}")
    for member in team["members"]:
        ends = ", ".join(f"{t} {e['count']}" for t, e in member["terminals"].items())
        lines.append(f"  {member['vehicle']}: {ends}; paths covered "
                     f"{member['covered_paths']} of {member['total_paths']}")
    coverage = team["coverage"]
    if coverage["checked"]:
        lines.append(f"Joint ends reached: {coverage['reached']} of {coverage['possible']} "
                     "the verifier counts" + (f"; never reached: {'; '.join(coverage['missed'])}"
                                              if coverage["missed"] else ""))
    else:
        lines.append("Joint ends not held against the verifier (its joint counts are missing).")
    lines += [f"error TEAM  {f['message']}" for f in team["findings"]]
    return lines


def cmd_status(args: argparse.Namespace) -> int:
    from ..errors import NotFound

    database = _database(args)
    try:
        if args.watch:
            return _watch(database, args.id, args.format, sys.stdout)
        return _print_status(database, args.id, args.format, sys.stdout)
    except NotFound as exc:
        raise UsageError(str(exc)) from None


def cmd_cancel(args: argparse.Namespace) -> int:
    from ..errors import DomainError
    from ..store import campaigns as store

    database = _database(args, appends=True)
    try:
        with database.session() as db:
            row = store.cancel(db, args.id, actor=None, signer=database.log_signer)
            done = store.count_done(db, row.id)
    except DomainError as exc:
        raise UsageError(str(exc)) from None
    sys.stdout.write(f"campaign {args.id}: cancelled after {done} of {row.simulations} "
                     "simulations\n")
    return EXIT_OK


def cmd_worker(args: argparse.Namespace) -> int:
    from ..jobs import is_postgres
    from ..jobs.pg import run_worker

    database = _database(args)
    if not is_postgres(database):
        raise UsageError("campaign workers need PostgreSQL (COUNTERSIGN_DATABASE_URL); on "
                         "SQLite `countersign campaign run` simulates in its own process")
    if not 1 <= args.concurrency <= 8:
        raise UsageError("--concurrency must be from 1 to 8")
    run_worker(database.url, concurrency=args.concurrency, name=args.name,
               heartbeat_s=args.heartbeat, stalled_after_s=args.stalled_after,
               wait=not args.once)
    return EXIT_OK
