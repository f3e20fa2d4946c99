"""`countersign package` (fetch a version's approved package) and `countersign vehicle verify`
(check one offline, as a vehicle or a launch checklist would). Its own module so the command
line package split can move it whole."""

from __future__ import annotations

import argparse
import json
import os
import sys
from datetime import UTC, datetime, timedelta
from pathlib import Path
from typing import Any

EXIT_OK, EXIT_REFUSED, EXIT_UNREADABLE = 0, 1, 2
MAX_BYTES = 64 * 1024 * 1024


def add_commands(commands: Any) -> None:
    package = commands.add_parser(
        "package", help="download the approved package of a mission version",
        description="Download MISSION version VERSION's approved package from the server: one "
        "deterministic tar with the orders, the IMC and MOOS-IvP files, the approval envelope "
        "(DSSE), its log receipt, an inclusion proof, the signed checkpoint and the log "
        "entries it covers. Token: COUNTERSIGN_TOKEN or --token-file. Exit 1 when the version "
        "has no standing approval.")
    package.add_argument("mission", metavar="MISSION")
    package.add_argument("version", metavar="VERSION", type=int)
    package.add_argument("--server", default=os.environ.get("COUNTERSIGN_SERVER",
                                                            "http://127.0.0.1:8000"))
    package.add_argument("--token-file", type=Path, default=None)
    package.add_argument("--output", "-o", type=Path, default=None, metavar="FILE",
                         help="where to write it (default MISSION-vVERSION.package.tar)")
    package.set_defaults(handler=cmd_package)

    vehicle = commands.add_parser("vehicle", help="vehicle-side checks of approved packages")
    actions = vehicle.add_subparsers(dest="vehicle_command", required=True, metavar="ACTION")
    verify = actions.add_parser(
        "verify", help="check an approved package offline",
        description="Check an approved package with no server and no network: the checkpoint "
        "is signed by the log key, the log entries hash to it, the inclusion proof and the "
        "receipts verify, the checkpoint is fresh (the log's own timestamp on it lies within "
        "--max-age-days of this clock), the envelope is the logged approval of this "
        "version and its signature verifies under the key registered in the log, the orders "
        "are the signed ones, no revocation is logged, and the vehicle files are the exports "
        "of those orders byte for byte and the files whose digests the approval signed. "
        "Exit 0 OK, 1 refused (the reason is named: FORMAT, "
        "LOG-KEY, CHECKPOINT, LOG, PROOF, RECEIPT, EXPIRED, ENVELOPE, SIGNATURE, ORDERS, "
        "REVOKED, EXPORT), 2 unreadable file. tools/verify_package.py does the same with only "
        "the standard library and cryptography.")
    verify.add_argument("package", metavar="PACKAGE", type=Path)
    verify.add_argument("--log-key", required=True, metavar="B64",
                        help="the log's Ed25519 public key (base64, as GET /api/log/checkpoint "
                        "names it): pin it from a source you trust, not from the package")
    verify.add_argument("--max-age-days", type=float, default=7.0,
                        help="refuse a checkpoint the log timestamped longer ago than this "
                        "(default 7; a package made before timestamps: its newest receipt)")
    verify.add_argument("--format", choices=["text", "json"], default="text")
    verify.set_defaults(handler=cmd_vehicle_verify)

    unpack = actions.add_parser(
        "unpack", help="verify an approved package, then write its files into a new directory",
        description="Run every check of `vehicle verify`; only when the package verifies, "
        "write its files (orders.json, the vehicle files, the envelope, the log) into DIR, a "
        "directory that must not exist yet. Only the members of the package's one canonical "
        "layout are written, each below DIR. Unpack packages with this (or "
        "tools/verify_package.py --unpack), never with tar: tar tools differ on what a hostile "
        "archive holds. Exit 0 unpacked, 1 refused (nothing written), 2 unreadable file or "
        "DIR not creatable.")
    unpack.add_argument("package", metavar="PACKAGE", type=Path)
    unpack.add_argument("--into", required=True, type=Path, metavar="DIR",
                        help="the new directory to create and fill")
    unpack.add_argument("--log-key", required=True, metavar="B64",
                        help="the log's Ed25519 public key (base64), pinned from a source "
                        "you trust")
    unpack.add_argument("--max-age-days", type=float, default=7.0,
                        help="as for `vehicle verify` (default 7)")
    unpack.set_defaults(handler=cmd_vehicle_unpack)


