"""The transparency log's entries and signed checkpoints.

Each event becomes one entry: RFC 8785 JSON `{"index", "prev", "event"}` where `prev` is the
hex leaf hash of the entry before (64 zeros for the first), so the entries form a hash chain,
and the leaf hash (RFC 6962: SHA-256 of 0x00 || entry bytes) is a leaf of the Merkle tree.
A checkpoint is the text `countersign-log/1\\n<size>\\n<base64 root>\\n`, signed with the
server's Ed25519 key."""

from __future__ import annotations

from datetime import UTC, datetime
from typing import Any

import rfc8785
from cryptography.exceptions import InvalidSignature
from cryptography.hazmat.primitives.asymmetric.ed25519 import Ed25519PrivateKey, Ed25519PublicKey

from .dsse import SignatureError, b64, key_id, public_text, unb64
from .merkle import leaf_hash

GENESIS = "0" * 64
ORIGIN = "countersign-log/1"


def entry_bytes(index: int, prev: str, event: dict[str, Any]) -> bytes:
    return bytes(rfc8785.dumps({"index": index, "prev": prev, "event": event}))


def entry_leaf(data: bytes) -> str:
    return leaf_hash(data).hex()


def checkpoint_note(size: int, root: bytes) -> str:
    return f"{ORIGIN}\n{size}\n{b64(root)}\n"


def sign_checkpoint(key: Ed25519PrivateKey, size: int, root: bytes) -> dict[str, Any]:
    note = checkpoint_note(size, root)
    return {"size": size, "root": root.hex(), "note": note, "key_id": key_id(key.public_key()),
            "public_key": public_text(key), "signature": b64(key.sign(note.encode()))}


def verify_checkpoint(checkpoint: dict[str, Any], key: Ed25519PublicKey) -> tuple[int, bytes]:
    """(size, root) of a checkpoint whose signature and note are valid under this key."""
    try:
        size, root = int(checkpoint["size"]), bytes.fromhex(str(checkpoint["root"]))
        note, signature = str(checkpoint["note"]), unb64(str(checkpoint["signature"]),
                                                         "the checkpoint signature")
    except (KeyError, ValueError, TypeError):
        raise SignatureError("the checkpoint lacks size, root, note or signature") from None
    if note != checkpoint_note(size, root):
        raise SignatureError(f"the checkpoint note does not state size {size} and its root")
    try:
        key.verify(signature, note.encode())
    except InvalidSignature:
        raise SignatureError(f"the checkpoint at size {size} is not signed by the log key") \
            from None
    return size, root


def event_data(
    *, id: int, at: datetime, actor: str | None, kind: str, mission: str | None,
    before: str | None, after: str | None, detail: dict[str, Any],
) -> dict[str, Any]:
    """What a log entry states about an event (the columns of the events table)."""
    return {"id": id, "at": at.astimezone(UTC).isoformat().replace("+00:00", "Z"),
            "actor": actor, "kind": kind, "mission": mission, "before": before,
            "after": after, "detail": detail}
