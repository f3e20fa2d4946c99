"""Offline verification of an audit bundle: no server, no network.

A bundle (`countersign.audit-bundle/1`) holds the whole log (entry texts), the server's signed
checkpoints and its public key, the supervisors' public keys, the approval envelopes verbatim
with inclusion proofs, and the orders they cover (keyed by digest). Verification recomputes
everything and names each entry, key, envelope or orders that does not match."""

from __future__ import annotations

import hashlib
import json
from dataclasses import dataclass, field
from typing import Any

import rfc8785
from cryptography.hazmat.primitives.asymmetric.ed25519 import Ed25519PublicKey

from ..orders.json_fields import Malformed
from .bundle_model import BUNDLE_FORMAT as BUNDLE_FORMAT
from .bundle_model import Bundle, BundleApprovalOut, BundleKeyOut
from .dsse import SignatureError, envelope_digest, public_key, read_envelope, verify_envelope
from .log import GENESIS, verify_checkpoint_head
from .log_rules import check_log
from .merkle import Tree, leaf_hash, verify_consistency, verify_inclusion
from .note import Head
from .receipt import verify_receipt
from .statement import Statement, json_digest
from .team_rules import team_problems


@dataclass
class BundleReport:
    problems: list[str] = field(default_factory=list)
    notes: list[str] = field(default_factory=list)
    entries: int = 0
    approvals: int = 0
    checkpoints: int = 0
    head: Head | None = None  # the newest checkpoint that verified (for a state file)

    @property
    def ok(self) -> bool:
        return not self.problems

    def to_json(self) -> dict[str, Any]:
        return {"ok": self.ok, "problems": self.problems, "notes": self.notes,
                "entries": self.entries, "approvals": self.approvals,
                "checkpoints": self.checkpoints}


@dataclass
class _Key:
    public_key: str
    user: str
    registered: int
    revoked: int | None = None


def from_problem(document: Any) -> tuple[Any, str | None]:
    """The bundle inside the server's 409 problem for a log with deleted entries (GET
    /api/audit/bundle), with the server's own words; any other document is returned as is."""
    if isinstance(document, dict) and document.get("status") == 409 and \
            isinstance(document.get("bundle"), dict):
        return document["bundle"], str(document.get("detail", ""))
    return document, None


def _es_numbers(value: Any) -> Any:
    """Floats as ECMAScript writes them where Python's repr agrees (integral floats become
    ints; others must lie in [1e-4, 1e16)); anything else raises ValueError (slow path)."""
    if isinstance(value, dict):
        return {k: _es_numbers(v) for k, v in value.items()}
    if isinstance(value, list):
        return [_es_numbers(v) for v in value]
    if isinstance(value, float):
        magnitude = abs(value)
        if magnitude < 1e16 and value.is_integer():
            return int(value)
        if not 1e-4 <= magnitude < 1e16:
            raise ValueError("float outside the fast path")
    return value


def orders_match(orders: Any, signed: str) -> bool:
    """Whether these orders hash to the signed digest (RFC 8785 canonical JSON).

    Fast path: Python's sorted, compact JSON equals RFC 8785 for the usual orders (no floats
    written differently, no characters outside the BMP in keys). Equal digests mean equal
    bytes, which parse to the same data, so a match is sound; on a mismatch the slow, exact
    canonicalisation decides."""
    try:
        fast = json.dumps(_es_numbers(orders), sort_keys=True, separators=(",", ":"),
                          ensure_ascii=False, allow_nan=False).encode()
        if "sha256:" + hashlib.sha256(fast).hexdigest() == signed:
            return True
    except (ValueError, UnicodeEncodeError):
        pass
    try:
        return json_digest(orders) == signed
    except (rfc8785.CanonicalizationError, TypeError, ValueError):
        return False


