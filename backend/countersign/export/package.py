"""The vehicle files of an approved package and their digests: what an approval statement
signs of the exports (approved_package/ builds and verifies the package itself, which also
holds the approval's evidence; `export` imports `orders` and `verify` only)."""

from __future__ import annotations

import hashlib
from typing import Any

from ..orders.model import Orders
from .notes import ExportError
from .vehicle import FORMATS, export_vehicle


def _sha(data: bytes) -> str:
    return "sha256:" + hashlib.sha256(data).hexdigest()


def export_provenance(envelope: str) -> dict[str, Any]:
    """What an export names of its approval when the statement does not sign the exports
    (statements signed before the predicate had an `exports` field): derivable from the
    envelope alone, so verifiers can rebuild it."""
    return {"decision": "approved", "envelope_digest": _sha(envelope.encode())}


def signed_provenance(submission: int) -> dict[str, Any]:
    """What an export names of its approval when the statement signs the exports: only what
    is known before the signature exists (the envelope signs the file, not the reverse)."""
    return {"decision": "approved", "submission": submission}


def vehicle_files(orders: Orders, version: int, approval: dict[str, Any]) -> dict[str, bytes]:
    """Every vehicle file of the orders by its name in the package: `vehicle/NAME` for one
    vehicle's orders, `vehicle/MEMBER.NAME` for each member of a team (a package keeps two
    path segments; member ids are names of the orders' safe alphabet)."""
    files: dict[str, bytes] = {}
    members = [None] if orders.team is None else [m.vehicle for m in orders.team]
    for member in members:
        prefix = "vehicle/" if member is None else f"vehicle/{member}."
        for fmt in FORMATS:
            export = export_vehicle(orders, fmt, version=version, approval=approval,
                                    member=member)
            files.update({prefix + f.name: f.content for f in export.files})
    return files


def export_digests(orders: Orders, *, version: int, submission: int) -> dict[str, str] | None:
    """The digests an approval statement signs (None when the orders cannot be exported)."""
    try:
        files = vehicle_files(orders, version, signed_provenance(submission))
    except ExportError:
        return None
    return {name: _sha(data) for name, data in sorted(files.items())}
