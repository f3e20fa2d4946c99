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

from ..orders.canonical import canonical_bytes
from ..orders.model import Orders
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


def export_provenance(envelope: str) -> dict[str, Any]:
    """What an export names of its approval: derivable from the envelope alone, so verifiers
    can rebuild it."""
    return {"decision": "approved",
            "envelope_digest": "sha256:" + hashlib.sha256(envelope.encode()).hexdigest()}


def package_files(parts: PackageParts) -> dict[str, bytes]:
    files: dict[str, bytes] = {ORDERS_FILE: canonical_bytes(parts.orders),
                               ENVELOPE_FILE: parts.envelope.encode()}
    approval = export_provenance(parts.envelope)
    for fmt in FORMATS:
        export = export_vehicle(parts.orders, fmt, version=parts.version, approval=approval)
        files.update({f"vehicle/{f.name}": f.content for f in export.files})
    files["log/entries.ndjson"] = "".join(e + "\n" for e in parts.entries).encode()
    files["log/receipt.json"] = parts.receipt.encode()
    files["log/head-receipt.json"] = parts.head_receipt.encode()
    files["log/inclusion.json"] = json.dumps(parts.inclusion, sort_keys=True).encode()
    files["log/checkpoint"] = parts.checkpoint.encode()
    manifest = {"format": PACKAGE_FORMAT, "mission": parts.orders.id, "version": parts.version,
                "approval_index": parts.approval_index,
                "files": {name: "sha256:" + hashlib.sha256(data).hexdigest()
                          for name, data in sorted(files.items())}}
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