def verify_bundle(
    bundle: dict[str, Any] | Bundle, *, trusted_log_key: str | None = None,
    published: list[dict[str, Any]] | None = None, seen: dict[str, Head] | None = None,
    held_receipts: list[str] | None = None,
) -> BundleReport:
    """Check a bundle; `trusted_log_key` pins the server's checkpoint key (otherwise the
    bundle's own is used and a note says so); `published` are checkpoints seen earlier, which
    the bundle's log must extend (no fork, no removed entries); `seen` are the heads an
    auditor verified before, by origin (its state file), which the log must extend too;
    `held_receipts` are receipts the verifier holds (a decision's, kept by its signer): the log
    must hold each one's entry. The server's word that its log signer refuses the log is a
    problem too."""
    report = BundleReport()
    try:
        typed = bundle if isinstance(bundle, Bundle) else Bundle.from_json(bundle)
        log_key = public_key(trusted_log_key or typed.log_key.public_key)
    except (Malformed, SignatureError) as exc:
        report.problems.append(str(exc) if isinstance(exc, Malformed)
                               else f"the log's public key is unusable: {exc}")
        return report
    if trusted_log_key is None:
        report.notes.append("checkpoints were checked against the log key inside the bundle; "
                            "pass --log-key to pin the server's published key")
    elif typed.log_key.public_key != trusted_log_key:
        report.problems.append("the bundle's log key is not the pinned log key")
    report.entries = len(typed.entries)
    leaves, events = _check_chain(typed.entries, report)
    tree = Tree(leaves)
    latest = _check_log(typed, tree, leaves, events, log_key, report)
    for checkpoint in published or []:
        _check_published(checkpoint, tree, log_key, report)
    if latest is not None and seen and latest.origin in seen:
        check_extends(seen[latest.origin], tree, report.problems)
    for held in held_receipts or []:
        _check_held(held, leaves, log_key, report)
    if typed.signer_refused:
        report.problems.append(f"the log signer refuses the log: {typed.signer_refused}")
    report.head = latest
    keys = _keys_from_log(events, report)
    _check_bundle_keys(typed.keys, keys, report)
    # --- log-wide rules, approvals/log_rules.py ---
    enveloped = [a.log_index for a in typed.approvals if a.log_index is not None]
    report.problems += check_log(events, enveloped=enveloped, scope=typed.scope)
    # --- end of the log-wide rules ---
    log = _Log(events, leaves, keys, latest)
    for approval in typed.approvals:
        report.approvals += 1
        _check_approval(approval, log, typed, report)
    return report


def _check_log(bundle: Bundle, tree: Tree, leaves: list[bytes], events: list[dict[str, Any]],
               key: Ed25519PublicKey, report: BundleReport) -> Head | None:
    """The checkpoints and the receipts over the chained entries; the newest checkpoint that
    verified."""
    latest = _check_checkpoints([c.model_dump() for c in bundle.checkpoints], tree, key, report)
    # Receipts name the log's origin; without a valid checkpoint, the bundle's word for it
    # (a receipt still needs the log key's signature).
    origin = latest.origin if latest is not None else bundle.log_key.origin or None
    _check_receipts(bundle.receipts, leaves, events, origin, key, report)
    _note_adoption(events, tree, report)
    return latest


def _check_chain(
    texts: list[str], report: BundleReport,
) -> tuple[list[bytes], list[dict[str, Any]]]:
    leaves: list[bytes] = []
    events: list[dict[str, Any]] = []
    prev = GENESIS
    for index, text in enumerate(texts):
        data = text.encode()
        leaf = leaf_hash(data)
        leaves.append(leaf)
        try:
            entry = json.loads(data)
            event = entry["event"]
            if entry["index"] != index:
                report.problems.append(f"log entry {index} claims index {entry['index']}")
            if entry["prev"] != prev:
                report.problems.append(
                    f"log entry {index} does not chain to entry {index - 1}: entry "
                    f"{index - 1} was changed or removed, or entry {index} was altered")
        except (ValueError, KeyError, TypeError):
            report.problems.append(f"log entry {index} is not a valid entry")
            event = {}
        events.append(event if isinstance(event, dict) else {})
        prev = leaf.hex()
    return leaves, events


