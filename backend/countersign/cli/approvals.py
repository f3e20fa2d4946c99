"""Command line for approvals: `countersign keygen | sign | audit verify` (DESIGN.md).

- `keygen [--out FILE]` writes an Ed25519 private key (PEM, mode 0600; never overwrites) and
  prints the public key (base64 of the raw 32 bytes, what the server registers) and its key id.
- `sign --server URL --submission ID --decision approved|rejected [--reason TEXT] --key FILE`
  asks the server for the exact statement, signs its DSSE PAE locally and sends the envelope;
  `sign --revoke APPROVAL_ID --reason TEXT` signs a revocation. The API token comes from
  COUNTERSIGN_TOKEN or --token-file; the private key never leaves this machine. The signer's
  password is asked for (or read from --password-file) and sent with the envelope: the server
  refuses a decision without it (a key alone is not the supervisor).
- `audit verify BUNDLE [--log-key B64] [--checkpoint FILE]... [--state FILE]` checks an
  exported bundle offline: exit 0 when everything verifies, 1 with a report of what failed, 2
  when unreadable. Every log entry must carry the log signer's receipt; with --state the log
  must extend the head verified last time; with --receipt FILE it must hold the entry of each
  receipt given; a bundle saying that the server's log signer refuses the log fails.
"""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path
from typing import Any

from .. import strict_json
from .common import api_token, server_url

EXIT_OK, EXIT_FAILED, EXIT_UNREADABLE = 0, 1, 2


def add_commands(commands: argparse._SubParsersAction) -> None:  # type: ignore[type-arg]
    keygen = commands.add_parser(
        "keygen", help="create an Ed25519 signing key file (0600) and print its public key")
    keygen.add_argument("--out", "-o", type=Path, default=Path("countersign-signing-key.pem"),
                        help="where to write the private key (refuses to overwrite)")
    keygen.set_defaults(handler=cmd_keygen)

    sign = commands.add_parser(
        "sign", help="sign a decision on a submission (or revoke an approval) with a key file",
        description="The server builds the statement; this command signs its DSSE PAE with "
        "the key file and sends the envelope. Token: COUNTERSIGN_TOKEN or --token-file.")
    sign.add_argument("--server", default=None)  # None: COUNTERSIGN_SERVER (server_url)
    sign.add_argument("--token-file", type=Path, default=None)
    sign.add_argument("--key", type=Path, required=True, help="private key file from keygen")
    target = sign.add_mutually_exclusive_group(required=True)
    target.add_argument("--submission", type=int, help="the submission to decide on")
    target.add_argument("--revoke", type=int, metavar="APPROVAL_ID",
                        help="revoke this approval")
    sign.add_argument("--decision", choices=["approved", "rejected"], default=None)
    sign.add_argument("--reason", default="")
    sign.add_argument("--password-file", type=Path, default=None,
                      help="file holding your account password (first line); without it the "
                      "password is asked for. The server checks it with every decision")
    sign.set_defaults(handler=cmd_sign)

    audit = commands.add_parser("audit", help="verify an exported audit bundle offline")
    audit_sub = audit.add_subparsers(dest="audit_command", required=True, metavar="ACTION")
    verify = audit_sub.add_parser(
        "verify", help="check signatures, keys, orders digests, the log chain, Merkle proofs "
        "and checkpoints of a bundle, with no server and no network")
    verify.add_argument("bundle", type=Path, help="the exported bundle (or the server's 409 "
                        "problem for a log with deleted entries, which holds one)")
    verify.add_argument("--log-key", default=None,
                        help="the server's published log public key (base64) to pin")
    verify.add_argument("--checkpoint", type=Path, action="append", default=[],
                        help="a checkpoint published earlier (JSON); the log must extend it")
    verify.add_argument("--state", type=Path, default=None, metavar="FILE",
                        help="keep the last verified tree head of each log in FILE (created on "
                        "first use): the bundle's log must extend it, else the rollback or "
                        "fork is reported naming both heads; updated when the bundle verifies")
    verify.add_argument("--receipt", type=Path, action="append", default=[], metavar="FILE",
                        help="a log receipt you hold (e.g. the one returned with your "
                        "decision, as JSON text): the log must still hold its entry")
    verify.add_argument("--format", choices=["text", "json"], default="text")
    verify.set_defaults(handler=cmd_audit_verify)


def _err(message: str) -> None:
    sys.stderr.write(f"countersign: {message}\n")


def cmd_keygen(args: argparse.Namespace) -> int:
    from ..approvals import dsse

    key = dsse.generate_key()
    try:
        dsse.write_private_key(args.out, key)
    except FileExistsError:
        _err(f"{args.out} exists; choose another --out (keys are never overwritten)")
        return EXIT_UNREADABLE
    except OSError as exc:
        _err(f"cannot write {args.out}: {exc.strerror}")
        return EXIT_UNREADABLE
    public = dsse.public_text(key)
    sys.stdout.write(f"private key: {args.out} (mode 0600; keep it secret)\n"
                     f"public key:  {public}\nkey id:      {dsse.key_id(public)}\n")
    return EXIT_OK


class ApiError(Exception):
    pass


