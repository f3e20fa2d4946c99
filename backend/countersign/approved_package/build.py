"""Approved packages (`countersign.package/1`): one deterministic tar holding the orders, their
vehicle exports, the approval envelope, its log receipt, an inclusion proof, the signed
checkpoint and the log entries it covers, so a vehicle can check offline what it loads.

A package joins two packages of one ring: the vehicle files come from `export`
(export/package.py), the evidence from `approvals`; so it sits above both (tests/codebase/
test_layering.py) and `export` never imports `approvals`."""

from __future__ import annotations

import hashlib
import io
import json
import re
import tarfile
from dataclasses import dataclass
from typing import Any

from ..approvals.dsse import read_envelope
from ..approvals.statement import Predicate, Statement
from ..export.package import export_provenance, signed_provenance, vehicle_files
from ..limits import MAX_PACKAGE_BYTES
from ..orders.canonical import canonical_bytes
from ..orders.model import Orders

PACKAGE_FORMAT = "countersign.package/1"
ORDERS_FILE = "orders.json"
ENVELOPE_FILE = "approval.dsse.json"


def _sha(data: bytes) -> str:
    return "sha256:" + hashlib.sha256(data).hexdigest()


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


def unverified_predicate(envelope: str) -> Predicate | None:
    """The predicate of an envelope's statement, read without checking its signature (only
    to choose how to rebuild the exports; verifiers check the signature themselves)."""
    try:
        return Statement.from_json(json.loads(read_envelope(envelope).payload_bytes)).predicate
    except ValueError:  # SignatureError and Malformed are ValueErrors
        return None


def approved_vehicle_files(orders: Orders, version: int, envelope: str) -> dict[str, bytes]:
    """The vehicle files of an approved package, as its approval statement determines them."""
    predicate = unverified_predicate(envelope)
    if predicate is not None and predicate.exports is not None:
        return vehicle_files(orders, version, signed_provenance(predicate.submission))
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


# The members every package holds besides its vehicle files; anything else a reader meets is
# not part of the layout, whatever a tar tool would make of it.
FIXED_MEMBERS = ("manifest.json", ORDERS_FILE, ENVELOPE_FILE, "log/entries.ndjson",
                 "log/receipt.json", "log/head-receipt.json", "log/inclusion.json",
                 "log/checkpoint")
MAX_MEMBERS = 64
# One or two plain segments (`orders.json`, `vehicle/x.imc`): no `.`/`..`, no leading `/` or
# `./`, nothing a file system could read as another place.
_MEMBER_NAME = re.compile(r"(?:(?:log|vehicle)/)?[A-Za-z0-9_][A-Za-z0-9_.:\-]{0,199}")


class LayoutError(ValueError):
    """The tar is not a package in its one canonical layout."""


def read_tar(data: bytes) -> dict[str, bytes]:
    """The files of a package tar, refused unless the bytes are exactly the canonical tar of
    those files (`write_tar`) and the members are exactly the manifest's list. Tar readers
    disagree on duplicates, `./` prefixes, bad header blocks and trailing data; a package
    that has none of them reads the same in every one of them."""
    if len(data) > MAX_PACKAGE_BYTES:
        raise LayoutError(f"the package is larger than {MAX_PACKAGE_BYTES:,} bytes")
    files: dict[str, bytes] = {}
    seen: set[str] = set()
    with tarfile.open(fileobj=io.BytesIO(data), mode="r:") as tar:
        while (member := tar.next()) is not None:
            name = member.name
            if len(files) == MAX_MEMBERS:
                raise LayoutError(f"the package has more than {MAX_MEMBERS} members")
            if not member.isfile():
                raise LayoutError(f"the package member {name[:80]!r} is not a regular file")
            if not _MEMBER_NAME.fullmatch(name) or ".." in name:
                raise LayoutError(f"the package member name {name[:80]!r} is not a package "
                                  "file name")
            if name.casefold() in seen:
                raise LayoutError(f"the package holds {name[:80]!r} twice")
            seen.add(name.casefold())
            handle = tar.extractfile(member)
            assert handle is not None
            files[name] = handle.read()
    if write_tar(files) != data:
        raise LayoutError("the package is not in its canonical tar layout (extra blocks, "
                          "headers or data besides its members)")
    _check_listed(files)
    return files


def _check_listed(files: dict[str, bytes]) -> None:
    """Every member is a file of the manifest's list with the listed digest, and the list
    names no file the package lacks."""
    try:
        listed = json.loads(files["manifest.json"])["files"]
        if not isinstance(listed, dict):
            raise TypeError
    except (KeyError, TypeError, ValueError):
        raise LayoutError("the package has no manifest listing its files") from None
    missing = [n for n in FIXED_MEMBERS if n not in files]
    if missing:
        raise LayoutError(f"the package lacks {missing[0]}")
    for name, content in files.items():
        if name != "manifest.json" and listed.get(name) != _sha(content):
            raise LayoutError(f"the package member {name!r} is not the file its manifest "
                              "lists")
    unlisted = sorted(set(listed) - set(files))
    if unlisted:
        raise LayoutError(f"the manifest lists {unlisted[0][:80]!r}, which the package lacks")
