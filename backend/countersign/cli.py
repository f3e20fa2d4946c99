"""The `countersign` command line (DESIGN.md, Command line).

Exit codes: 0 no errors, 1 error findings (or a mission that cannot run), 2 unreadable input
or bad usage, 3 an internal error (reported in one line; COUNTERSIGN_DEBUG=1 shows the trace).
"""

from __future__ import annotations

import argparse
import json
import math
import os
import sys
from collections.abc import Sequence
from pathlib import Path
from typing import TYPE_CHECKING, TextIO

from . import __version__
from .orders.examples import example_bytes, example_names
from .orders.reader import OrdersReadError, ReadResult, read_bytes, read_file
from .rehearse.checks import validate_with_rules
from .verify.graph import build_graph
from .verify.paths import (
    ANSWER,
    END_LINE,
    QUESTION,
    commence_line,
    count_paths,
    iter_path_lines,
    iter_paths,
    trace_text,
)
from .verify.report import SOLVER_BUDGET_S, Report
from .verify.structure import check_structure

if TYPE_CHECKING:
    from .store.db import Database
    from .web.settings import Settings

EXIT_OK, EXIT_FINDINGS, EXIT_UNREADABLE, EXIT_INTERNAL = 0, 1, 2, 3

ANSWERS = {
    "s": "succeed", "succeed": "succeed", "success": "succeed",
    "f": "fail", "fail": "fail", "failure": "fail",
    "c": "violate", "constraint": "violate", "x": "violate", "violate": "violate",
}


class UsageError(Exception):
    """Bad input the user can fix; printed without a trace, exit code 2."""


def _load(source: str) -> ReadResult:
    """Orders from a path, `-` for standard input, or `example:NAME` for a built-in."""
    if source.startswith("example:"):
        try:
            return read_bytes(example_bytes(source.removeprefix("example:")), source)
        except KeyError as exc:
            raise UsageError(str(exc.args[0])) from None
    if source == "-":
        from .orders.reader import MAX_INPUT_BYTES

        return read_bytes(sys.stdin.buffer.read(MAX_INPUT_BYTES + 1), "standard input")
    return read_file(source)


def _print_report_text(report: Report, out: TextIO) -> None:
    out.write(f"Mission {report.mission}  {report.digest}\n")
    errors = sum(f.severity == "error" for f in report.findings)
    warnings = len(report.findings) - errors
    for finding in report.findings:
        subjects = ", ".join(finding.subjects)
        out.write(f"  {finding.severity:<7} {finding.code:<13} [{subjects}]\n")
        out.write(f"          {finding.message}\n")
    if report.paths is None:
        out.write("Paths: not countable until the errors above are fixed.\n")
    else:
        parts = ", ".join(f"{n} to {t}" for t, n in report.paths.by_terminal.items())
        out.write(f"Paths: {report.paths.total} ({parts})\n")
    for quantity, worst in (report.costs or {}).items():
        limit = f" of budget {worst.budget:g}" if worst.budget is not None else ""
        out.write(f"Worst {quantity}: {worst.total:g}{limit}\n")
    verdict = "OK" if report.ok else "NOT OK"
    out.write(f"{verdict}: {errors} error(s), {warnings} warning(s).\n")


def _print_explanation(report: Report, out: TextIO) -> None:
    explanation = report.explanation or {}
    out.write("\nWhy (facts the Mission Execution Ontology infers, with their rules):\n")
    for fact in explanation.get("facts", []):
        rule = f" [{fact['rule']}]" if fact.get("rule") else ""
        out.write(f"  {fact['subject']} {fact['property']} {fact['object']}{rule}\n")
    scope = explanation.get("constraint_scope") or {}
    if scope:
        out.write("Constraint scope after C3 (mission constraints apply to every goal):\n")
        for constraint, goals in scope.items():
            out.write(f"  {constraint}: {', '.join(goals)}\n")


def _budget_seconds(text: str) -> float:
    try:
        value = float(text)
    except ValueError:
        value = math.nan
    if not 0 <= value <= 3600:  # also refuses nan and inf
        raise argparse.ArgumentTypeError(f"give seconds from 0 to 3600, not {text!r}")
    return value


def cmd_validate(args: argparse.Namespace) -> int:
    loaded = _load(args.file)
    report = validate_with_rules(loaded.orders, loaded.findings,
                                 solver_budget_s=args.solver_budget)
    if args.format == "json":
        json.dump(report.to_json(explain=args.explain), sys.stdout, indent=2)
        sys.stdout.write("\n")
    else:
        _print_report_text(report, sys.stdout)
        if args.explain:
            _print_explanation(report, sys.stdout)
    return EXIT_OK if report.ok else EXIT_FINDINGS


