"""`countersign charts`: the chart registry (import GeoJSON/KML, list, export, delete) and an
offline check of a chart file."""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:  # the readers (pydantic, fastkml) load with the commands that read charts
    from ..orders.model import Chart

EXIT_OK, EXIT_UNREADABLE = 0, 2

DESCRIPTION = """\
Shared charts (protected areas, shipping lanes and traffic separation schemes, keep-out
zones, anchorages) that every mission is checked against: each outcome edge's leg, each
sweep and loiter is tested for crossing them (finding GEO). Charts are Polygon features of
GeoJSON (properties: title, kind, contexts, norms, forbids) or Polygon placemarks of KML
(ExtendedData kind, contexts, forbids). `forbids` lists behaviours forbidden inside, where
`transit` is the leg between goals; the tags keep_out and land forbid everything.
The charts in use are copied into each mission version, so an approval covers them."""


def _read(path: Path) -> list[Chart]:
    from ..orders.geo_formats import GeoFormatError, read_charts

    try:
        content = path.read_bytes()
    except OSError as exc:
        raise GeoFormatError(f"{path}: {exc.strerror}") from None
    try:
        return read_charts(path.name, content)
    except GeoFormatError as exc:
        raise GeoFormatError(f"{path}: {exc}") from None


def _fail(exc: Exception) -> int:
    sys.stderr.write(f"countersign: {exc}\n")
    return EXIT_UNREADABLE


def _summary(charts: list[Chart]) -> None:
    for chart in charts:
        norms = ", ".join(n.text or n.forbidden for n in chart.norms)
        sys.stdout.write(f"{chart.id}\t{chart.kind}\t{','.join(chart.contexts)}\t"
                         f"{len(chart.polygon)} points\t{chart.title}"
                         f"{f'  [{norms}]' if norms else ''}\n")


def cmd_check(args: argparse.Namespace) -> int:
    from ..orders.geo_formats import GeoFormatError

    try:
        charts = _read(args.file)
    except GeoFormatError as exc:
        return _fail(exc)
    _summary(charts)
    return EXIT_OK


def _with_db(args: argparse.Namespace, work: Any) -> int:
    from .server import open_database

    _, database = open_database(args)
    with database.session() as db:
        # The log signer the command opened receipts what `work` appends.
        result: int = work(db, database.log_signer)
    return result


def cmd_import(args: argparse.Namespace) -> int:
    from ..orders.geo_formats import GeoFormatError
    from ..store.charts import save_charts
    from ..store.events import record

    try:
        charts = _read(args.file)
    except GeoFormatError as exc:
        return _fail(exc)

    def work(db: Any, signer: Any) -> int:
        saved = save_charts(db, charts)
        record(db, signer=signer, kind="chart.saved", actor=None, detail={"charts": saved[:1000],
                                                           "source": "cli"})
        sys.stdout.write(f"imported {len(saved)} chart(s): {', '.join(saved[:20])}"
                         f"{' ...' if len(saved) > 20 else ''}\n")
        return EXIT_OK

    return _with_db(args, work)


def cmd_list(args: argparse.Namespace) -> int:
    from ..orders.geo_formats import areas_to_geojson, charts_to_kml
    from ..store.charts import all_charts

    def work(db: Any, _signer: Any) -> int:
        charts = all_charts(db)
        if args.format == "geojson":
            sys.stdout.write(json.dumps(areas_to_geojson(charts), indent=2) + "\n")
        elif args.format == "kml":
            sys.stdout.write(charts_to_kml(charts))
        else:
            _summary(charts)
        return EXIT_OK

    return _with_db(args, work)


def cmd_delete(args: argparse.Namespace) -> int:
    from ..store.charts import delete_chart
    from ..store.events import record

    def work(db: Any, signer: Any) -> int:
        if not delete_chart(db, args.chart_id):
            sys.stderr.write(f"countersign: there is no chart {args.chart_id!r}\n")
            return EXIT_UNREADABLE
        record(db, kind="chart.deleted", actor=None, detail={"charts": [args.chart_id],
                                                             "source": "cli"}, signer=signer)
        return EXIT_OK

    return _with_db(args, work)


def add_commands(commands: Any) -> None:
    charts_cmd = commands.add_parser(
        "charts", help="the shared chart registry (GeoJSON/KML areas checked by GEO)",
        description=DESCRIPTION, formatter_class=argparse.RawDescriptionHelpFormatter)
    sub = charts_cmd.add_subparsers(dest="charts_command", required=True, metavar="ACTION")
    check = sub.add_parser("check", help="read a chart file and list its charts (offline)")
    check.add_argument("file", type=Path, metavar="FILE.geojson|kml")
    check.set_defaults(handler=cmd_check)
    imp = sub.add_parser("import", help="add or replace charts from a GeoJSON or KML file",
                         description="Add or replace (by id) the charts of FILE in the "
                         "registry of --data-dir (or COUNTERSIGN_DATABASE_URL).")
    imp.add_argument("file", type=Path, metavar="FILE.geojson|kml")
    imp.add_argument("--data-dir", type=Path, default=None)
    imp.set_defaults(handler=cmd_import)
    listing = sub.add_parser("list", help="list the registry's charts, or export them")
    listing.add_argument("--format", choices=["text", "geojson", "kml"], default="text",
                         help="text: one line per chart; geojson (RFC 7946) or kml: the "
                         "charts as polygons, exterior rings counterclockwise")
    listing.add_argument("--data-dir", type=Path, default=None)
    listing.set_defaults(handler=cmd_list)
    remove = sub.add_parser("delete", help="remove a chart from the registry")
    remove.add_argument("chart_id")
    remove.add_argument("--data-dir", type=Path, default=None)
    remove.set_defaults(handler=cmd_delete)