def cmd_package(args: argparse.Namespace) -> int:
    # urllib.request brings http.client, email and ssl: a third of `countersign --help`.
    import urllib.error
    import urllib.parse
    import urllib.request

    token = args.token_file.read_text().strip() if args.token_file else \
        os.environ.get("COUNTERSIGN_TOKEN")
    path = (f"/api/missions/{urllib.parse.quote(args.mission, safe='')}/versions/"
            f"{args.version}/package")
    request = urllib.request.Request(args.server.rstrip("/") + path, headers=(
        {"Authorization": f"Bearer {token}"} if token else {}))
    try:
        with urllib.request.urlopen(request, timeout=120) as response:
            data = response.read(MAX_BYTES + 1)
    except urllib.error.HTTPError as exc:
        try:
            detail = json.loads(exc.read()).get("detail", "")
        except ValueError:
            detail = ""
        sys.stderr.write(f"countersign: {path}: {exc.code} {detail}\n")
        return EXIT_REFUSED if exc.code in (409, 422) else EXIT_UNREADABLE
    except urllib.error.URLError as exc:
        sys.stderr.write(f"countersign: cannot reach {args.server}: {exc.reason}\n")
        return EXIT_UNREADABLE
    target = args.output or Path(f"{args.mission}-v{args.version}.package.tar")
    target.write_bytes(data)
    sys.stdout.write(f"{target}\n")
    return EXIT_OK


def _read_package(path: Path) -> bytes | None:
    try:
        with path.open("rb") as handle:
            return handle.read(MAX_BYTES + 1)
    except OSError as exc:
        sys.stderr.write(f"countersign: cannot read {path}: {exc.strerror}\n")
        return None


def cmd_vehicle_verify(args: argparse.Namespace) -> int:
    from ..approved_package.verify import verify_package

    data = _read_package(args.package)
    if data is None:
        return EXIT_UNREADABLE
    verdict = verify_package(data, log_key=args.log_key, now=datetime.now(UTC),
                             max_age=timedelta(days=args.max_age_days))
    if args.format == "json":
        sys.stdout.write(json.dumps(verdict.to_json()) + "\n")
    else:
        sys.stdout.write(f"OK {verdict.message}\n" if verdict.ok
                         else f"REFUSED {verdict.code}: {verdict.message}\n")
    return EXIT_OK if verdict.ok else EXIT_REFUSED


def cmd_vehicle_unpack(args: argparse.Namespace) -> int:
    from ..approved_package.unpack import unpack_package

    data = _read_package(args.package)
    if data is None:
        return EXIT_UNREADABLE
    if args.into.exists() or args.into.is_symlink():
        sys.stderr.write(f"countersign: {args.into} exists: unpack into a new directory\n")
        return EXIT_UNREADABLE
    try:
        verdict = unpack_package(data, args.into, log_key=args.log_key, now=datetime.now(UTC),
                                 max_age=timedelta(days=args.max_age_days))
    except OSError as exc:
        sys.stderr.write(f"countersign: cannot unpack into {args.into}: {exc.strerror}\n")
        return EXIT_UNREADABLE
    if not verdict.ok:
        sys.stdout.write(f"REFUSED {verdict.code}: {verdict.message} (nothing written)\n")
        return EXIT_REFUSED
    sys.stdout.write(f"OK {verdict.message}\nunpacked into {args.into}\n")
    return EXIT_OK