def _refuse_structural_errors(loaded: ReadResult, why: str) -> int | None:
    """Print the structural errors that stop a command (why: what cannot be done), if any."""
    errors = [f for f in check_structure(loaded.orders) if f.severity == "error"]
    if not errors:
        return None
    sys.stderr.write(f"countersign: {why}:\n")
    for finding in errors[:10]:
        sys.stderr.write(f"  {finding.code}: {finding.message}\n")
    return EXIT_FINDINGS


def cmd_paths(args: argparse.Namespace) -> int:
    loaded = _load(args.file)
    graph = build_graph(loaded.orders)
    counts = count_paths(graph)
    if counts is None:
        refused = _refuse_structural_errors(
            loaded, f"the paths of {args.file} cannot be enumerated")
        return refused if refused is not None else EXIT_FINDINGS
    out = sys.stdout
    if args.format == "trace":
        for path in iter_paths(graph, counts, args.offset, args.limit):
            out.write(trace_text(graph, path) + "\n")
    else:
        for line in iter_path_lines(graph, counts, args.offset, args.limit):
            out.write(line + "\n")
    out.flush()
    return EXIT_OK


def _ask(prompt_echo: bool) -> str | None:
    """One answer from the operator: the outcome, or None at end of input."""
    while True:
        sys.stdout.write(f"{QUESTION} ")
        sys.stdout.flush()
        line = sys.stdin.readline()
        if not line:
            sys.stdout.write("\n")
            return None
        answer = ANSWERS.get(line.strip().lower().rstrip("."))
        if answer is not None:
            if prompt_echo:
                sys.stdout.write(f"{ANSWER[answer]}.\n")
            return answer
        if prompt_echo:
            sys.stdout.write(f"{line.strip()}\n")
        sys.stdout.write(
            "Please answer s (the goal succeeded), f (it failed) or c (it ended with an "
            "imminent constraint violation).\n"
        )


def cmd_run(args: argparse.Namespace) -> int:
    loaded = _load(args.file)
    refused = _refuse_structural_errors(loaded, "these orders cannot be executed until fixed")
    if refused is not None:
        return refused
    graph = build_graph(loaded.orders)
    assert graph.start is not None
    echo = not sys.stdin.isatty()
    sys.stdout.write("?- execute_mission.\n")
    node = graph.start
    while not graph.is_terminal(node):
        goal = graph.goals[node]
        sys.stdout.write(commence_line(goal.label) + "\n")
        answer = _ask(echo)
        if answer is None:
            sys.stdout.write(f"Mission execution stopped: no outcome given for {goal.id}.\n")
            return EXIT_FINDINGS
        node = graph.succ[node][("succeed", "fail", "violate").index(answer)]
    sys.stdout.write(END_LINE[graph.terminal(node).kind] + "\n")
    return EXIT_OK


def cmd_export(args: argparse.Namespace) -> int:
    from .rehearse.plain import write_for_supervisor

    loaded = _load(args.file)
    sys.stdout.write(write_for_supervisor(loaded.orders, args.format))
    return EXIT_OK


def cmd_explain(args: argparse.Namespace) -> int:
    from .verify.logic import UnknownIds, explain_goal_set, format_goal_set

    loaded = _load(args.file)
    goals = [g for g in args.goals.split(",") if g] if args.goals else None
    constraints = [c for c in args.constraints.split(",") if c] if args.constraints else None
    try:
        result = explain_goal_set(loaded.orders, goals, constraints)
    except UnknownIds as exc:
        raise UsageError(str(exc)) from None
    if args.format == "json":
        sys.stdout.write(json.dumps(result.to_json(), indent=2) + "\n")
    else:
        sys.stdout.write(format_goal_set(result).rstrip("\n") + "\n")
    return EXIT_OK if result.consistent is True else EXIT_FINDINGS


def cmd_examples(args: argparse.Namespace) -> int:
    if args.name is None:
        for name in example_names():
            sys.stdout.write(f"{name}\n")
        return EXIT_OK
    try:
        sys.stdout.write(example_bytes(args.name).decode("utf-8"))
    except KeyError as exc:
        raise UsageError(str(exc.args[0])) from None
    return EXIT_OK


