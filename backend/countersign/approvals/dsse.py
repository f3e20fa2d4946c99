"""DSSE envelopes (v1) signed with Ed25519, and key handling.

A key id is the hex SHA-256 of the raw 32-byte public key; public keys travel as standard
base64 of those raw bytes (what WebCrypto's `exportKey("raw")` gives)."""

from __future__ import annotations

import base64
import binascii
import hashlib
import os
from pathlib import Path
from typing import Any

from cryptography.exceptions import InvalidSignature
from cryptography.hazmat.primitives import serialization
from cryptography.hazmat.primitives.asymmetric.ed25519 import Ed25519PrivateKey, Ed25519PublicKey

from .. import strict_json

PAYLOAD_TYPE = "application/vnd.in-toto+json"


class SignatureError(ValueError):
    """An envelope, key or signature that cannot be accepted; the message says why."""


def pae(payload_type: str, payload: bytes) -> bytes:
    """DSSE pre-authentication encoding: the exact bytes that are signed."""
    kind = payload_type.encode()
    return b"DSSEv1 %d %s %d %s" % (len(kind), kind, len(payload), payload)


def b64(data: bytes) -> str:
    return base64.b64encode(data).decode()


def unb64(text: str, what: str) -> bytes:
    try:
        return base64.b64decode(text.encode(), validate=True)
    except (binascii.Error, ValueError, UnicodeEncodeError):
        raise SignatureError(f"{what} is not valid base64") from None


def public_key(text: str) -> Ed25519PublicKey:
    raw = unb64(text, "the public key")
    if len(raw) != 32:
        raise SignatureError(f"an Ed25519 public key has 32 bytes, not {len(raw)}")
    return Ed25519PublicKey.from_public_bytes(raw)


def raw_public(key: Ed25519PublicKey) -> bytes:
    return key.public_bytes(serialization.Encoding.Raw, serialization.PublicFormat.Raw)


def key_id(public: str | Ed25519PublicKey) -> str:
    key = public_key(public) if isinstance(public, str) else public
    return hashlib.sha256(raw_public(key)).hexdigest()


def public_text(key: Ed25519PrivateKey | Ed25519PublicKey) -> str:
    public = key.public_key() if isinstance(key, Ed25519PrivateKey) else key
    return b64(raw_public(public))


def sign_envelope(payload: bytes, key: Ed25519PrivateKey,
                  payload_type: str = PAYLOAD_TYPE) -> dict[str, Any]:
    signature = key.sign(pae(payload_type, payload))
    return {"payloadType": payload_type, "payload": b64(payload),
            "signatures": [{"keyid": key_id(key.public_key()), "sig": b64(signature)}]}


def parse_envelope(envelope: str | dict[str, Any]) -> dict[str, Any]:
    if isinstance(envelope, str):
        try:
            data = strict_json.loads(envelope)
        except ValueError:
            raise SignatureError("the envelope is not JSON") from None
    else:
        data = envelope
    if not isinstance(data, dict) or not isinstance(data.get("payload"), str) or not isinstance(
            data.get("payloadType"), str) or not isinstance(data.get("signatures"), list):
        raise SignatureError("a DSSE envelope has payloadType, payload and signatures")
    sigs = data["signatures"]
    if len(sigs) != 1 or not isinstance(sigs[0], dict) or not isinstance(
            sigs[0].get("sig"), str) or not isinstance(sigs[0].get("keyid", ""), str):
        raise SignatureError("the envelope must carry exactly one signature {keyid, sig}")
    return data


def envelope_key_id(envelope: dict[str, Any]) -> str:
    return str(envelope["signatures"][0].get("keyid", ""))


def verify_envelope(envelope: dict[str, Any], key: Ed25519PublicKey) -> bytes:
    """The payload bytes if the envelope's one signature is valid under this key."""
    if envelope["payloadType"] != PAYLOAD_TYPE:
        raise SignatureError(f"the payloadType must be {PAYLOAD_TYPE}")
    payload = unb64(envelope["payload"], "the payload")
    signature = unb64(envelope["signatures"][0]["sig"], "the signature")
    try:
        key.verify(signature, pae(envelope["payloadType"], payload))
    except InvalidSignature:
        raise SignatureError("the signature does not verify over the DSSE PAE of the payload "
                             "with this key") from None
    return payload


def envelope_digest(envelope_text: str) -> str:
    return "sha256:" + hashlib.sha256(envelope_text.encode()).hexdigest()


def generate_key() -> Ed25519PrivateKey:
    return Ed25519PrivateKey.generate()


def private_pem(key: Ed25519PrivateKey) -> bytes:
    return key.private_bytes(serialization.Encoding.PEM, serialization.PrivateFormat.PKCS8,
                             serialization.NoEncryption())


def load_private_pem(data: bytes) -> Ed25519PrivateKey:
    try:
        key = serialization.load_pem_private_key(data, password=None)
    except (ValueError, TypeError):
        raise SignatureError("the key file is not an unencrypted PEM private key") from None
    if not isinstance(key, Ed25519PrivateKey):
        raise SignatureError("the key file does not hold an Ed25519 key")
    return key


def write_private_key(path: Path, key: Ed25519PrivateKey) -> None:
    """Create the key file with permissions 0600; refuse to overwrite one."""
    descriptor = os.open(path, os.O_WRONLY | os.O_CREAT | os.O_EXCL, 0o600)
    with os.fdopen(descriptor, "wb") as handle:
        handle.write(private_pem(key))
