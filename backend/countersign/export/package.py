"""Approved packages (`countersign.package/1`): one deterministic tar holding the orders, their
vehicle exports, the approval envelope, its log receipt, an inclusion proof, the signed
checkpoint and the log entries it covers, so a vehicle can check offline what it loads."""

from __future__ import annotations

import hashlib
import io
import json
import tarfile
from dataclasses import dataclass
from typing import Any

from ..approvals.dsse import SignatureError, parse_envelope, unb64
from ..orders.canonical import canonical_bytes
from ..orders.model import Orders
from .notes import ExportError
from .vehicle import FORMATS, export_vehicle

PACKAGE_FORMAT = "countersign.package/1"
ORDERS_FILE = "orders.json"
ENVELOPE_FILE = "approval.dsse.json"
MAX_PACKAGE_BYTES = 64 * 1024 * 1024


@dataclass(frozen=True)
class PackageParts:
    orders: Orders
    version: int
    envelope: str
    approval_index: int
    entries: list[str]  # log entry texts 0 .. checkpoint size - 1
    receipt: str  # the approval entry's receipt
    head_receipt: str  # the last covered entry's receipt: how fresh the checkpoint is
    inclusion: dict[str, Any]  # {"index", "size", "hashes"}
    checkpoint: str  # C2SP signed note


# The approval statement's predicate field holding the digest of every vehicle file, by its
# name in the package: the signature then names the exports, so a verifier that cannot rebuild
# them (tools/verify_package.py) still detects a forged one.
SIGNED_EXPORTS = "exports"


def _sha(data: bytes) -> str:
    return "sha256:" + hashlib.sha256(data).hexdigest()


def export_provenance(envelope: str) -> dict[str, Any]:
    """What an export names of its approval when the statement does not sign the exports
    (statements signed before SIGNED_EXPORTS): derivable from the envelope alone, so verifiers
    can rebuild it."""
    return {"decision": "approved", "envelope_digest": _sha(envelope.encode())}


def signed_provenance(submission: int) -> dict[str, Any]:
    """What an export names of its approval when the statement signs the exports: only what
    is known before the signature exists (the envelope signs the file, not the reverse)."""
    return {"decision": "approved", "submission": submission}


def vehicle_files(orders: Orders, version: int, approval: dict[str, Any]) -> dict[str, bytes]:
    files: dict[str, bytes] = {}
    for fmt in FORMATS:
        export = export_vehicle(orders, fmt, version=version, approval=approval)
        files.update({f"vehicle/{f.name}": f.content for f in export.files})
    return files


def export_digests(orders: Orders, *, version: int, submission: int) -> dict[str, str] | None:
    """The digests an approval statement signs (None when the orders cannot be exported)."""
    try:
        files = vehicle_files(orders, version, signed_provenance(submission))
    except ExportError:
        return None
    return {name: _sha(data) for name, data in sorted(files.items())}


def unverified_predicate(envelope: str) -> dict[str, Any]:
    """The predicate of an envelope's statement, read without checking its signature (only
    to choose how to rebuild the exports; verifiers check the signature themselves)."""
    try:
        payload = unb64(parse_envelope(envelope)["payload"], "the payload")
        predicate = json.loads(payload).get("predicate")
    except (SignatureError, ValueError, KeyError, TypeError, AttributeError):
        return {}
    return predicate if isinstance(predicate, dict) else {}


def approved_vehicle_files(orders: Orders, version: int, envelope: str) -> dict[str, bytes]:
    """The vehicle files of an approved package, as its approval statement determines them."""
    predicate = unverified_predicate(envelope)
    if isinstance(predicate.get(SIGNED_EXPORTS), dict):
        return vehicle_files(orders, version, signed_provenance(int(predicate["submission"])))
    return vehicle_files(orders, version, export_provenance(envelope))


def package_files(parts: PackageParts) -> dict[str, bytes]:
    files: dict[str, bytes] = {ORDERS_FILE: canonical_bytes(parts.orders),
                               ENVELOPE_FILE: parts.envelope.encode()}
    files.update(approved_vehicle_files(parts.orders, parts.version, parts.envelope))
    files["log/entries.ndjson"] = "".join(e + "\n" for e in parts.entries).encode()
    files["log/receipt.json"] = parts.receipt.encode()
    files["log/head-receipt.json"] = parts.head_receipt.encode()
    files["log/inclusion.json"] = json.dumps(parts.inclusion, sort_keys=True).encode()
    files["log/checkpoint"] = parts.checkpoint.encode()
    manifest = {"format": PACKAGE_FORMAT, "mission": parts.orders.id, "version": parts.version,
                "approval_index": parts.approval_index,
                "files": {name: _sha(data) for name, data in sorted(files.items())}}
    files["manifest.json"] = json.dumps(manifest, sort_keys=True, indent=1).encode()
    return files


def write_tar(files: dict[str, bytes]) -> bytes:
    """Deterministic tar: sorted names, zero times and owners, fixed modes."""
    out = io.BytesIO()
    with tarfile.open(fileobj=out, mode="w", format=tarfile.USTAR_FORMAT) as tar:
        for name in sorted(files):
            info = tarfile.TarInfo(name)
            info.size, info.mtime, info.mode = len(files[name]), 0, 0o644
            info.uid = info.gid = 0
            info.uname = info.gname = ""
            tar.addfile(info, io.BytesIO(files[name]))
    return out.getvalue()


def build_package(parts: PackageParts) -> bytes:
    return write_tar(package_files(parts))


def read_tar(data: bytes) -> dict[str, bytes]:
    """Regular files of a package tar (bounded; links and odd members refused)."""
    if len(data) > MAX_PACKAGE_BYTES:
        raise ValueError(f"the package is larger than {MAX_PACKAGE_BYTES:,} bytes")
    files: dict[str, bytes] = {}
    with tarfile.open(fileobj=io.BytesIO(data), mode="r:") as tar:
        for member in tar.getmembers():
            if not member.isfile() or member.name in files:
                raise ValueError(f"the package member {member.name[:80]!r} is not one plain file")
            handle = tar.extractfile(member)
            assert handle is not None
            files[member.name] = handle.read()
    return files
