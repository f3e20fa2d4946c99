"""`countersign rehearse`: run a rehearsal without the web app.

Headless, the simulation runs as fast as it can on this thread and writes the record; with a
viser server (the default) the scene is served on 127.0.0.1 and the URL printed, so one can
watch, choose outcomes (manual source) and inject faults from the browser.
"""

from __future__ import annotations

import argparse
import contextlib
import json
import sys
import time
from pathlib import Path
from typing import TYPE_CHECKING, Any, TextIO

if TYPE_CHECKING:
    from ..orders.model import Orders
    from ..rehearse.manager import Rehearsal
    from ..rehearse.record import RehearsalRecord
    from ..verify.nesting import Nesting

# rehearse.sim.FAULTS and rehearse.sources.SOURCES, named here so that help does not import
# the simulation and viser (tests/cli/test_cli_startup.py holds them equal).
FAULTS = ("gps_loss", "nav_drift", "leak", "low_energy", "contact_close")
SOURCES = ("manual", "replay", "tour", "simulate")

EXIT_OK, EXIT_CANNOT_RUN, EXIT_UNREADABLE = 0, 1, 2
END = {"complete": "Mission Complete!", "abort": "Mission Abort!"}

DESCRIPTION = """\
Rehearse orders in a simulated world: the vehicle flies every goal in a seeded
world (areas, shipping lanes, contacts, seafloor, currents); outcomes come from the
simulation (constraint monitors, contingency rules, energy), from one path of the
exhaustive traversal (replay), from every path (tour), or from you (manual, in the browser).
The record (format countersign.rehearsal/1, with its sha256 digest) can be attached to a
submission; --html-out writes a standalone HTML replay that plays offline."""

EPILOG = f"""\
FILE is orders (JSON, AVCL, Turtle), 'example:NAME' for a built-in example or '-' for
standard input.

faults ({', '.join(FAULTS)}) apply at the start, or later with NAME@GOAL (when that goal
starts) or NAME@SECONDS (simulated time): --fault nav_drift@G4 --fault leak@3600

examples:
  countersign rehearse example:transect-survey --headless --fault nav_drift@G4
  countersign rehearse example:search-and-sample --source replay --path 5 --headless \\
      --record-out rec.json --html-out replay.html
  countersign rehearse example:search-and-sample --source manual      (open the printed URL)

team orders (a `team`, e.g. example:search-and-sample-team) rehearse every vehicle in one
world clock and one scene: a vehicle at a meeting holds there until every member naming it
has come, then all leave with one shared outcome; a wait for a partner that ended or went
past ends as the TEAM finding says (a deadlock, in words). Sources simulate or replay;
--member-path VEHICLE=N replays one member's path N; --fault VEHICLE:FAULT targets one
member (FAULT alone: every member). Headless, the joint events print one a line, each
naming its vehicle:
  countersign rehearse example:search-and-sample-team --headless --member-path vehicle-2=19

refined orders (goals with `refines`, e.g. example:search-and-sample-refined) are flown as the
flat automaton `countersign paths` lists: every goal inside a refined goal is flown and decided
(G1/G1.2#3: the third goal commenced inside G1), its time-out ends the refinement as DESIGN.md
says, --path N replays path N of `countersign paths`, NAME@G1/G1.2 waits for a goal inside,
and the summary indents a refinement's goals under its goal (then `Time-out: G1.` if it timed
out, and the outcome the refinement returned):
  countersign rehearse example:search-and-sample-refined --source replay --path 118 --headless

exit codes: 0 rehearsed, 1 the orders cannot be rehearsed (e.g. no start goal, or paths that
cannot be counted for replay/tour), 2 unreadable input or bad usage."""


class RehearseUsageError(Exception):
    pass


