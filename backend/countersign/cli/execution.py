"""`countersign execution check ORDERS LOG`: which path a vehicle's execution log followed, and
its deviations from the orders. Its own module so the command line package split can move it."""

from __future__ import annotations

import argparse
import json
import sys
from datetime import UTC, datetime
from pathlib import Path
from typing import Any

from .common import load_orders, member_orders

EXIT_OK, EXIT_DEVIATION, EXIT_UNREADABLE, EXIT_UNVERIFIED = 0, 1, 2, 3
MAX_LOG_BYTES = 16 * 1024 * 1024


def add_commands(commands: Any) -> None:
    execution = commands.add_parser("execution", help="check what a vehicle did")
    actions = execution.add_subparsers(dest="execution_command", required=True,
                                       metavar="ACTION")
    check = actions.add_parser(
        "check", help="check an execution log against the orders",
        description="Read an execution log (NDJSON, one line per goal run: {\"goal\", "
        "\"outcome\": succeed|fail|violate, \"time\", \"start\", \"readings\": {quantity: "
        "value}}) and say which path of the orders it followed, numbered as `countersign "
        "paths` numbers them, or name every deviation: SKIPPED-GOAL, WRONG-TRANSITION, "
        "UNKNOWN-GOAL, CONSTRAINT (a reading breaks a constraint in scope), BUDGET (time or "
        "energy over the vehicle's budget: from energy_wh/duration_s readings, the log's ISO "
        "8601 times, or else verify's cost model), INCOMPLETE, AFTER-END. \"No deviation\" "
        "needs evidence: every goal run with start and end times, and readings for every "
        "constraint in scope; without them the run is unverified, naming what is missing. "
        "Times that cannot be real (not a time, no zone, backwards, in the future beyond "
        "clock skew) make the log unreadable. Exit 0 no deviation, 1 deviations, 2 "
        "unreadable input, 3 unverified (no deviation found, but times or readings "
        "missing). Team orders: --member VEHICLE checks that member's log against its own "
        "orders (paths numbered as in its orders alone).")
    check.add_argument("orders", metavar="ORDERS", help="orders file (or example:NAME)")
    check.add_argument("log", metavar="LOG", type=Path,
                       help="execution log: NDJSON, IMC messages (PlanControlState, "
                       "LogBookEntry outcomes, EstimatedState depth) or a MOOS alog; or a "
                       "rehearsal record (countersign.rehearsal/1), every run of it checked")
    check.add_argument("--member", metavar="VEHICLE", default=None,
                       help="team orders: check this member's run against its own orders "
                       "(a team's rehearsal record holds every member's; a log is one "
                       "member's). Required for a team, refused otherwise")
    check.add_argument("--input-format", choices=["auto", "ndjson", "imc", "alog"],
                       default="auto", help="the log's format (default: detected)")
    check.add_argument("--format", choices=["text", "json"], default="text")
    check.set_defaults(handler=cmd_execution_check)


def cmd_execution_check(args: argparse.Namespace) -> int:
    from ..export.execution_input import ExecutionInputError, to_execution_log
    from ..limits import CLOCK_SKEW
    from ..rehearse.execution import ExecutionLogError, check_execution, read_log
    from ..rehearse.execution_evidence import TimeWindow

    orders = member_orders(load_orders(args.orders, teams=True).orders, args.member,
                           what="execution check")
    try:
        with args.log.open("rb") as handle:
            data = handle.read(MAX_LOG_BYTES + 1)
        if len(data) > MAX_LOG_BYTES:
            raise ExecutionLogError(f"the log is larger than {MAX_LOG_BYTES:,} bytes")
        record = rehearsal_record(data)
        if record is not None:
            return check_record(args, orders, record)
        converted = to_execution_log(orders, data, args.input_format)
        # Without the approval at hand, only the future is out of bounds.
        window = TimeWindow.of(now=datetime.now(UTC), skew_s=CLOCK_SKEW.total_seconds())
        verdict = check_execution(orders, read_log(converted.ndjson), window)
    except OSError as exc:
        sys.stderr.write(f"countersign: cannot read {args.log}: {exc}\n")
        return EXIT_UNREADABLE
    except (ExecutionLogError, ExecutionInputError) as exc:
        sys.stderr.write(f"countersign: {args.log}: {exc}\n")
        return EXIT_UNREADABLE
    for note in converted.notes:
        sys.stderr.write(f"countersign: note: {note}\n")
    return _print_verdict(args, verdict)


def _print_verdict(args: argparse.Namespace, verdict: Any, prefix: str = "") -> int:
    if args.format == "json":
        sys.stdout.write(json.dumps(verdict.to_json()) + "\n")
    else:
        sys.stdout.write(prefix + verdict.summary() + "\n")
        for deviation in verdict.deviations:
            sys.stdout.write(f"  step {deviation.step}  {deviation.code:<16} "
                             f"{deviation.message}\n")
        evidence = verdict.evidence
        if evidence.read:
            sys.stdout.write(f"  readings for: {', '.join(evidence.read)}\n")
        for usage in verdict.usage:
            budget = "no budget" if usage.budget is None else f"budget {usage.budget:g}"
            sys.stdout.write(f"  {usage.quantity}: {'>=' if usage.lower_bound else ''}"
                             f"{usage.used:.1f} used ({usage.source}), {budget}\n")
    if verdict.deviations:
        return EXIT_DEVIATION
    return EXIT_OK if verdict.ok else EXIT_UNVERIFIED


def rehearsal_record(data: bytes) -> dict[str, Any] | None:
    """The rehearsal record these bytes hold, or None when they are an execution log."""
    from ..rehearse.record import FORMAT
    from ..strict_json import JsonPolicyError, loads

    try:
        parsed = loads(data)
    except JsonPolicyError:
        # NDJSON of several lines, IMC or an alog; or JSON the log reader refuses by line.
        return None
    return parsed if isinstance(parsed, dict) and parsed.get("format") == FORMAT else None


def check_record(args: argparse.Namespace, orders: Any, record: dict[str, Any]) -> int:
    """Every run of a rehearsal record (the member's, for a team's) through the check; the
    exit code is the worst run's."""
    from ..export.rehearsal_log import RehearsalRecordError, rehearsal_runs
    from ..rehearse.execution import ExecutionLogError, check_execution, read_log

    try:
        runs = rehearsal_runs(record, args.member)
        verdicts = [check_execution(orders, read_log(run.ndjson)) for run in runs]
    except (RehearsalRecordError, ExecutionLogError) as exc:
        sys.stderr.write(f"countersign: {args.log}: {exc}\n")
        return EXIT_UNREADABLE
    if not verdicts:
        sys.stderr.write(f"countersign: {args.log}: the record holds no run\n")
        return EXIT_UNREADABLE
    # Worst first: a deviation (1) over unverified (3) over none (0).
    codes = [_print_verdict(args, v, f"run {i + 1}: " if len(verdicts) > 1 else "")
             for i, v in enumerate(verdicts)]
    return next((c for c in (EXIT_DEVIATION, EXIT_UNVERIFIED) if c in codes), EXIT_OK)
