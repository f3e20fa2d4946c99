"""The server commands: serve and users create (the database, the web app)."""

from __future__ import annotations

import argparse
import sys
from functools import partial
from pathlib import Path
from typing import TYPE_CHECKING, Any

from .. import __version__
from .common import EXIT_OK, UsageError

if TYPE_CHECKING:
    from ..settings import Settings
    from ..store.db import Database


def open_database(args: argparse.Namespace, *, validation_processes: int | None = None,
                  log_signer: bool = True) -> tuple[Settings, Database]:
    """The app's database for --data-dir (or COUNTERSIGN_DATABASE_URL), migrated. With
    `log_signer` (any command that appends to the log) the log signer is opened as the server
    opens it, so the entries the command appends carry its receipts as the web app's do."""
    from ..settings import Settings
    from ..store.db import Database, DatabaseTooNew

    settings = Settings.from_environment(data_dir=args.data_dir,
                                         validation_processes=validation_processes)
    settings.prepare()
    database = Database(settings.database_url)
    try:
        database.migrate()
    except DatabaseTooNew as exc:
        raise UsageError(str(exc)) from None
    if log_signer:
        from ..approvals.signer import SignerError
        from ..services.log_signer import open_log_signer

        try:
            database.log_signer = open_log_signer(settings, database)
        except SignerError as exc:
            raise UsageError(str(exc)) from None
    return settings, database


def _seed_demo(database: Database) -> None:
    import secrets

    from sqlalchemy import select

    from ..orders.examples import example_bytes, example_names
    from ..orders.reader import read_bytes
    from ..store.accounts import create_user
    from ..store.missions import create_mission
    from ..store.tables import Mission, User
    from ..store.vehicles import seed_registry

    with database.session() as db:
        created = []
        for role in ("operator", "supervisor", "auditor", "admin"):
            name = f"demo-{role}"
            if db.scalar(select(User).where(User.username == name)) is None:
                password = secrets.token_urlsafe(12)
                create_user(db, username=name, role=role, password=password,
                            display_name=f"Demo {role}", signer=database.log_signer)
                created.append((name, role, password))
        operator = db.scalar(select(User).where(User.username == "demo-operator"))
        assert operator is not None
        admin = db.scalar(select(User).where(User.username == "demo-admin"))
        assert admin is not None
        examples = {name: read_bytes(example_bytes(name), name).orders for name in example_names()}
        # The examples' vehicles into the registry first, so that a mission created in the
        # browser can pick one and is checked against its profile.
        seeded = seed_registry(
            db, [v for orders in examples.values() for v in orders.vehicles or []], admin,
            signer=database.log_signer)
        for name, orders in examples.items():
            if db.get(Mission, name) is None:
                create_mission(db, orders=orders, author=operator, signer=database.log_signer)
    if seeded:
        sys.stderr.write(f"Vehicle registry: added {', '.join(seeded)} from the examples.\n")
    if created:
        sys.stderr.write("Demo users (one-time passwords, shown only now):\n")
        for name, role, password in created:
            sys.stderr.write(f"  {name:<18} {role:<11} {password}\n")
    else:
        sys.stderr.write("Demo users exist already (their passwords were shown when created).\n")


def _has_users(database: Database) -> bool:
    from sqlalchemy import select

    from ..store.tables import User

    with database.session() as db:
        return db.scalar(select(User.id).limit(1)) is not None


def cmd_serve(args: argparse.Namespace) -> int:
    import uvicorn

    from ..settings import MAX_VALIDATION_PROCESSES
    from ..web.app import create_app

    if args.validation_processes is not None and not (
            0 <= args.validation_processes <= MAX_VALIDATION_PROCESSES):
        raise UsageError(f"--validation-processes must be from 0 to {MAX_VALIDATION_PROCESSES}")
    settings, database = open_database(args, validation_processes=args.validation_processes)
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
    # Several server processes: each builds its app from these settings after gunicorn forks
    # it (the database is migrated above, once, before any of them starts). The app keeps no
    # state that another process could contradict: sessions, tokens, rate limiting, reports
    # and the log live in the database; the in-process caches (reports, solver results, the
    # log's Merkle tree) are pure or checked against the database on use.
    database.engine.dispose()
    from ..web.gunicorn_server import serve_workers
    from ..web.host_pool import HostPool

    # One validation pool for all of them, so that its fair queue sees every user's work on
    # the host (web/host_pool.py); started before gunicorn forks, ended after it stops.
    shared = settings.validation_processes > 0 and not args.pool_per_process
    host_pool = HostPool(settings.validation_processes) if shared else None
    try:
        return serve_workers(
            partial(create_app, settings,
                    host_pool=host_pool.address if host_pool is not None else None),
            host=args.host, port=args.port, workers=args.workers, log_level="info",
            reuse_port=not args.shared_socket)
    finally:
        if host_pool is not None:
            host_pool.stop()


def cmd_users_create(args: argparse.Namespace) -> int:
    import getpass
    import secrets

    from ..store.accounts import AccountError, create_user

    _, database = open_database(args)
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
                        display_name=args.display_name or args.username,
                        signer=database.log_signer)
    except AccountError as exc:
        raise UsageError(str(exc)) from None
    sys.stdout.write(f"Created {args.role} {args.username}.\n")
    if generated:
        sys.stdout.write(f"One-time password: {password}\n")
    return EXIT_OK


def add_commands(commands: Any) -> None:
    serve_cmd = commands.add_parser(
        "serve",
        help="run the web app",
        description="Run the Countersign web app. Data lives in --data-dir (default: the "
        "per-user data directory, e.g. ~/.local/share/countersign) unless COUNTERSIGN_DATABASE_URL "
        "names a database. The chart (areas and plan view) draws a coastline bundled with the "
        "app and requests no map tile unless COUNTERSIGN_MAP_TILES holds a "
        "https://.../{z}/{x}/{y}.png template (COUNTERSIGN_MAP_TILES_ATTRIBUTION: its credit).",
    )
    serve_cmd.add_argument("--host", default="127.0.0.1")
    serve_cmd.add_argument("--port", type=int, default=8000)
    serve_cmd.add_argument("--data-dir", type=Path, default=None)
    serve_cmd.add_argument(
        "--workers", type=int, default=1, metavar="N",
        help="server processes (default 1, more: gunicorn with uvicorn workers), each with its "
        "own listening socket on the port (reuse_port) so that connections spread over them; "
        "more use more cores: on SQLite they share the one writer, on PostgreSQL they scale "
        "reads and validation",
    )
    serve_cmd.add_argument(
        "--validation-processes", type=int, default=None, metavar="N",
        help="processes that validate orders beside the server processes (one pool that all "
        "--workers share), at a lower priority so that reads go first, each user queued fairly "
        "so that one user's heavy validation leaves a process for another's edit (default 2, or "
        "COUNTERSIGN_VALIDATION_PROCESSES; 0: validate in the server's own threads); they "
        "start warm with the server, keep their caches between jobs and are replaced once "
        "one passes 768 MB of resident memory",
    )
    # One listening socket shared by the --workers processes, as gunicorn does without
    # reuse_port: hidden, bench_api's baseline.
    serve_cmd.add_argument("--shared-socket", action="store_true", help=argparse.SUPPRESS)
    # A validation pool in each server process, as before the host's one pool: hidden,
    # bench_fair's baseline.
    serve_cmd.add_argument("--pool-per-process", action="store_true", help=argparse.SUPPRESS)
    serve_cmd.add_argument(
        "--demo", action="store_true",
        help="seed demo users (printing one-time passwords), the built-in examples and their "
             "vehicles in the vehicle registry",
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
