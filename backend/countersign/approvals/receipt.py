"""Receipts: the log signer's signed word that it appended entry `index` with this leaf hash
at this time. Every entry the app appends gets one, so an entry without a valid receipt was
written behind the app's back (a database writer who is not the app)."""

from __future__ import annotations

import json
from dataclasses import dataclass
from typing import Any

import rfc8785
from cryptography.exceptions import InvalidSignature
from cryptography.hazmat.primitives.asymmetric.ed25519 import Ed25519PrivateKey, Ed25519PublicKey

from .dsse import SignatureError, b64, unb64

RECEIPT_FORMAT = "countersign-receipt/v1"


def receipt_message(origin: str, index: int, leaf: str, time: str) -> bytes:
    return f"{RECEIPT_FORMAT}\n{origin}\n{index}\n{leaf}\n{time}\n".encode()


def make_receipt(key: Ed25519PrivateKey, origin: str, index: int, leaf: str, time: str) -> str:
    signature = key.sign(receipt_message(origin, index, leaf, time))
    return bytes(rfc8785.dumps({"format": RECEIPT_FORMAT, "origin": origin, "index": index,
                                "leaf": leaf, "time": time, "signature": b64(signature)})).decode()


@dataclass(frozen=True)
class Receipt:
    origin: str
    index: int
    leaf: str
    time: str


def verify_receipt(text: str | None, *, index: int, leaf: str, origin: str,
                   key: Ed25519PublicKey) -> Receipt:
    """The receipt of entry `index` with this leaf, or SignatureError saying what is wrong."""
    if not text:
        raise SignatureError("carries no receipt from the log signer")
    try:
        data: dict[str, Any] = json.loads(text)
        got = Receipt(str(data["origin"]), int(data["index"]), str(data["leaf"]),
                      str(data["time"]))
        signature = unb64(str(data["signature"]), "the receipt signature")
    except (ValueError, KeyError, TypeError):
        raise SignatureError("has a malformed receipt") from None
    if (got.origin, got.index, got.leaf) != (origin, index, leaf):
        raise SignatureError("has a receipt for another entry (origin, index or leaf hash "
                             "differ)")
    try:
        key.verify(signature, receipt_message(origin, index, leaf, got.time))
    except InvalidSignature:
        raise SignatureError("has a receipt not signed by the log key") from None
    return got
