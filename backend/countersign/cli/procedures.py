"""`countersign procedures check|reference FILE` and the `--procedures` library option.

A procedure library on the command line is a procedure file (`countersign.procedure/1`) or a
directory of them (`*.json`, not recursive). `validate`, `paths` and `run` copy the body of
each reference the orders make from it (verify/procedures.py) before checking, exactly as the
server copies them from its library.
"""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path
from typing import TYPE_CHECKING, Any

from .common import EXIT_FINDINGS, EXIT_OK, UsageError

if TYPE_CHECKING:
    from ..orders.procedure import Procedure
    from ..orders.reader import ReadResult

MAX_LIBRARY_FILES = 1000
LIBRARY_HELP = ("a procedure file (countersign.procedure/1) or a directory of them (*.json): "
                "references to procedures in the orders are filled in from it")


def add_library_argument(parser: argparse.ArgumentParser) -> None:
    parser.add_argument("--procedures", type=Path, action="append", default=[],
                        metavar="PATH", help=LIBRARY_HELP + " (may be repeated)")


def _files(path: Path) -> list[Path]:
    if path.is_dir():
        files = sorted(p for p in path.glob("*.json") if p.is_file())
        if len(files) > MAX_LIBRARY_FILES:
            raise UsageError(f"{path} holds {len(files)} procedure files; a library on the "
                             f"command line has at most {MAX_LIBRARY_FILES}")
        return files
    return [path]


def _read(path: Path) -> Procedure:
    from ..orders.procedure import MAX_PROCEDURE_BYTES, read_procedure
    from ..orders.reader import OrdersReadError

    try:
        with path.open("rb") as handle:
            data = handle.read(MAX_PROCEDURE_BYTES + 1)
    except OSError as exc:
        raise UsageError(f"cannot read procedure file {path}: {exc.strerror}") from None
    try:
        return read_procedure(data)
    except OrdersReadError as exc:
        raise UsageError(f"{path} is not a procedure:\n  "
                         + exc.summary().replace("\n", "\n  ")) from None


def load_library(paths: list[Path]) -> dict[tuple[str, int], Procedure]:
    library: dict[tuple[str, int], Procedure] = {}
    origin: dict[tuple[str, int], Path] = {}
    for root in paths:
        for file in _files(root):
            if len(origin) >= MAX_LIBRARY_FILES:
                raise UsageError(f"a library on the command line has at most "
                                 f"{MAX_LIBRARY_FILES} procedure files")
            procedure = _read(file)
            key = (procedure.name, procedure.version)
            if key in library and library[key].digest != procedure.digest:
                raise UsageError(f"{origin[key]} and {file} both hold procedure {key[0]} "
                                 f"version {key[1]}, with different goals; a version never "
                                 "changes: give one of them a new version")
            library[key] = procedure
            origin[key] = file
    return library


def with_library(loaded: ReadResult, paths: list[Path]) -> ReadResult:
    """The orders with the library's procedures copied in (unchanged without --procedures)."""
    if not paths:
        return loaded
    from dataclasses import replace

    from ..verify.procedures import expand

    library = load_library(paths)
    return replace(loaded, orders=expand(loaded.orders,
                                         lambda name, version: library.get((name, version))))


def cmd_check(args: argparse.Namespace) -> int:
    from ..verify.procedures import check_procedure, expand_procedure

    procedure = _read(args.file)
    if args.procedures:
        library = load_library(args.procedures)
        procedure = expand_procedure(
            procedure, lambda name, version: library.get((name, version)))
    findings, paths = check_procedure(procedure)
    ok = not any(f.severity == "error" for f in findings)
    if args.format == "json":
        json.dump({"procedure": procedure.name, "version": procedure.version,
                   "digest": procedure.digest, "reference": procedure.reference(), "ok": ok,
                   "findings": [f.to_json() for f in findings],
                   "paths": paths.to_json() if paths is not None else None},
                  sys.stdout, indent=2)
        sys.stdout.write("\n")
    else:
        out = sys.stdout
        out.write(f"Procedure {procedure.name} version {procedure.version}  "
                  f"{procedure.digest}\n")
        for finding in findings:
            out.write(f"  {finding.severity:<7} {finding.code:<13} "
                      f"[{', '.join(finding.subjects)}]\n          {finding.message}\n")
        if paths is not None:
            returns = {"COMPLETE": "succeed", "ABORT": "fail or violate"}
            parts = ", ".join(f"{n} returning {returns.get(t, t)}"
                              for t, n in paths.by_terminal.items())
            out.write(f"Paths: {paths.total} ({parts})\n")
        out.write(f"Use it as: \"refines\": {json.dumps(procedure.reference())}\n")
        out.write(f"{'OK' if ok else 'NOT OK'}\n")
    return EXIT_OK if ok else EXIT_FINDINGS


