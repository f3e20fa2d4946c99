"""Offline check of an approved package, as a vehicle or a launch checklist runs it.

Checks run in a fixed order and the first failure is the verdict, named by a stable code
(tools/verify_package.py, the standalone verifier, follows the same order and codes):
FORMAT, LOG-KEY, CHECKPOINT, LOG, PROOF, RECEIPT, EXPIRED, ENVELOPE, SIGNATURE, ORDERS,
REVOKED, EXPORT.

Freshness (EXPIRED) is the checkpoint's own timestamp, a cosignature the log signer adds
when it packages a checkpoint that is its latest head, against the verifier's window
(max_age before its clock, CLOCK_SKEW after). Exports are rebuilt from the signed orders and,
when the approval statement signs their digests, compared with those too."""

from __future__ import annotations

import base64
import hashlib
import json
import tarfile
from dataclasses import dataclass
from datetime import UTC, datetime, timedelta
from typing import Any

from cryptography.hazmat.primitives.asymmetric.ed25519 import Ed25519PublicKey

from ..approvals.dsse import (
    SignatureError,
    public_key,
    raw_public,
    read_envelope,
    verify_envelope,
)
from ..approvals.merkle import leaf_hash, root_of, verify_inclusion
from ..approvals.note import (
    COSIGNATURE,
    DASH,
    Head,
    key_hash,
    parse_body,
    split_note,
    verify_cosignature,
    verify_note,
)
from ..approvals.receipt import verify_receipt
from ..approvals.statement import Predicate, Statement, read_statement
from ..approvals.team_rules import team_problems
from ..export.package import export_provenance, signed_provenance, vehicle_files
from ..limits import CLOCK_SKEW
from ..orders.reader import orders_from_data
from .build import ENVELOPE_FILE, ORDERS_FILE, PACKAGE_FORMAT, read_tar

DEFAULT_MAX_AGE = timedelta(days=7)


@dataclass(frozen=True)
class Verdict:
    ok: bool
    code: str
    message: str

    def to_json(self) -> dict[str, Any]:
        return {"ok": self.ok, "code": self.code, "message": self.message}


class Refusal(Exception):
    def __init__(self, code: str, message: str) -> None:
        super().__init__(message)
        self.code, self.message = code, message


def _sha(data: bytes) -> str:
    return "sha256:" + hashlib.sha256(data).hexdigest()


def verify_package(data: bytes, *, log_key: str, now: datetime | None = None,
                   max_age: timedelta = DEFAULT_MAX_AGE) -> Verdict:
    try:
        message = _verify(data, log_key, now or datetime.now(UTC), max_age)
    except Refusal as refusal:
        return Verdict(False, refusal.code, refusal.message)
    return Verdict(True, "OK", message)


def checkpoint_time(note: str, body: str, origin: str, raw: bytes) -> int | None:
    """The Unix time at which the log itself vouched for this checkpoint as its latest head
    (its cosignature line under the log's origin), None when the note carries none."""
    want = key_hash(origin, raw, COSIGNATURE)
    for name, blob in split_note(note)[1]:
        if name == origin and blob[:4] == want:
            line = f"{DASH} {name} " + base64.b64encode(blob).decode() + "\n"
            return verify_cosignature(line, body, origin, raw)
    return None


def _check_fresh(stamp: int | None, receipt_time: str, now: datetime,
                 max_age: timedelta) -> None:
    """Freshness is the checkpoint's own timestamp within the verifier's window [now -
    max_age, now + CLOCK_SKEW]. A package without one (made before timestamps) falls back to
    its newest receipt, which is never newer than a timestamp would have been."""
    if stamp is None:
        newest = datetime.fromisoformat(receipt_time.replace("Z", "+00:00"))
        if now - newest > max_age:
            raise Refusal("EXPIRED", f"the checkpoint has no timestamp and covers nothing "
                          f"newer than {receipt_time}, older than the window of "
                          f"{_window(max_age)}: fetch a fresh package")
        return
    at = datetime.fromtimestamp(stamp, UTC)
    shown = at.isoformat().replace("+00:00", "Z")
    if at > now + CLOCK_SKEW:
        raise Refusal("EXPIRED", f"the checkpoint is timestamped {shown}, in the future of "
                      "this verifier's clock")
    if now - at > max_age:
        raise Refusal("EXPIRED", f"the log timestamped the checkpoint at {shown}, older than "
                      f"the window of {_window(max_age)}: fetch a fresh package")