def add_commands(commands: Any) -> None:
    cmd = commands.add_parser(
        "rehearse", help="rehearse orders in a simulated 3D world (headless or with viser)",
        description=DESCRIPTION, epilog=EPILOG,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    cmd.add_argument("file", metavar="FILE")
    cmd.add_argument("--source", choices=SOURCES, default="simulate",
                     help="where outcomes come from (default: simulate)")
    cmd.add_argument("--path", type=int, default=None, metavar="N",
                     help="path index for --source replay (1-based, as `countersign paths`)")
    cmd.add_argument("--seed", type=int, default=0, help="world and current seed (default 0)")
    cmd.add_argument("--fault", action="append", default=[], metavar="FAULT",
                     help="inject a fault (repeatable): NAME, NAME@GOAL or NAME@SECONDS")
    cmd.add_argument("--speed", type=float, default=50.0,
                     help="simulated seconds per wall second with a viser server (default 50)")
    cmd.add_argument("--record-out", type=Path, default=None, metavar="FILE",
                     help="write the record JSON here")
    cmd.add_argument("--html-out", type=Path, default=None, metavar="FILE",
                     help="write the standalone HTML replay here")
    cmd.add_argument("--headless", action="store_true",
                     help="no browser view: simulate as fast as possible and exit")
    cmd.add_argument("--exit-when-done", action="store_true",
                     help="with a viser server: exit when the rehearsal ends (default: keep "
                          "serving until Ctrl-C)")
    cmd.add_argument("--member-path", action="append", default=[], metavar="VEHICLE=N",
                     help="team orders: this member replays path N of its own orders "
                          "(repeatable); the others follow --source (simulate or replay "
                          "path 1)")
    cmd.add_argument("--format", choices=("text", "json"), default="text")
    cmd.set_defaults(handler=cmd_rehearse)


def _load(source: str) -> Orders:
    from ..limits import MAX_INPUT_BYTES
    from ..orders.examples import example_bytes
    from ..orders.reader import read_bytes

    if source.startswith("example:"):
        try:
            data, label = example_bytes(source.removeprefix("example:")), source
        except KeyError as exc:
            raise RehearseUsageError(str(exc.args[0])) from None
    elif source == "-":
        data, label = sys.stdin.buffer.read(MAX_INPUT_BYTES + 1), "standard input"
    else:
        try:
            data, label = Path(source).read_bytes(), source
        except OSError as exc:
            raise RehearseUsageError(f"cannot read {source}: {exc.strerror or exc}") from None
    return read_bytes(data, label).orders  # OrdersReadError: cli.main reports it (exit 2)


def cmd_rehearse(args: argparse.Namespace) -> int:
    try:
        return _rehearse(args, sys.stdout)
    except RehearseUsageError as exc:
        sys.stderr.write(f"countersign rehearse: {exc}\n")
        return EXIT_UNREADABLE


def _rehearse(args: argparse.Namespace, out: TextIO) -> int:
    from ..rehearse.manager import Rehearsal, RehearsalOptions
    from ..rehearse.sim import FaultSpec

    for fault in args.fault:
        try:
            FaultSpec.parse(fault.partition(":")[2] if ":" in fault else fault)
        except ValueError as exc:
            raise RehearseUsageError(str(exc)) from None
    if args.source == "manual" and args.headless:
        raise RehearseUsageError("--source manual needs the browser view: drop --headless")
    if args.path is not None and args.source != "replay":
        raise RehearseUsageError("--path goes with --source replay")
    orders = _load(args.file)
    if orders.team is not None:
        return _rehearse_team(args, orders, out)
    if args.member_path:
        raise RehearseUsageError("--member-path goes with a team's orders; these are one "
                                 "vehicle's (use --source replay --path N)")
    if any(":" in fault for fault in args.fault):
        raise RehearseUsageError("VEHICLE:FAULT names a team member; these orders are one "
                                 "vehicle's (give the fault alone)")
    options = RehearsalOptions(source=args.source, seed=args.seed, path_index=args.path,
                               faults=tuple(args.fault), speed=args.speed)
    # Headless needs no server, unless a replay page is wanted: the scene is then drawn on a
    # private server nobody is told about, only to be recorded.
    serve = not args.headless or args.html_out is not None
    # viser prints its banner and "Server stopped" on standard output, which belongs to the
    # summary (or JSON) here: send them to standard error.
    try:
        with contextlib.redirect_stdout(sys.stderr):
            rehearsal = Rehearsal(orders, owner="cli", options=options, headless=not serve,
                                  gated=False)
    except ValueError as exc:
        sys.stderr.write(f"countersign rehearse: cannot rehearse {args.file}: {exc}\n")
        return EXIT_CANNOT_RUN
    record = _run_and_record(rehearsal, args, out)
    data = record.to_json()
    if args.format == "json":
        out.write(json.dumps({"digest": record.digest, "record": data}, indent=1) + "\n")
    else:
        from ..rehearse.sim_nesting import rehearsed_form

        _summary(data, record.digest, out, rehearsed_form(orders)[1])
    return EXIT_OK


def _run_and_record(rehearsal: Rehearsal, args: argparse.Namespace,
                    out: TextIO) -> RehearsalRecord:
    """Run the rehearsal (headless or watched), stop it, and write the record and replay files
    the options ask for."""
    try:
        if args.headless:
            rehearsal.run_headless()
        else:
            _watch(rehearsal, args, out)
    finally:
        with contextlib.redirect_stdout(sys.stderr):
            record = rehearsal.stop()
    if args.record_out is not None:
        args.record_out.write_text(
            json.dumps({**record.to_json(), "digest": record.digest}, indent=1) + "\n")
    if args.html_out is not None and record.has_replay:
        args.html_out.write_bytes(record.replay_html())
    return record


def _member_paths(texts: list[str]) -> dict[str, int]:
    paths: dict[str, int] = {}
    for text in texts:
        vehicle, sep, number = text.partition("=")
        if not sep or not vehicle or not number.isdigit() or int(number) < 1:
            raise RehearseUsageError(f"--member-path {text!r}: write VEHICLE=N with N a path "
                                     "number from 1 (as `countersign paths` of that member)")
        if vehicle in paths:
            raise RehearseUsageError(f"--member-path names {vehicle!r} twice")
        paths[vehicle] = int(number)
    return paths


def _rehearse_team(args: argparse.Namespace, orders: Orders, out: TextIO) -> int:
    """Every member's simulation in one clock; the joint events, each naming its vehicle."""
    from ..rehearse.manager import RehearsalOptions
    from ..rehearse.team_rehearsal import TeamRehearsal

    if args.source not in ("simulate", "replay"):
        raise RehearseUsageError(f"--source {args.source}: a team is rehearsed with --source "
                                 "simulate or replay (--member-path VEHICLE=N for one member)")
    if args.path is not None:
        raise RehearseUsageError("--path N replays one vehicle's orders; for a team give "
                                 "--member-path VEHICLE=N per member")
    paths = _member_paths(args.member_path)
    options = RehearsalOptions(source=args.source, seed=args.seed, faults=tuple(args.fault),
                               speed=args.speed)
    serve = not args.headless or args.html_out is not None
    try:
        with contextlib.redirect_stdout(sys.stderr):
            rehearsal = TeamRehearsal(orders, owner="cli", options=options, paths=paths,
                                      headless=not serve, gated=False)
    except ValueError as exc:
        sys.stderr.write(f"countersign rehearse: cannot rehearse {args.file}: {exc}\n")
        usage = ("paths name", "fault", "path index")
        return EXIT_UNREADABLE if any(w in str(exc) for w in usage) else EXIT_CANNOT_RUN
    record = _run_and_record(rehearsal, args, out)
    data = record.to_json()
    if args.format == "json":
        out.write(json.dumps({"digest": record.digest, "record": data}, indent=1) + "\n")
        return EXIT_OK
    team = data["team"]
    out.write(f"Team of {len(team['vehicles'])}: {', '.join(team['vehicles'])}\n")
    for line in rehearsal.team.lines():
        out.write(f"  {line}\n")
    for member in team["members"]:
        energy = member["energy"]
        out.write(f"{member['vehicle']}: {member['state']}; energy used "
                  f"{energy['used_wh']:g} Wh of {energy['capacity_wh']:g} Wh\n")
    out.write(f"Joint end: {team['joint_end']}\n")
    out.write(f"Record {record.digest}\n")
    return EXIT_OK


def _watch(rehearsal: Rehearsal, args: argparse.Namespace, out: TextIO) -> None:
    rehearsal.start()
    err = sys.stderr
    err.write(f"Rehearsal running at http://127.0.0.1:{rehearsal.port}/ "
              "(Ctrl-C to stop and write the record)\n")
    err.flush()
    announced = False
    try:
        while True:
            state = rehearsal.status()["state"]
            if state in ("finished", "stopped"):
                if args.exit_when_done:
                    return
                if not announced:
                    err.write("Rehearsal finished; still serving the scene (Ctrl-C to stop).\n")
                    announced = True
            time.sleep(0.5)
    except KeyboardInterrupt:
        err.write("\n")


def _summary(data: dict[str, Any], digest: str, out: TextIO,
             nesting: Nesting | None = None) -> None:
    """The runs goal by goal (a refined goal's goals indented under it, as traces indent
    them), the notable events, energy, time and the record's digest."""
    from ..rehearse.sim_nesting import summary_lines

    words = {"succeed": "succeed.", "fail": "fail.", "violate": "constraint."}
    for run in data["runs"]:
        if run["path_index"] is not None:
            out.write(f"Path #{run['path_index']}:\n")
        lines = summary_lines(nesting, run["goals"], run["outcomes"]) if nesting else [
            f"{goal}: {words[outcome]}"
            for goal, outcome in zip(run["goals"], run["outcomes"], strict=False)]
        for line in lines:
            out.write(f"  {line}\n")
        out.write(f"  {END.get(run['terminal_kind'], 'Mission did not end in a terminal.')}\n")
    for event in data["events"]:
        if event["kind"] in ("decision", "fault", "current", "safe_action", "error", "timeout"):
            hours, rem = divmod(int(event["t"]), 3600)
            goal = event.get("goal") or "-"
            out.write(f"  [{hours}h{rem // 60:02d}m] {goal}: {event['text'].strip()}\n")
    energy = data["energy"]
    out.write(f"Energy used {energy['used_wh']:g} Wh of {energy['capacity_wh']:g} Wh; "
              f"simulated {data['sim_time_s'] / 3600:.2f} h.\n")
    if data["rule_firings"]:
        out.write("Rules fired: " + ", ".join(f"{k} x{v}" for k, v in
                                              data["rule_firings"].items()) + "\n")
    out.write(f"Record {digest}\n")
