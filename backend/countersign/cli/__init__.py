"""The `countersign` command line (DESIGN.md, Command line): one module per command group.

Exit codes: 0 no errors, 1 error findings (or a mission that cannot run), 2 unreadable input
or bad usage (a bad COUNTERSIGN_* variable too), 3 an internal error (reported in one line;
COUNTERSIGN_DEBUG=1 shows the trace).
"""

from __future__ import annotations

import argparse
import os
import sys
from collections.abc import Sequence

from .. import __version__
from . import (
    approvals,
    campaign,
    charts,
    execution,
    orders,
    package,
    plan,
    procedures,
    rehearse,
    rules,
    server,
    witness,
)
from .common import EXIT_INTERNAL, EXIT_OK, EXIT_UNREADABLE, UsageError

__all__ = ["UsageError", "build_parser", "main"]


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

    # The order of the groups is the order of `countersign --help`.
    for group in (orders, procedures, server, plan, rules, rehearse, campaign, approvals,
                  witness, package, execution, charts):
        group.add_commands(commands)
    return parser


def main(argv: Sequence[str] | None = None) -> int:
    parser = build_parser()
    args = parser.parse_args(argv)
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
