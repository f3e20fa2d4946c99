"""`countersign witness`: an auditor, on a machine of their own, holds the server to one history.

It fetches the latest checkpoint, verifies it under the pinned log key, checks that it is a
consistent extension of the one it kept last time (RFC 6962 consistency proof from the server),
keeps one checkpoint per log (by origin) in its state file and, with --key, cosigns it
(c2sp.org/tlog-cosignature) and posts the cosignature for the server to publish. A rollback or
fork is reported naming both tree heads, exit 1; nothing is cosigned then."""

from __future__ import annotations

import argparse
import sys
import time
from collections.abc import Callable
from pathlib import Path
from typing import Any, NamedTuple

from .approvals import ApiError, api_request
from .common import api_token

EXIT_OK, EXIT_FAILED, EXIT_UNREADABLE = 0, 1, 2

Get = Callable[[str], dict[str, Any]]
Post = Callable[[str, dict[str, Any]], dict[str, Any]]


class WitnessError(Exception):
    pass


class Round(NamedTuple):  # not a dataclass: `countersign --help` need not import dataclasses
    ok: bool
    lines: list[str]


def witness_round(get: Get, post: Post | None, *, log_key: str, state: Path,
                  key: Any = None, name: str = "") -> Round:
    """One round: fetch, verify, check consistency, remember, cosign (when `key` is given)."""
    import urllib.parse

    from ..approvals import dsse
    from ..approvals.auditor_state import consistency_problem, load_state, save_state
    from ..approvals.log import verify_checkpoint_head
    from ..approvals.merkle import verify_consistency
    from ..approvals.note import cosign

    lines: list[str] = []
    checkpoint = get("/api/log/checkpoint")
    head = verify_checkpoint_head(checkpoint, dsse.public_key(log_key))
    heads = load_state(state)
    seen = heads.get(head.origin)
    if seen is not None:
        proof_ok: bool | None = None
        if head.size > seen.size and seen.size:
            query = urllib.parse.urlencode({"first": seen.size, "second": head.size})
            proof = get(f"/api/log/consistency?{query}")
            proof_ok = verify_consistency(seen.size, head.size,
                                          [bytes.fromhex(h) for h in proof.get("hashes", [])],
                                          seen.root, head.root)
        problem = consistency_problem(seen, head, proof_ok)
        if problem is not None:
            return Round(False, [f"log {head.origin}: {problem}"])
        lines.append(f"log {head.origin}: {head} extends {seen}")
    else:
        lines.append(f"log {head.origin}: first checkpoint seen, {head}")
    heads[head.origin] = head
    save_state(state, heads)
    if key is not None and post is not None:
        stamp = int(time.time())
        line = cosign(str(checkpoint["note"]), name, key, stamp)
        post("/api/log/cosignatures", {"checkpoint": checkpoint["note"], "cosignature": line})
        lines.append(f"cosigned as {name}")
    return Round(True, lines)


def add_commands(commands: argparse._SubParsersAction) -> None:  # type: ignore[type-arg]
    witness = commands.add_parser(
        "witness", help="verify the server's checkpoint extends the last one seen; cosign it",
        description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    witness.add_argument("--url", required=True, help="the Countersign server")
    witness.add_argument("--log-key", required=True, metavar="B64",
                         help="the log's public key (base64 of the raw 32 bytes), pinned")
    witness.add_argument("--state", required=True, type=Path, metavar="FILE",
                         help="one checkpoint per log, kept between rounds (created first time)")
    witness.add_argument("--key", type=Path, default=None, metavar="WITNESS_KEY",
                         help="the witness's Ed25519 private key (PEM, `countersign keygen`); "
                         "cosign and post the checkpoint")
    # The host's name is looked up when the command runs (socket: not for every --help).
    witness.add_argument("--name", default=None,
                         help="the witness's key name in its cosignatures "
                         "(default: witness.HOSTNAME)")
    witness.add_argument("--token-file", type=Path, default=None,
                         help="API token (otherwise COUNTERSIGN_TOKEN): an auditor's")
    witness.add_argument("--print-key", action="store_true",
                         help="print the witness's verifier key (what the server's "
                         "administrator adds to the witnesses file) and exit")
    witness.set_defaults(handler=cmd_witness)


def _http(url: str, token: str | None) -> tuple[Get, Post]:
    def call(path: str, body: dict[str, Any] | None) -> dict[str, Any]:
        try:
            return api_request(url, token, path, body)
        except ApiError as exc:
            raise WitnessError(str(exc)) from None

    return (lambda path: call(path, None)), call


def cmd_witness(args: argparse.Namespace) -> int:
    from ..approvals import dsse
    from ..approvals.note import COSIGNATURE, verifier_key

    if args.name is None:
        import socket

        args.name = f"witness.{socket.gethostname()}"
    key = None
    if args.key is not None:
        try:
            key = dsse.load_private_pem(args.key.read_bytes())
        except (OSError, dsse.SignatureError) as exc:
            sys.stderr.write(f"countersign: {args.key}: {exc}\n")
            return EXIT_UNREADABLE
        if args.print_key:
            sys.stdout.write(verifier_key(args.name, dsse.raw_public(key.public_key()),
                                          COSIGNATURE) + "\n")
            return EXIT_OK
    token = api_token(args.token_file)
    get, post = _http(args.url, token)
    try:
        result = witness_round(get, post, log_key=args.log_key, state=args.state, key=key,
                               name=args.name)
    except (WitnessError, dsse.SignatureError, KeyError, ValueError) as exc:
        sys.stderr.write(f"countersign: {exc}\n")
        return EXIT_UNREADABLE
    for line in result.lines:
        sys.stdout.write(("" if result.ok else "error: ") + line + "\n")
    return EXIT_OK if result.ok else EXIT_FAILED
