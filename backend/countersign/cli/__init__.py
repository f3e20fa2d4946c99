"""The `countersign` command line (DESIGN.md, Command line): one module per command group.

Exit codes: 0 no errors, 1 error findings (or a mission that cannot run), 2 unreadable input
or bad usage (a bad COUNTERSIGN_* variable too), 3 an internal error (reported in one line;
COUNTERSIGN_DEBUG=1 shows the trace).
"""

from __future__ import annotations

import argparse
import gc
import os
import sys
from collections.abc import Sequence
from importlib import import_module

from .. import __version__
from .common import EXIT_INTERNAL, EXIT_OK, EXIT_UNREADABLE, UsageError

__all__ = ["UsageError", "build_parser", "main"]

# The command groups, each a module of this package, in the order of `countersign --help`, with
# the commands each adds. A command's own run imports and builds only its group's parser (the
# dozen modules and 80-odd parsers of all are about 0.02 s of CPU of every command);
# tests/cli/test_cli_startup.py holds this table to what the groups add.
GROUPS: dict[str, tuple[str, ...]] = {
    "orders": ("validate", "paths", "run", "export", "explain", "examples"),
    "procedures": ("procedures",),
    "server": ("serve", "users"),
    "plan": ("plan",),
    "rules": ("rules",),
    "rehearse": ("rehearse",),
    "campaign": ("campaign",),
    "approvals": ("keygen", "sign", "audit"),
    "witness": ("witness",),
    "package": ("package", "vehicle"),
    "execution": ("execution",),
    "charts": ("charts",),
}
GROUP_OF = {command: group for group, commands in GROUPS.items() for command in commands}


def build_parser(group: str | None = None) -> argparse.ArgumentParser:
    """The parser of every command, or (`group`) of that group's commands alone."""
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

    # The order of the groups is the order of `countersign --help`.
    for name in GROUPS if group is None else (group,):
        import_module(f"{__name__}.{name}").add_commands(commands)
    return parser


def main(argv: Sequence[str] | None = None) -> int:
    """Run the command `argv`, or (None) the program's own (`sys.argv`), which then ends with
    the garbage collector's objects frozen."""
    code = _run(argv)
    if argv is None:
        # The process ends next, and Python's collections at its exit would walk every object
        # the command loaded (modules, classes, pydantic's schemas, numpy's and z3's): about a
        # quarter of the CPU of `countersign validate` (tests/bench/bench_startup.py). Frozen,
        # they are not walked; the exit still frees them by their counts and runs atexit.
        # In-process callers (tests) pass `argv` and keep their collector as it was.
        gc.freeze()
    return code


def _run(argv: Sequence[str] | None) -> int:
    given = list(sys.argv[1:] if argv is None else argv)
    # A command named first is parsed by its group's parser, which parses it as the whole
    # parser does; anything else (an option, a misspelt command) by the whole parser.
    parser = build_parser(GROUP_OF.get(given[0]) if given else None)
    args = parser.parse_args(given)
    args.program = argv is None  # cli.common.loading
    try:
        code: int = args.handler(args)
        return code
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
        # The reader and the settings are imported by the commands that use them, not before.
        from ..orders.reader import OrdersReadError
        from ..settings import ClientEnvironment, SettingsError, read

        if isinstance(exc, SettingsError):  # a variable's value, named with what is wrong
            sys.stderr.write(f"countersign: {exc}\n")
            return EXIT_UNREADABLE
        if isinstance(exc, OrdersReadError):
            sys.stderr.write(f"countersign: cannot read {getattr(args, 'file', 'input')}:\n")
            for line in exc.summary().splitlines():
                sys.stderr.write(f"  {line}\n")
            return EXIT_UNREADABLE
        if read(ClientEnvironment).debug:
            raise
        sys.stderr.write(
            f"countersign: internal error ({type(exc).__name__}: {exc}); "
            "set COUNTERSIGN_DEBUG=1 for details\n"
        )
        return EXIT_INTERNAL