def _check_held(text: str, leaves: list[bytes], key: Ed25519PublicKey,
                report: BundleReport) -> None:
    """A receipt the verifier holds names an entry the log must still hold."""
    try:
        data = json.loads(text)
        index, leaf, origin = int(data["index"]), str(data["leaf"]), str(data["origin"])
        verify_receipt(text, index=index, leaf=leaf, origin=origin, key=key)
    except (ValueError, KeyError, TypeError, SignatureError) as exc:
        report.problems.append(f"a receipt given to check is not a receipt of this log: {exc}")
        return
    if index >= len(leaves):
        report.problems.append(f"log entry {index} has a receipt from the log signer, but the "
                               f"log ends at {len(leaves)} entries: the entry was erased")
    elif leaves[index].hex() != leaf:
        report.problems.append(f"log entry {index} has a receipt from the log signer for "
                               "another entry than the log holds there: it was replaced")


def _check_receipts(receipts: list[Any], leaves: list[bytes], events: list[dict[str, Any]],
                    origin: str | None, key: Ed25519PublicKey, report: BundleReport) -> None:
    """Every entry carries the log signer's receipt: an entry without one was not appended by
    the app (a row written straight into the database)."""
    if origin is None:
        return
    for index, leaf in enumerate(leaves):
        text = receipts[index] if index < len(receipts) else None
        try:
            verify_receipt(text if isinstance(text, str) else None, index=index, leaf=leaf.hex(),
                           origin=origin, key=key)
        except SignatureError as exc:
            kind = events[index].get("kind") or "?"
            report.problems.append(f"log entry {index} ({kind}) {exc}: it was not appended by "
                                   "the app's log signer")


def _note_adoption(events: list[dict[str, Any]], tree: Tree, report: BundleReport) -> None:
    """Say which entries the log signer adopted at upgrade (receipted after the fact, being
    older than receipts: store/log_adoption.py), and check the adoption names them."""
    for index, event in enumerate(events):
        if event.get("kind") != "log.adopted":
            continue
        detail = event.get("detail") or {}
        size = detail.get("entries")
        if not isinstance(size, int) or not 0 < size <= index or \
                tree.root(size).hex() != detail.get("root"):
            report.problems.append(f"log entry {index} (log.adopted) does not name the entries "
                                   "before it (their count and root)")
            continue
        report.notes.append(f"log entries 0..{size - 1} were appended before the log signer "
                            f"issued receipts; it adopted them on upgrade (log entry {index}), "
                            "so their receipts are not from when they were appended")


def _check_checkpoints(checkpoints: list[dict[str, Any]], tree: Tree, key: Ed25519PublicKey,
                       report: BundleReport) -> Head | None:
    latest: Head | None = None
    good = 0
    seen: dict[int, Head] = {}
    for checkpoint in sorted(checkpoints, key=lambda c: int(c.get("size", 0))):
        report.checkpoints += 1
        try:
            head = verify_checkpoint_head(checkpoint, key)
        except SignatureError as exc:
            report.problems.append(str(exc))
            continue
        size, root = head.size, head.root
        other = seen.setdefault(size, head)
        if other.root != root:
            report.problems.append(f"the log key signed two heads of one size, a fork: "
                                   f"{other} and {head}")
        if latest is not None and latest.origin != head.origin:
            report.problems.append(f"checkpoints of two logs: origins {latest.origin!r} and "
                                   f"{head.origin!r}")
        if size > tree.size:
            report.problems.append(f"a signed checkpoint covers {size} entries but the bundle "
                                   f"holds {tree.size}: entries were removed")
            continue
        if tree.root(size) != root:
            report.problems.append(
                f"log entries {good}..{size - 1} differ from what the checkpoint at size "
                f"{size} signed (an entry in that range was changed): the signed head is "
                f"{head}, the bundle's log gives size {size}, root {tree.root(size).hex()}")
            continue
        good = size
        latest = head
    if latest is None:
        report.problems.append("no valid signed checkpoint covers the log")
    elif latest.size < tree.size:
        report.problems.append(f"log entries {latest.size}..{tree.size - 1} are not covered by "
                               "a signed checkpoint")
    return latest