def _window(max_age: timedelta) -> str:
    return f"{max_age.total_seconds() / 86400:g} day(s)"


@dataclass(frozen=True)
class _Package:
    """The parts of a readable package the checks read."""

    files: dict[str, bytes]
    mission: str
    version: int
    index: int  # the approval's log entry
    entries: list[str]
    proof: dict[str, Any]
    note: str


@dataclass(frozen=True)
class _Log:
    """The log as the package gives it, once its checkpoint verified."""

    head: Head
    leaves: list[bytes]
    events: list[dict[str, Any]]


def _verify(data: bytes, log_key: str, now: datetime, max_age: timedelta) -> str:
    """The checks in the order the module docstring lists them; the first failure raises."""
    package = _read(data)
    try:
        key = public_key(log_key)
    except SignatureError as exc:
        raise Refusal("LOG-KEY", f"the log key is unusable: {exc}") from None
    log = _check_log(package, key, now, max_age)
    statement, envelope_text = _check_approval(package, log.events)
    _check_exports(package, statement.predicate, envelope_text)
    return (f"{package.mission} version {package.version}: approved, orders "
            f"{statement.orders_digest}, log entry {package.index} in checkpoint size "
            f"{log.head.size}; vehicle files match")


def _read(data: bytes) -> _Package:
    try:
        files = read_tar(data)
        manifest = json.loads(files["manifest.json"])
        if manifest.get("format") != PACKAGE_FORMAT:
            raise ValueError(f"not a {PACKAGE_FORMAT} package")
        return _Package(files, str(manifest["mission"]), int(manifest["version"]),
                        int(manifest["approval_index"]),
                        files["log/entries.ndjson"].decode().splitlines(),
                        json.loads(files["log/inclusion.json"]),
                        files["log/checkpoint"].decode())
    except (ValueError, KeyError, TypeError, UnicodeDecodeError, OSError,
            tarfile.TarError) as exc:
        raise Refusal("FORMAT", f"the package is not readable: {exc}") from None


def _check_log(package: _Package, key: Ed25519PublicKey, now: datetime,
               max_age: timedelta) -> _Log:
    """CHECKPOINT, LOG, PROOF, RECEIPT and EXPIRED: the checkpoint, the entries, the proof,
    the receipts and the checkpoint's freshness."""
    try:
        origin = package.note.split("\n", 1)[0]
        body = verify_note(package.note, origin, key)
        head = parse_body(body)
        stamp = checkpoint_time(package.note, body, origin, raw_public(key))
    except SignatureError as exc:
        raise Refusal("CHECKPOINT", f"the checkpoint does not verify under the log key: {exc}"
                      ) from None
    leaves = [leaf_hash(e.encode()) for e in package.entries]
    prev = "0" * 64
    events: list[dict[str, Any]] = []
    for i, text in enumerate(package.entries):
        entry = json.loads(text)
        if entry.get("index") != i or entry.get("prev") != prev:
            raise Refusal("LOG", f"log entry {i} does not chain to the one before")
        events.append(entry["event"])
        prev = leaves[i].hex()
    if len(leaves) != head.size or root_of(leaves) != head.root:
        raise Refusal("LOG", f"the log entries do not hash to the checkpoint ({head})")
    _check_proof(package, leaves, head)
    index = package.index
    for name, at in (("log/receipt.json", index), ("log/head-receipt.json", head.size - 1)):
        try:
            receipt = verify_receipt(package.files[name].decode(), index=at,
                                     leaf=leaves[at].hex(), origin=head.origin, key=key)
        except (SignatureError, KeyError, UnicodeDecodeError) as exc:
            raise Refusal("RECEIPT", f"log entry {at} {exc}") from None
    _check_fresh(stamp, receipt.time, now, max_age)
    return _Log(head, leaves, events)


def _check_proof(package: _Package, leaves: list[bytes], head: Head) -> None:
    index, proof = package.index, package.proof
    if not 0 <= index < head.size:
        raise Refusal("PROOF", f"the approval entry {index} is outside the checkpoint")
    try:
        hashes = [bytes.fromhex(h) for h in proof["hashes"]]
        proved = proof["index"] == index and proof["size"] == head.size and \
            verify_inclusion(leaves[index], index, head.size, hashes, head.root)
    except (KeyError, TypeError, ValueError):
        proved = False
    if not proved:
        raise Refusal("PROOF", f"the inclusion proof of entry {index} does not lead to the "
                      "checkpoint's root")


