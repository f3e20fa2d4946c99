"""What every command shares: exit codes, usage errors and reading orders.

Imports nothing heavy at module level: `countersign --help` loads every command module.
"""

from __future__ import annotations

import argparse
import gc
import math
import os
import sys
from collections.abc import Iterator
from contextlib import contextmanager
from pathlib import Path
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from ..orders.model import Orders
    from ..orders.reader import ReadResult

EXIT_OK, EXIT_FINDINGS, EXIT_UNREADABLE, EXIT_INTERNAL = 0, 1, 2, 3

# The solver budget the server allows (verify.report.SOLVER_BUDGET_S; the help text shows it
# without importing the verifier; tests/cli/test_cli_startup.py holds the two equal).
SOLVER_BUDGET_S = 8.0

FILE_HELP = (
    "orders JSON (countersign.orders/1) or AVCL XML; '-' reads standard input, "
    "'example:NAME' a built-in example"
)


class UsageError(Exception):
    """Bad input the user can fix; printed without a trace, exit code 2."""


@contextmanager
def loading(args: argparse.Namespace) -> Iterator[None]:
    """A command's imports. Run by the program itself (`args.program`, cli.main), they load
    without the collector, each of whose full collections would walk every object loaded so
    far (modules, classes, pydantic's schemas: garbage-free and kept to the end, about 0.04 s
    of `countersign validate`), and are then frozen out of the later ones. Called in-process
    (tests), nothing changes.

    The program also keeps numpy's OpenBLAS to the calling thread and pydantic from looking for
    plugins, each unless its variable says otherwise. As numpy loads, OpenBLAS starts a thread
    per core that spins waiting for work no check gives it (Countersign multiplies no matrices):
    more CPU than a validation's wall time (tests/bench/bench_startup.py). Pydantic's search
    reads the metadata of every installed distribution, for observers of validation that
    Countersign neither ships nor needs to print its report."""
    if not getattr(args, "program", False) or not gc.isenabled():
        yield
        return
    os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
    os.environ.setdefault("PYDANTIC_DISABLE_PLUGINS", "__all__")
    gc.disable()
    try:
        yield
    finally:
        gc.freeze()
        gc.enable()


def server_url(given: str | None) -> str:
    """--server, else COUNTERSIGN_SERVER, else this machine's default server."""
    if given is not None:
        return given
    from ..settings import ClientEnvironment, read  # pydantic: not for `--help`

    return read(ClientEnvironment).server


def api_token(token_file: Path | None) -> str | None:
    """The API token of a client command: --token-file's content, else COUNTERSIGN_TOKEN."""
    if token_file is not None:
        return token_file.read_text().strip()
    from ..settings import ClientEnvironment, read

    token = read(ClientEnvironment).token
    return None if token is None else token.get_secret_value()


def load_orders(source: str, *, teams: bool = False) -> ReadResult:
    """Orders from a path, `-` for standard input, or `example:NAME` for a built-in. Orders
    with a team are refused (exit 2) unless `teams`: most commands read one vehicle's MEA."""
    loaded = _read_orders(source)
    if loaded.orders.team is not None and not teams:
        raise UsageError(
            f"{source} holds a team's orders (one MEA per vehicle) and this command reads one "
            "vehicle's orders: 'countersign validate' checks the team, 'countersign export "
            "--format plain' (or json) writes it, 'export --member VEHICLE' writes one "
            "member's vehicle files; a member's own orders are its team[i].orders")
    return loaded


def member_orders(orders: Orders, member: str | None, *, what: str) -> Orders:
    """The orders of team member `member` (--member), or `orders` themselves when they are one
    vehicle's and no member is named; a team without --member, an unknown member, or a member
    of one vehicle's orders is exit 2 naming --member. `what`: the command, for the message."""
    from ..export.team import MemberNeeded, UnknownMember, select_member

    try:
        chosen = select_member(orders, member)
    except MemberNeeded as exc:
        raise UsageError(f"{what} of a team's orders needs --member VEHICLE, one of "
                         f"{', '.join(exc.vehicles)}") from None
    except UnknownMember as exc:
        raise UsageError(f"--member {exc.member}: {exc}") from None
    return orders if chosen is None else chosen.orders


def _read_orders(source: str) -> ReadResult:
    from ..limits import MAX_INPUT_BYTES
    from ..orders.examples import example_bytes
    from ..orders.reader import read_bytes, read_file

    if source.startswith("example:"):
        try:
            return read_bytes(example_bytes(source.removeprefix("example:")), source)
        except KeyError as exc:
            raise UsageError(str(exc.args[0])) from None
    if source == "-":
        return read_bytes(sys.stdin.buffer.read(MAX_INPUT_BYTES + 1), "standard input")
    return read_file(source)


def budget_seconds(text: str) -> float:
    try:
        value = float(text)
    except ValueError:
        value = math.nan
    if not 0 <= value <= 3600:  # also refuses nan and inf
        raise argparse.ArgumentTypeError(f"give seconds from 0 to 3600, not {text!r}")
    return value


def non_negative(text: str) -> int:
    try:
        value = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r} is not a whole number") from None
    if value < 0:
        raise argparse.ArgumentTypeError("must be 0 or more")
    return value