def _database(args: argparse.Namespace) -> tuple[Settings, Database]:
    from .store.db import Database, DatabaseTooNew
    from .web.settings import Settings

    settings = Settings.from_environment(data_dir=args.data_dir)
    settings.prepare()
    database = Database(settings.database_url)
    try:
        database.migrate()
    except DatabaseTooNew as exc:
        raise UsageError(str(exc)) from None
    # What the CLI appends to the log (users, demo missions) is receipted by the log signer.
    from .approvals.signer import SignerError
    from .web.log_signer import open_log_signer

    try:
        database.log_signer = open_log_signer(settings, database)
    except SignerError as exc:
        raise UsageError(str(exc)) from None
    return settings, database


def _seed_demo(database: Database) -> None:
    import secrets

    from sqlalchemy import select

    from .store.accounts import create_user
    from .store.missions import create_mission
    from .store.tables import Mission, User

    with database.session() as db:
        created = []
        for role in ("operator", "supervisor", "auditor", "admin"):
            name = f"demo-{role}"
            if db.scalar(select(User).where(User.username == name)) is None:
                password = secrets.token_urlsafe(12)
                create_user(db, username=name, role=role, password=password,
                            display_name=f"Demo {role}")
                created.append((name, role, password))
        operator = db.scalar(select(User).where(User.username == "demo-operator"))
        assert operator is not None
        for name in example_names():
            if db.get(Mission, name) is None:
                orders = read_bytes(example_bytes(name), name).orders
                create_mission(db, orders=orders, author=operator)
    if created:
        sys.stderr.write("Demo users (one-time passwords, shown only now):\n")
        for name, role, password in created:
            sys.stderr.write(f"  {name:<18} {role:<11} {password}\n")
    else:
        sys.stderr.write("Demo users exist already (their passwords were shown when created).\n")


def _has_users(database: Database) -> bool:
    from sqlalchemy import select

    from .store.tables import User

    with database.session() as db:
        return db.scalar(select(User.id).limit(1)) is not None


def cmd_serve(args: argparse.Namespace) -> int:
    import uvicorn

    from .web.app import create_app
    from .web.workers import serve_workers

    if args.validation_processes is not None:
        if not 0 <= args.validation_processes <= 64:
            raise UsageError("--validation-processes must be from 0 to 64")
        # Read by Settings here and in every server process.
        os.environ["COUNTERSIGN_VALIDATION_PROCESSES"] = str(args.validation_processes)
    settings, database = _database(args)
    if args.demo:
        _seed_demo(database)
    elif not _has_users(database):
        sys.stderr.write(
            "No accounts yet. Create the first admin with\n"
            "  countersign users create --username admin --role admin"
            + (f" --data-dir {args.data_dir}" if args.data_dir else "")
            + "\nor start with --demo for demo users and the built-in examples.\n"
        )
    sys.stderr.write(
        f"Countersign {__version__} on http://{args.host}:{args.port}/ "
        f"(database: {database.engine.url.render_as_string(hide_password=True)})\n"
    )
    if args.workers <= 1:
        uvicorn.run(create_app(settings, database), host=args.host, port=args.port,
                    log_level="info")
        return EXIT_OK
    # Several server processes: each builds its app from the environment (the database is
    # migrated above, once, before any of them starts). The app keeps no state that another
    # process could contradict: sessions, tokens, rate limiting, reports and the log live in
    # the database; the in-process caches (reports, solver results, the log's Merkle tree) are
    # pure or checked against the database on use.
    database.engine.dispose()
    os.environ["COUNTERSIGN_DATA_DIR"] = str(settings.data_dir)
    os.environ["COUNTERSIGN_DATABASE_URL"] = settings.database_url
    return serve_workers("countersign.web.app:app_from_environment", host=args.host,
                         port=args.port, workers=args.workers, log_level="info")


def cmd_users_create(args: argparse.Namespace) -> int:
    import getpass
    import secrets

    from .store.accounts import AccountError, create_user

    _, database = _database(args)
    generated = False
    if args.password_stdin:
        password = sys.stdin.readline().rstrip("\n")
    elif sys.stdin.isatty():
        password = getpass.getpass(f"Password for {args.username}: ")
    else:
        password, generated = secrets.token_urlsafe(12), True
    try:
        with database.session() as db:
            create_user(db, username=args.username, role=args.role, password=password,
                        display_name=args.display_name or args.username)
    except AccountError as exc:
        raise UsageError(str(exc)) from None
    sys.stdout.write(f"Created {args.role} {args.username}.\n")
    if generated:
        sys.stdout.write(f"One-time password: {password}\n")
    return EXIT_OK


def _non_negative(text: str) -> int:
    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r} is not a whole number") from None
    if value < 0:
        raise argparse.ArgumentTypeError("must be 0 or more")
    return value