def _check_published(checkpoint: dict[str, Any], tree: Tree, key: Ed25519PublicKey,
                     report: BundleReport) -> None:
    try:
        seen = verify_checkpoint_head(checkpoint, key)
    except SignatureError as exc:
        report.problems.append(f"published checkpoint: {exc}")
        return
    check_extends(seen, tree, report.problems)


def check_extends(seen: Head, tree: Tree, problems: list[str]) -> None:
    """The log (tree) is the head seen before (a state file, a published checkpoint) or a
    consistent extension of it (RFC 6962 consistency proof); a problem names both heads."""
    current = f"size {tree.size}, root {tree.root().hex()}"
    if seen.size > tree.size:
        problems.append(f"the log was rolled back (truncated): a checkpoint seen before has "
                        f"{seen}; the log now has {current}")
    elif seen.size and not verify_consistency(seen.size, tree.size,
                                              tree.consistency_proof(seen.size), seen.root,
                                              tree.root()):
        problems.append(f"the log forks from the checkpoint seen before ({seen}); the log now "
                        f"has {current}")


def _keys_from_log(events: list[dict[str, Any]], report: BundleReport) -> dict[str, _Key]:
    keys: dict[str, _Key] = {}
    for index, event in enumerate(events):
        detail = event.get("detail") or {}
        if event.get("kind") == "key.registered":
            keys[str(detail.get("key_id"))] = _Key(str(detail.get("public_key")),
                                                   str(detail.get("user")), index)
        elif event.get("kind") == "key.revoked":
            found = keys.get(str(detail.get("key_id")))
            if found is None:
                report.problems.append(f"log entry {index} revokes an unregistered key")
            elif found.revoked is None:
                found.revoked = index
    return keys


def _check_bundle_keys(bundle_keys: list[BundleKeyOut], keys: dict[str, _Key],
                       report: BundleReport) -> None:
    for key in bundle_keys:
        logged = keys.get(key.key_id)
        if logged is None:
            report.problems.append(f"key {key.key_id} was never registered in the log")
        elif logged.public_key != key.public_key:
            report.problems.append(f"key {key.key_id} differs from its registration in "
                                   f"log entry {logged.registered}")


@dataclass(frozen=True)
class _Log:
    """What the approvals are checked against: the log's events and leaves, the keys it
    registered and its newest verified checkpoint."""

    events: list[dict[str, Any]]
    leaves: list[bytes]
    keys: dict[str, _Key]
    latest: Head | None


