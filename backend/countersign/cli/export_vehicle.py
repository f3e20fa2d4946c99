"""`countersign export --format imc|moos`: vehicle formats, with what they cannot carry on stderr.

The export package (and imcpy) is imported only when such an export runs, so `--help` stays
light."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path
from typing import TYPE_CHECKING

from .common import EXIT_FINDINGS, EXIT_OK, EXIT_UNREADABLE

if TYPE_CHECKING:
    from ..export.notes import VehicleExport
    from ..orders.model import Orders


def add_export_arguments(parser: argparse.ArgumentParser) -> None:
    parser.add_argument(
        "--output", type=Path, default=None, metavar="DIR",
        help="imc/moos: write every file of the export into DIR (moos: NAME.bhv and "
        "NAME.moos); without it the main file goes to standard output")
    parser.add_argument(
        "--plan-version", type=int, default=None, metavar="N",
        help="imc/moos: the version number to name in the plan id (default: a short digest)")
    parser.add_argument(
        "--member", default=None, metavar="VEHICLE",
        help="team orders: write this member vehicle's files (its own orders and meetings); "
        "imc, moos and avcl of a team need it")


def print_notes(export: VehicleExport) -> None:
    for note in export.notes:
        sys.stderr.write(f"countersign: {note.line()}\n")


def write_vehicle_export(orders: Orders, args: argparse.Namespace) -> int:
    from ..export.notes import ExportError
    from ..export.vehicle import export_vehicle

    try:
        export = export_vehicle(orders, args.format, version=args.plan_version,
                                member=args.member)
    except ExportError as exc:
        sys.stderr.write(f"countersign: cannot export: {exc}\n")
        return EXIT_FINDINGS
    if args.output is not None:
        try:
            args.output.mkdir(parents=True, exist_ok=True)
            for item in export.files:
                (args.output / item.name).write_bytes(item.content)
        except OSError as exc:
            sys.stderr.write(f"countersign: cannot write {args.output}: {exc.strerror}\n")
            return EXIT_UNREADABLE
    else:
        if export.format == "imc" and sys.stdout.isatty():
            sys.stderr.write("countersign: IMC is binary: give --output DIR or redirect "
                             "standard output\n")
            return EXIT_UNREADABLE
        sys.stdout.flush()
        sys.stdout.buffer.write(export.primary.content)
        sys.stdout.buffer.flush()
    print_notes(export)
    return EXIT_OK