def api_request(server: str, token: str | None, path: str,
                body: dict[str, Any] | None) -> dict[str, Any]:
    """GET (no body) or POST JSON to the server's API; an error answer raises ApiError with
    the problem's detail."""
    import urllib.error
    import urllib.request

    headers = {"Content-Type": "application/json"}
    if token:
        headers["Authorization"] = f"Bearer {token}"
    request = urllib.request.Request(
        server.rstrip("/") + path, method="GET" if body is None else "POST", headers=headers,
        data=None if body is None else json.dumps(body).encode())
    try:
        with urllib.request.urlopen(request, timeout=60) as response:
            data: dict[str, Any] = json.loads(response.read())
            return data
    except urllib.error.HTTPError as exc:
        try:
            detail = json.loads(exc.read()).get("detail", "")
        except ValueError:
            detail = ""
        raise ApiError(f"{path}: {exc.code} {detail}".strip()) from None
    except urllib.error.URLError as exc:
        raise ApiError(f"cannot reach {server}: {exc.reason}") from None


def cmd_sign(args: argparse.Namespace) -> int:
    import getpass

    from ..approvals import dsse

    token = api_token(args.token_file)
    if not token:
        _err("set COUNTERSIGN_TOKEN or pass --token-file with an API token")
        return EXIT_UNREADABLE
    try:
        key = dsse.load_private_pem(args.key.read_bytes())
    except OSError as exc:
        _err(f"cannot read {args.key}: {exc.strerror}")
        return EXIT_UNREADABLE
    except dsse.SignatureError as exc:
        _err(f"{args.key}: {exc}")
        return EXIT_UNREADABLE
    kid = dsse.key_id(key.public_key())
    try:
        password = (args.password_file.read_text().splitlines() or [""])[0] \
            if args.password_file is not None else getpass.getpass("countersign password: ")
    except OSError as exc:
        _err(f"cannot read {args.password_file}: {exc.strerror}")
        return EXIT_UNREADABLE
    except EOFError:
        password = ""
    if not password:
        _err("a decision needs your password (--password-file or typed when asked)")
        return EXIT_UNREADABLE
    if args.submission is not None:
        if args.decision is None:
            _err("--decision approved or rejected is needed with --submission")
            return EXIT_UNREADABLE
        base = f"/api/submissions/{args.submission}"
        prepare = {"decision": args.decision, "reason": args.reason, "key_id": kid}
        finish = f"{base}/decision"
    else:
        base = f"/api/approvals/{args.revoke}"
        prepare = {"reason": args.reason, "key_id": kid}
        finish = f"{base}/revoke"
    try:
        prepared = api_request(server_url(args.server), token, f"{base}/statement", prepare)
        payload = dsse.unb64(prepared["payload"], "the payload")
        envelope = dsse.sign_envelope(payload, key, prepared["payloadType"])
        stored = api_request(server_url(args.server), token, finish,
                             {"envelope": json.dumps(envelope), "password": password})
    except (ApiError, dsse.SignatureError, KeyError) as exc:
        _err(f"refused: {exc}")
        return EXIT_FAILED
    sys.stdout.write(f"{stored['decision']}: {stored['mission']} version {stored['version']} "
                     f"({stored['digest']}), approval {stored['id']}, log entry "
                     f"{stored['log_index']}\n")
    return EXIT_OK


def cmd_audit_verify(args: argparse.Namespace) -> int:
    from ..approvals import dsse
    from ..approvals.auditor_state import load_state, save_state
    from ..approvals.bundle import from_problem, verify_bundle

    try:
        # JsonPolicyError is a ValueError: nesting too deep is "not JSON" too, not a crash.
        bundle = strict_json.loads(args.bundle.read_bytes())
        published = [strict_json.loads(p.read_bytes()) for p in args.checkpoint]
    except OSError as exc:
        _err(f"cannot read {exc.filename}: {exc.strerror}")
        return EXIT_UNREADABLE
    except ValueError as exc:
        _err(f"not JSON: {exc}")
        return EXIT_UNREADABLE
    try:
        seen = load_state(args.state) if args.state is not None else {}
        held = [p.read_text() for p in args.receipt]
    except dsse.SignatureError as exc:
        _err(str(exc))
        return EXIT_UNREADABLE
    bundle, server_said = from_problem(bundle)
    report = verify_bundle(bundle, trusted_log_key=args.log_key, published=published, seen=seen,
                           held_receipts=held)
    if server_said:
        report.problems.insert(0, f"the server refused the bundle: {server_said}")
    if args.state is not None and report.ok and report.head is not None:
        seen[report.head.origin] = report.head
        save_state(args.state, seen)
    if args.format == "json":
        sys.stdout.write(json.dumps(report.to_json(), indent=2) + "\n")
    else:
        verdict = "OK" if report.ok else "FAILED"
        sys.stdout.write(f"{verdict}: {report.entries} log entries, {report.approvals} "
                         f"signed records, {report.checkpoints} checkpoints\n")
        for problem in report.problems:
            sys.stdout.write(f"  error: {problem}\n")
        for note in report.notes:
            sys.stdout.write(f"  note: {note}\n")
    return EXIT_OK if report.ok else EXIT_FAILED