def _check_approval(approval: BundleApprovalOut, log: _Log, bundle: Bundle,
                    report: BundleReport) -> None:
    name = f"approval {approval.id}"
    index = approval.log_index
    if index is None:
        report.problems.append(f"{name}: its log entry is missing (deleted from the log)")
        return
    if not 0 <= index < len(log.events):
        report.problems.append(f"{name}: its log entry {index} is not in the log")
        return
    detail = log.events[index].get("detail") or {}
    if not str(log.events[index].get("kind", "")).startswith("approval."):
        report.problems.append(f"{name}: log entry {index} does not record a signed decision")
        return
    if envelope_digest(approval.envelope) != detail.get("envelope_digest"):
        report.problems.append(f"{name}: the envelope differs from the one logged in entry "
                               f"{index}")
    try:
        statement, key = _signed_statement(approval.envelope, index, log.keys)
    except (SignatureError, ValueError) as exc:
        report.problems.append(f"{name}: {exc}")
        return
    predicate, signed = statement.predicate, statement.orders_digest
    if signed != detail.get("orders_digest"):
        report.problems.append(f"{name}: the signed subject {signed} is not the digest logged "
                               f"in entry {index}")
    if predicate.decision != detail.get("decision"):
        report.problems.append(f"{name}: the signed decision differs from log entry {index}")
    if predicate.supervisor != key.user:
        report.problems.append(f"{name}: signed by {key.user}'s key but names "
                               f"{predicate.supervisor}")
    if predicate.decision != "revoked":
        _check_orders(name, statement, bundle.orders, report)
    _check_cited(name, "rehearsal", predicate.rehearsal_digest, signed, bundle.rehearsals,
                 report)
    for cited in predicate.campaigns or ():
        _check_cited(name, "campaign", cited, signed, bundle.campaigns, report)
    if log.latest is not None and not _included(approval, index, log.leaves, log.latest):
        report.problems.append(f"{name}: the inclusion proof of log entry {index} does not "
                               "verify against the signed checkpoint")


def _signed_statement(text: str, index: int, keys: dict[str, _Key]) -> tuple[Statement, _Key]:
    """The statement this envelope signs, with a key the log registered before entry `index`
    and had not revoked by then."""
    envelope = read_envelope(text)
    kid = envelope.key_id
    key = keys.get(kid)
    if key is None or key.registered > index:
        raise SignatureError(f"key {kid} was not registered before log entry {index}")
    if key.revoked is not None and key.revoked < index:
        raise SignatureError(f"key {kid} was revoked (log entry {key.revoked}) before it "
                             "signed")
    payload = verify_envelope(envelope, public_key(key.public_key))
    try:
        data = json.loads(payload)
    except ValueError:
        raise ValueError("the signed payload is not an approval statement") from None
    if not isinstance(data, dict) or not isinstance(data.get("predicate"), dict):
        raise ValueError("the signed payload is not an approval statement")
    return Statement.from_json(data), key


def _check_orders(name: str, statement: Statement, orders: dict[str, dict[str, Any]],
                  report: BundleReport) -> None:
    """The bundle holds the signed orders, they hash to the signed digest and, for a team,
    every member's orders to the digest the predicate gives it."""
    signed = statement.orders_digest
    covered = orders.get(signed)
    if covered is None:
        report.problems.append(f"{name}: the bundle lacks the orders {signed}")
    elif not orders_match(covered, signed):
        report.problems.append(f"{name}: the stored orders of {statement.subject[0].name}"
                               f" do not hash to the signed digest {signed}")
    else:
        report.problems.extend(f"{name}: {problem}" for problem in
                               team_problems(covered, statement.predicate.to_json()))


def _included(approval: BundleApprovalOut, index: int, leaves: list[bytes],
              latest: Head) -> bool:
    proof = approval.inclusion
    try:
        hashes = [bytes.fromhex(h) for h in proof.hashes]
    except ValueError:
        return False
    return proof.size == latest.size and verify_inclusion(leaves[index], index, latest.size,
                                                          hashes, latest.root)


def _check_cited(name: str, kind: str, cited: Any, signed: str, records: dict[str, Any],
                 report: BundleReport) -> None:
    """A cited rehearsal or campaign record is in the bundle, hashes to the cited digest
    (RFC 8785) and simulated the signed orders."""
    if cited is None:
        return
    record = records.get(str(cited))
    if not isinstance(record, dict):
        report.problems.append(f"{name}: the bundle lacks the {kind} record {cited} the "
                               "statement cites")
    elif json_digest(record) != cited:
        report.problems.append(f"{name}: the {kind} record does not hash to the cited "
                               f"digest {cited}")
    elif (record.get("orders") or {}).get("digest") != signed:
        verb = "rehearsed" if kind == "rehearsal" else "simulated"
        report.problems.append(f"{name}: the cited {kind} record {verb} other orders "
                               f"than {signed}")