def _check_approval(package: _Package, events: list[dict[str, Any]]) -> tuple[Statement, str]:
    """ENVELOPE, SIGNATURE, ORDERS and REVOKED: the approval's entry, envelope, signature,
    orders and revocation; the signed statement and the envelope's text."""
    mission, version, index = package.mission, package.version, package.index
    event = events[index]
    detail = event.get("detail") or {}
    envelope_text = package.files[ENVELOPE_FILE].decode()
    if event.get("kind") != "approval.approved" or event.get("mission") != mission or \
            detail.get("version") != version or \
            detail.get("envelope_digest") != _sha(envelope_text.encode()):
        raise Refusal("ENVELOPE", f"the envelope is not the logged approval of {mission} "
                      f"version {version} (log entry {index})")
    try:
        envelope = read_envelope(envelope_text)
        registered = [e for e in events if e.get("kind") == "key.registered"
                      and (e.get("detail") or {}).get("key_id") == envelope.key_id]
        if not registered:
            raise SignatureError(f"its key {envelope.key_id[:16]} is not registered in the log")
        payload = verify_envelope(envelope, public_key(registered[0]["detail"]["public_key"]))
        statement = read_statement(payload)
    except (SignatureError, ValueError, KeyError, TypeError) as exc:
        raise Refusal("SIGNATURE", f"the approval envelope does not verify: {exc}") from None
    orders_bytes = package.files[ORDERS_FILE]
    signed = statement.orders_digest
    if _sha(orders_bytes) != signed or detail.get("orders_digest") != signed:
        raise Refusal("ORDERS", "the orders are not the ones the approval signed "
                      f"({signed})")
    check_team(orders_bytes, statement.predicate.to_json())
    for later in events[index + 1:]:
        if later.get("kind") == "approval.revoked" and \
                (later.get("detail") or {}).get("submission") == detail.get("submission"):
            raise Refusal("REVOKED", f"the approval was revoked (by {later.get('actor')} at "
                          f"{later.get('at')}), as of the checkpoint")
    return statement, envelope_text


def _check_exports(package: _Package, predicate: Predicate, envelope_text: str) -> None:
    """EXPORT: the exports rebuilt from the signed orders, byte for byte, and (statements
    that sign them) each one's digest as the approval signed it."""
    try:
        orders = orders_from_data(json.loads(package.files[ORDERS_FILE]))
    except ValueError as exc:
        raise Refusal("ORDERS", f"the signed orders do not load: {exc}") from None
    files, signed_exports = package.files, predicate.exports
    if signed_exports is not None:
        provenance = signed_provenance(predicate.submission)
    else:
        provenance = export_provenance(envelope_text)
    rebuilt = vehicle_files(orders, package.version, provenance)
    for name, content in rebuilt.items():
        if files.get(name) != content:
            raise Refusal("EXPORT", f"{name} is not the export of the approved orders")
        if signed_exports is not None and signed_exports.get(name) != _sha(content):
            raise Refusal("EXPORT", f"{name} is not the file the approval signed")
    extra = sorted(n for n in files if n.startswith("vehicle/") and n not in rebuilt)
    if extra:
        raise Refusal("EXPORT", f"{extra[0]} is not an export of the approved orders")
    if signed_exports is not None and set(signed_exports) != set(rebuilt):
        missing = sorted(set(signed_exports) ^ set(rebuilt))[0]
        raise Refusal("EXPORT", f"{missing} is signed but not in the package, or the reverse")


def check_team(orders_bytes: bytes, predicate: dict[str, Any]) -> None:
    """A team's approval signs each member's digest too (approvals/team_rules.py): a vehicle
    loading its member's orders relies on it, so a disagreeing list is ORDERS, naming the
    member."""
    try:
        orders = json.loads(orders_bytes)
    except ValueError as exc:
        raise Refusal("ORDERS", f"the signed orders are not JSON: {exc}") from None
    problems = team_problems(orders, predicate)
    if problems:
        raise Refusal("ORDERS", "; ".join(problems))