FILE_HELP = (
    "orders JSON (countersign.orders/1) or AVCL XML; '-' reads standard input, "
    "'example:NAME' a built-in example"
)


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog="countersign",
        description=(
            "Verify, traverse and rehearse mission orders for uncrewed vehicles, "
            "so that a supervisor can sign exactly what the vehicle will do."
        ),
        epilog="Exit codes: 0 ok, 1 error findings, 2 unreadable input or bad usage.",
    )
    parser.add_argument("--version", action="version", version=f"countersign {__version__}")
    commands = parser.add_subparsers(dest="command", required=True, metavar="COMMAND")

    validate_cmd = commands.add_parser(
        "validate",
        help="check orders: structure, paths, budget, contradictions, norms, properties, "
        "contingency rules",
        description="Check orders and count every path. Exit 0 no errors, 1 errors, "
        "2 unreadable input. The command line has no vehicle registry: orders must carry the "
        "profile of their target vehicle, or VEHICLE is reported (an error).",
    )
    validate_cmd.add_argument("file", metavar="FILE", help=FILE_HELP)
    validate_cmd.add_argument("--format", choices=["text", "json"], default="text")
    validate_cmd.add_argument(
        "--explain", action="store_true",
        help="also show why: the facts the MEO infers (includes, canIdentify, hasCapability, "
        "performableBy, constraint scope after C3)",
    )
    validate_cmd.add_argument(
        "--solver-budget", type=_budget_seconds, default=SOLVER_BUDGET_S, metavar="SECONDS",
        help=f"solver time for the whole validation (default {SOLVER_BUDGET_S:g}, as the "
        "server allows); what it leaves undecided is reported as a warning")
    validate_cmd.set_defaults(handler=cmd_validate)

    paths_cmd = commands.add_parser(
        "paths",
        help="enumerate every path lazily (succeed, fail, violate first)",
        description="Enumerate the paths from the start goal to a terminal, depth first in "
        "the order succeed, fail, violate. 'json' writes one JSON object per line (NDJSON): "
        '{"index", "goals", "outcomes", "terminal"}; \'trace\' writes Figure 6 traces.',
    )
    paths_cmd.add_argument("file", metavar="FILE", help=FILE_HELP)
    paths_cmd.add_argument("--limit", type=_non_negative, default=None, help="at most N paths")
    paths_cmd.add_argument(
        "--offset", type=_non_negative, default=0, help="skip the first N paths (instantly)"
    )
    paths_cmd.add_argument(
        "--format", choices=["json", "ndjson", "trace"], default="json",
        help="json/ndjson: one path per line; trace: execution traces",
    )
    paths_cmd.set_defaults(handler=cmd_paths)

    run_cmd = commands.add_parser(
        "run",
        help="execute the orders interactively (the MEE of seed 000 Figure 6)",
        description="Commence each goal and ask whether it succeeded (s), failed (f) or ended "
        "with an imminent constraint violation (c), until the mission completes or aborts.",
    )
    run_cmd.add_argument("file", metavar="FILE", help=FILE_HELP)
    run_cmd.set_defaults(handler=cmd_run)

    export_cmd = commands.add_parser(
        "export",
        help="write orders as plain language, JSON, DOT, MEO Turtle, NPS MEO 3.0 Turtle or AVCL",
        description="Convert orders between formats: the plain-language orders a supervisor "
        "reads (seed 000 Figures 3 and 4; with a \"Contingency rules\" section, one sentence "
        "per rule, when the orders or their vehicle carry rules), orders JSON, a Graphviz DOT "
        "graph, MEO Turtle (lossless), an NPS MEO 3.0 Turtle view, or AVCL XML.",
    )
    export_cmd.add_argument("file", metavar="FILE", help=FILE_HELP)
    export_cmd.add_argument(
        "--format", choices=["plain", "json", "dot", "turtle", "nps-turtle", "avcl"],
        default="plain",
    )
    export_cmd.set_defaults(handler=cmd_export)

    explain_cmd = commands.add_parser(
        "explain",
        help="can these goals and constraints hold together? (minimal incompatible subset)",
        description="Check whether a set of goals and the constraints in their scope can hold "
        "together (z3). If not, print a minimal incompatible subset: removing any one of its "
        "members makes the rest consistent. Exit 0 consistent, 1 incompatible or undecided, "
        "2 unreadable input or unknown ids.",
    )
    explain_cmd.add_argument("file", metavar="FILE", help=FILE_HELP)
    explain_cmd.add_argument("--goals", default=None,
                             help="comma-separated goal ids (default: every goal)")
    explain_cmd.add_argument(
        "--constraints", default=None,
        help="comma-separated constraint ids (default: every constraint applying to the goals)",
    )
    explain_cmd.add_argument("--format", choices=["text", "json"], default="text")
    explain_cmd.set_defaults(handler=cmd_explain)

    examples_cmd = commands.add_parser(
        "examples", help="list the built-in example orders, or print one"
    )
    examples_cmd.add_argument("name", nargs="?", help="print this example's orders JSON")
    examples_cmd.set_defaults(handler=cmd_examples)

    serve_cmd = commands.add_parser(
        "serve",
        help="run the web app",
        description="Run the Countersign web app. Data lives in --data-dir (default: the "
        "per-user data directory, e.g. ~/.local/share/countersign) unless COUNTERSIGN_DATABASE_URL "
        "names a database.",
    )
    serve_cmd.add_argument("--host", default="127.0.0.1")
    serve_cmd.add_argument("--port", type=int, default=8000)
    serve_cmd.add_argument("--data-dir", type=Path, default=None)
    serve_cmd.add_argument(
        "--workers", type=int, default=1, metavar="N",
        help="server processes (default 1), each with its own listening socket on the port "
        "so that connections spread over them; more use more cores: on SQLite they share the "
        "one writer, on PostgreSQL they scale reads and validation",
    )
    serve_cmd.add_argument(
        "--validation-processes", type=int, default=None, metavar="N",
        help="processes that validate orders beside each server process, at a lower "
        "priority so that reads go first, each user queued fairly so that one user's heavy "
        "validation leaves a process for another's edit (default 2, or "
        "COUNTERSIGN_VALIDATION_PROCESSES; 0: validate in the server's own threads)",
    )
    serve_cmd.add_argument(
        "--demo", action="store_true",
        help="seed demo users (printing one-time passwords) and the built-in examples",
    )
    serve_cmd.set_defaults(handler=cmd_serve)

    users_cmd = commands.add_parser("users", help="manage accounts (e.g. the first admin)")
    users_sub = users_cmd.add_subparsers(dest="users_command", required=True, metavar="ACTION")
    create_cmd = users_sub.add_parser(
        "create", help="create an account",
        description="Create an account in the database of --data-dir (or "
        "COUNTERSIGN_DATABASE_URL). The password is read with --password-stdin, asked for on "
        "a terminal, or generated and printed once.",
    )
    create_cmd.add_argument("--username", required=True)
    create_cmd.add_argument("--role", required=True,
                            choices=["operator", "supervisor", "auditor", "admin"])
    create_cmd.add_argument("--display-name", default="")
    create_cmd.add_argument("--password-stdin", action="store_true",
                            help="read the password from the first line of standard input")
    create_cmd.add_argument("--data-dir", type=Path, default=None)
    create_cmd.set_defaults(handler=cmd_users_create)

    from .cli_approvals import add_commands as add_approval_commands
    from .cli_plan import add_commands as add_plan_commands
    from .cli_rehearse import add_commands as add_rehearse_commands
    from .cli_rules import add_commands as add_rules_commands

    add_plan_commands(commands)
    add_rules_commands(commands)
    add_rehearse_commands(commands)
    add_approval_commands(commands)
    from .cli_witness import add_commands as add_witness_commands

    add_witness_commands(commands)
    from .cli_charts import add_commands as add_chart_commands

    add_chart_commands(commands)
    return parser


def main(argv: Sequence[str] | None = None) -> int:
    parser = build_parser()
    args = parser.parse_args(argv)
    try:
        code: int = args.handler(args)
        return code
    except OrdersReadError as exc:
        sys.stderr.write(f"countersign: cannot read {getattr(args, 'file', 'input')}:\n")
        for line in exc.summary().splitlines():
            sys.stderr.write(f"  {line}\n")
        return EXIT_UNREADABLE
    except UsageError as exc:
        sys.stderr.write(f"countersign: {exc}\n")
        return EXIT_UNREADABLE
    except BrokenPipeError:
        # The reader (e.g. `| head`) has gone; that is not an error of ours.
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, sys.stdout.fileno())
        return EXIT_OK
    except KeyboardInterrupt:
        sys.stderr.write("\ncountersign: interrupted\n")
        return 130
    except Exception as exc:
        if os.environ.get("COUNTERSIGN_DEBUG"):
            raise
        sys.stderr.write(
            f"countersign: internal error ({type(exc).__name__}: {exc}); "
            "set COUNTERSIGN_DEBUG=1 for details\n"
        )
        return EXIT_INTERNAL


if __name__ == "__main__":
    sys.exit(main())
