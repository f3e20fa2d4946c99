"""C2SP signed notes (c2sp.org/signed-note), tlog checkpoints (c2sp.org/tlog-checkpoint) and
tlog cosignatures (c2sp.org/tlog-cosignature), with Ed25519 keys.

A checkpoint body is `<origin>\\n<size>\\n<base64 root>\\n`; a signed note is the body, a blank
line and one `— <name> <base64(key hash || signature)>` line per signer. The key hash is the
first 4 bytes of SHA-256(name || 0x0A || type || public key): type 0x01 for a note signature
(over the body), 0x04 for a witness cosignature (over `cosignature/v1\\ntime <t>\\n` + body,
the signature bytes then carry the 8-byte big-endian time before the Ed25519 signature)."""

from __future__ import annotations

import base64
import hashlib
import struct
from dataclasses import dataclass

from cryptography.exceptions import InvalidSignature
from cryptography.hazmat.primitives.asymmetric.ed25519 import Ed25519PrivateKey, Ed25519PublicKey

from .dsse import SignatureError, raw_public

DASH = "\u2014"
ED25519 = 0x01
COSIGNATURE = 0x04


def key_hash(name: str, public: bytes, kind: int = ED25519) -> bytes:
    return hashlib.sha256(name.encode() + b"\n" + bytes([kind]) + public).digest()[:4]


def verifier_key(name: str, public: bytes, kind: int = ED25519) -> str:
    """The `name+hash+key` text naming a verifier (what auditors pin)."""
    return f"{name}+{key_hash(name, public, kind).hex()}+" + \
        base64.b64encode(bytes([kind]) + public).decode()


def parse_verifier_key(text: str) -> tuple[str, int, bytes]:
    """(name, type, raw public key) of a `name+hash+key` verifier key."""
    try:
        name, hash_hex, key_b64 = text.strip().split("+", 2)  # names hold no "+"
        blob = base64.b64decode(key_b64, validate=True)
    except ValueError:
        raise SignatureError("a verifier key is name+hash+base64 key") from None
    if len(blob) != 33 or blob[0] not in (ED25519, COSIGNATURE):
        raise SignatureError("the verifier key is not an Ed25519 key")
    if key_hash(name, blob[1:], blob[0]).hex() != hash_hex:
        raise SignatureError("the verifier key's hash does not match its name and key")
    return name, blob[0], blob[1:]


def checkpoint_body(origin: str, size: int, root: bytes) -> str:
    return f"{origin}\n{size}\n{base64.b64encode(root).decode()}\n"


@dataclass(frozen=True)
class Head:
    origin: str
    size: int
    root: bytes

    def __str__(self) -> str:
        return f"size {self.size}, root {self.root.hex()}"


def parse_body(body: str) -> Head:
    lines = body.split("\n")
    if len(lines) < 4 or lines[-1] != "" or not lines[0]:
        raise SignatureError("the checkpoint is not origin, size and root lines")
    try:
        size = int(lines[1])
        root = base64.b64decode(lines[2], validate=True)
    except ValueError:
        raise SignatureError("the checkpoint's size or root is malformed") from None
    if size < 0 or len(root) != 32 or lines[1] != str(size):
        raise SignatureError("the checkpoint's size or root is malformed")
    return Head(lines[0], size, root)


def signature_line(name: str, public: bytes, signature: bytes, kind: int = ED25519) -> str:
    return f"{DASH} {name} " + base64.b64encode(key_hash(name, public, kind) + signature).decode() \
        + "\n"


def sign_note(body: str, name: str, key: Ed25519PrivateKey) -> str:
    signature = key.sign(body.encode())
    return body + "\n" + signature_line(name, raw_public(key.public_key()), signature)


def split_note(note: str) -> tuple[str, list[tuple[str, bytes]]]:
    """(body, [(name, key hash || signature)]) of a signed note."""
    body, sep, rest = note.partition("\n\n")
    if not sep or not rest.endswith("\n"):
        raise SignatureError("the signed note lacks its blank line or signature lines")
    lines: list[tuple[str, bytes]] = []
    for line in rest[:-1].split("\n"):
        parts = line.split(" ")
        if len(parts) != 3 or parts[0] != DASH:
            raise SignatureError(f"a signature line of the note is malformed: {line[:80]!r}")
        try:
            lines.append((parts[1], base64.b64decode(parts[2], validate=True)))
        except ValueError:
            raise SignatureError("a note signature is not base64") from None
    return body + "\n", lines


def verify_note(note: str, name: str, public: Ed25519PublicKey) -> str:
    """The body of a note that carries a valid signature by this named key."""
    body, lines = split_note(note)
    raw = raw_public(public)
    want = key_hash(name, raw)
    for signer, blob in lines:
        if signer == name and blob[:4] == want:
            try:
                public.verify(blob[4:], body.encode())
            except InvalidSignature:
                raise SignatureError(f"the note's signature by {name} is invalid") from None
            return body
    raise SignatureError(f"the note carries no signature by {name}")


def cosigned_message(body: str, timestamp: int) -> bytes:
    return f"cosignature/v1\ntime {timestamp}\n".encode() + body.encode()


def cosign(body: str, name: str, key: Ed25519PrivateKey, timestamp: int) -> str:
    """A witness's cosignature line over a checkpoint body."""
    signature = key.sign(cosigned_message(body, timestamp))
    return signature_line(name, raw_public(key.public_key()),
                          struct.pack(">Q", timestamp) + signature, COSIGNATURE)


def cosignature_time(line: str, body: str) -> int:
    """The time a stored (already verified) cosignature line claims, without checking it."""
    _, lines = split_note(body + "\n" + line)
    (_, blob), = lines
    return int(struct.unpack(">Q", blob[4:12])[0])


def verify_cosignature(line: str, body: str, name: str, public: bytes) -> int:
    """The time of a valid cosignature line by this witness key over this body."""
    _, lines = split_note(body + "\n" + line)
    (signer, blob), = lines
    if signer != name or blob[:4] != key_hash(name, public, COSIGNATURE) or len(blob) != 76:
        raise SignatureError(f"the cosignature is not by witness {name}")
    timestamp = struct.unpack(">Q", blob[4:12])[0]
    try:
        Ed25519PublicKey.from_public_bytes(public).verify(
            blob[12:], cosigned_message(body, timestamp))
    except InvalidSignature:
        raise SignatureError(f"the cosignature by witness {name} is invalid") from None
    return int(timestamp)