def cmd_reference(args: argparse.Namespace) -> int:
    procedure = _read(args.file)
    sys.stdout.write(json.dumps(procedure.reference()) + "\n")
    return EXIT_OK


def cmd_sign(args: argparse.Namespace) -> int:
    """Ask the server for the statement about a procedure version, sign its DSSE PAE with the
    key file here and send the envelope with the password (as `countersign sign` does)."""
    import getpass

    from ..approvals import dsse
    from .approvals import ApiError, api_request
    from .common import api_token, server_url

    token = api_token(args.token_file)
    if not token:
        raise UsageError("set COUNTERSIGN_TOKEN or pass --token-file with an API token")
    try:
        key = dsse.load_private_pem(args.key.read_bytes())
        password = (args.password_file.read_text().splitlines() or [""])[0] \
            if args.password_file is not None else getpass.getpass("countersign password: ")
    except OSError as exc:
        raise UsageError(f"cannot read {exc.filename}: {exc.strerror}") from None
    except dsse.SignatureError as exc:
        raise UsageError(f"{args.key}: {exc}") from None
    except EOFError:
        password = ""
    if not password:
        raise UsageError("a decision needs your password (--password-file or typed when asked)")
    base = f"/api/procedures/{args.name}/versions/{args.version}"
    try:
        prepared = api_request(server_url(args.server), token, f"{base}/statement", {
            "decision": args.decision, "reason": args.reason,
            "key_id": dsse.key_id(key.public_key())})
        payload = dsse.unb64(prepared["payload"], "the payload")
        envelope = dsse.sign_envelope(payload, key, prepared["payloadType"])
        stored = api_request(server_url(args.server), token, f"{base}/decision",
                             {"envelope": json.dumps(envelope), "password": password})
    except (ApiError, dsse.SignatureError, KeyError) as exc:
        sys.stderr.write(f"countersign: refused: {exc}\n")
        return EXIT_FINDINGS
    sys.stdout.write(f"{stored['decision']}: procedure {args.name} version {args.version} "
                     f"({stored['procedure_digest']}), log entry {stored['log_index']}\n")
    return EXIT_OK


def add_commands(commands: Any) -> None:
    group = commands.add_parser(
        "procedures", help="check a procedure, print its reference, sign a decision on it",
        description="A procedure (countersign.procedure/1: name, integer version, refines) is a "
        "refinement saved once and used by reference: a goal's \"refines\": {\"procedure\": "
        "NAME, \"version\": N, \"digest\": \"sha256:...\"}. validate, paths and run take "
        "--procedures PATH to fill references in offline. Exit codes: 0 ok, 1 error "
        "findings, 2 unreadable input.")
    sub = group.add_subparsers(dest="procedures_command", required=True, metavar="SUBCOMMAND")
    check = sub.add_parser("check", help="check a procedure like a refinement; print its "
                           "digest and the reference to use")
    check.add_argument("file", metavar="FILE", type=Path, help="a procedure JSON file")
    check.add_argument("--format", choices=["text", "json"], default="text")
    add_library_argument(check)
    check.set_defaults(handler=cmd_check)
    reference = sub.add_parser("reference", help="print the reference JSON that uses a "
                               "procedure file (name, version, digest)")
    reference.add_argument("file", metavar="FILE", type=Path, help="a procedure JSON file")
    reference.set_defaults(handler=cmd_reference)
    sign = sub.add_parser(
        "sign", help="sign a decision on a library procedure version with a key file",
        description="The server builds the statement (subject: the procedure's digest); this "
        "command signs its DSSE PAE with the key file and sends the envelope with your "
        "password. Token: COUNTERSIGN_TOKEN or --token-file. Exit 0 stored, 1 refused, 2 "
        "bad usage.")
    sign.add_argument("--server", default=None)  # None: COUNTERSIGN_SERVER (server_url)
    sign.add_argument("--token-file", type=Path, default=None)
    sign.add_argument("--key", type=Path, required=True, help="private key file from keygen")
    sign.add_argument("--name", required=True, help="the procedure's name")
    sign.add_argument("--version", type=int, required=True, help="its version number")
    sign.add_argument("--decision", choices=["approved", "rejected"], required=True)
    sign.add_argument("--reason", default="")
    sign.add_argument("--password-file", type=Path, default=None,
                      help="file holding your account password (first line); without it the "
                      "password is asked for")
    sign.set_defaults(handler=cmd_sign)
