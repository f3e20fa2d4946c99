"""The transparency log's entries and signed checkpoints.

Each event becomes one entry: RFC 8785 JSON `{"index", "prev", "event"}` where `prev` is the
hex leaf hash of the entry before (64 zeros for the first), so the entries form a hash chain,
and the leaf hash (RFC 6962: SHA-256 of 0x00 || entry bytes) is a leaf of the Merkle tree.
A checkpoint is a C2SP tlog-checkpoint signed note (note.py) whose origin names the log,
signed by the log signer (signer.py)."""

from __future__ import annotations

from datetime import UTC, datetime
from typing import Any

import rfc8785
from cryptography.exceptions import InvalidSignature
from cryptography.hazmat.primitives.asymmetric.ed25519 import Ed25519PrivateKey, Ed25519PublicKey

from .dsse import SignatureError, b64, key_id, public_text, unb64
from .merkle import leaf_hash
from .note import Head, checkpoint_body, parse_body, sign_note, verify_note

GENESIS = "0" * 64


def entry_bytes(index: int, prev: str, event: dict[str, Any]) -> bytes:
    return bytes(rfc8785.dumps({"index": index, "prev": prev, "event": event}))


def entry_leaf(data: bytes) -> str:
    return leaf_hash(data).hex()


DEFAULT_ORIGIN = "countersign.example/log"


def sign_checkpoint(key: Ed25519PrivateKey, size: int, root: bytes, *,
                    origin: str = DEFAULT_ORIGIN) -> dict[str, Any]:
    """A checkpoint as the API and bundles carry it (the log signer decides when to call)."""
    body = checkpoint_body(origin, size, root)
    return {"size": size, "root": root.hex(), "origin": origin, "note": body,
            "signed_note": sign_note(body, origin, key), "key_id": key_id(key.public_key()),
            "public_key": public_text(key), "signature": b64(key.sign(body.encode()))}


def verify_checkpoint_head(checkpoint: dict[str, Any], key: Ed25519PublicKey) -> Head:
    """The head of a checkpoint: `note` is its C2SP tlog-checkpoint body, `signature` the log
    key's Ed25519 signature over it, `signed_note` (when present) the signed note."""
    try:
        size, root = int(checkpoint["size"]), bytes.fromhex(str(checkpoint["root"]))
        body, signature = str(checkpoint["note"]), unb64(str(checkpoint["signature"]),
                                                         "the checkpoint signature")
    except (KeyError, ValueError, TypeError):
        raise SignatureError("the checkpoint lacks size, root, note or signature") from None
    head = parse_body(body)
    if (head.size, head.root) != (size, root):
        raise SignatureError(f"the checkpoint note does not state size {size} and its root")
    try:
        key.verify(signature, body.encode())
    except InvalidSignature:
        raise SignatureError(f"the checkpoint at size {size} is not signed by the log key") \
            from None
    signed = checkpoint.get("signed_note")
    if signed is not None and verify_note(str(signed), head.origin, key) != body:
        raise SignatureError(f"the signed note of the checkpoint at size {size} has another "
                             "body")
    return head


def event_data(
    *, id: int, at: datetime, actor: str | None, kind: str, mission: str | None,
    before: str | None, after: str | None, detail: dict[str, Any],
) -> dict[str, Any]:
    """What a log entry states about an event (the columns of the events table)."""
    return {"id": id, "at": at.astimezone(UTC).isoformat().replace("+00:00", "Z"),
            "actor": actor, "kind": kind, "mission": mission, "before": before,
            "after": after, "detail": detail}
