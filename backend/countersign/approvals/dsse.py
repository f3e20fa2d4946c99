"""DSSE envelopes (v1) signed with Ed25519, and key handling.

A key id is the hex SHA-256 of the raw 32-byte public key; public keys travel as standard
base64 of those raw bytes (what WebCrypto's `exportKey("raw")` gives)."""

from __future__ import annotations

import base64
import binascii
import hashlib
import os
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from cryptography.exceptions import InvalidSignature
from cryptography.hazmat.primitives import serialization
from cryptography.hazmat.primitives.asymmetric.ed25519 import Ed25519PrivateKey, Ed25519PublicKey

from .. import strict_json
from ..orders.json_fields import Malformed, an_object, optional, required

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


@dataclass(frozen=True)
class Signature:
    sig: str
    keyid: str | None = None  # optional in DSSE; absent, not null, when not given

    def to_json(self) -> dict[str, str]:
        return ({} if self.keyid is None else {"keyid": self.keyid}) | {"sig": self.sig}


@dataclass(frozen=True)
class Envelope:
    """A DSSE envelope as Countersign accepts it: exactly one signature. Fields DSSE does
    not define are ignored, as they always were (the signature covers only the payload)."""

    payloadType: str
    payload: str  # standard base64
    signatures: tuple[Signature, ...]

    @property
    def key_id(self) -> str:
        return self.signatures[0].keyid or ""

    @property
    def payload_bytes(self) -> bytes:
        """The payload, unverified: verify_envelope gives it only under a valid signature."""
        return unb64(self.payload, "the payload")

    def to_json(self) -> dict[str, Any]:
        return {"payloadType": self.payloadType, "payload": self.payload,
                "signatures": [s.to_json() for s in self.signatures]}

    @classmethod
    def from_json(cls, data: Any) -> Envelope:
        """The envelope in this JSON; SignatureError names the field that is wrong."""
        try:
            data = an_object(data, "the envelope")
            payload_type = required(data, "payloadType", str, "envelope")
            payload = required(data, "payload", str, "envelope")
            signatures = required(data, "signatures", list, "envelope")
        except Malformed as exc:
            raise SignatureError(f"a DSSE envelope has payloadType, payload and signatures: "
                                 f"{exc}") from None
        try:
            if len(signatures) != 1:
                raise Malformed(f"envelope.signatures has {len(signatures)}")
            one = an_object(signatures[0], "envelope.signatures[0]")
            signature = Signature(required(one, "sig", str, "envelope.signatures[0]"),
                                  optional(one, "keyid", str, "envelope.signatures[0]"))
        except Malformed as exc:
            raise SignatureError(f"the envelope must carry exactly one signature {{keyid, sig}}"
                                 f": {exc}") from None
        return cls(payload_type, payload, (signature,))


def sign_envelope(payload: bytes, key: Ed25519PrivateKey,
                  payload_type: str = PAYLOAD_TYPE) -> dict[str, Any]:
    signature = key.sign(pae(payload_type, payload))
    return Envelope(payload_type, b64(payload),
                    (Signature(b64(signature), key_id(key.public_key())),)).to_json()


def read_envelope(envelope: str | dict[str, Any]) -> Envelope:
    """The envelope in this text (or parsed JSON)."""
    if isinstance(envelope, str):
        try:
            data = strict_json.loads(envelope)
        except ValueError:
            raise SignatureError("the envelope is not JSON") from None
    else:
        data = envelope
    return Envelope.from_json(data)


def parse_envelope(envelope: str | dict[str, Any]) -> dict[str, Any]:
    """The envelope as JSON, checked as read_envelope checks it."""
    return read_envelope(envelope).to_json()


def envelope_key_id(envelope: dict[str, Any] | Envelope) -> str:
    return _typed(envelope).key_id


def _typed(envelope: dict[str, Any] | Envelope) -> Envelope:
    return envelope if isinstance(envelope, Envelope) else Envelope.from_json(envelope)


def verify_envelope(envelope: dict[str, Any] | Envelope, key: Ed25519PublicKey) -> bytes:
    """The payload bytes if the envelope's one signature is valid under this key."""
    typed = _typed(envelope)
    if typed.payloadType != PAYLOAD_TYPE:
        raise SignatureError(f"the payloadType must be {PAYLOAD_TYPE}")
    payload = typed.payload_bytes
    signature = unb64(typed.signatures[0].sig, "the signature")
    try:
        key.verify(signature, pae(typed.payloadType, payload))
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
