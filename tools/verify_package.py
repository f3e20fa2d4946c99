#!/usr/bin/env python3
"""Standalone verifier of a Countersign approved package (countersign.package/1).

For vehicles that cannot install Countersign: one file, the standard library plus
`cryptography` and `rfc8785` (canonical JSON, for a team's member digests).
Usage: python3 verify_package.py PACKAGE.tar --log-key BASE64 [--max-age-days N]
[--unpack DIR]
Exit 0 and "OK ..." when the package verifies; exit 1 and "REFUSED CODE: reason" otherwise.
It runs the same checks in the same order as `countersign vehicle verify` and names the first
failure with the same code: FORMAT, LOG-KEY, CHECKPOINT, LOG, PROOF, RECEIPT, EXPIRED,
ENVELOPE, SIGNATURE, ORDERS, REVOKED, EXPORT.

Freshness: the checkpoint's own timestamp (the log's cosignature over it, added when the
package was made) must lie within the last N days (--max-age-days) of this machine's clock,
and not more than 5 minutes ahead of it; a package made before timestamps falls back to its
newest receipt. Exports: it cannot rebuild the vehicle files, so it checks each against the
digest the approval statement signs. A statement signed before statements carried export
digests names none: such a package is refused (EXPORT) unless --trust-manifest is given, when
each file is checked against the manifest and for the approved orders' header only."""

from __future__ import annotations

import argparse
import base64
import binascii
import hashlib
import io
import json
import os
import re
import struct
import sys
import tarfile
from datetime import UTC, datetime, timedelta
from typing import Any

import rfc8785
from cryptography.exceptions import InvalidSignature
from cryptography.hazmat.primitives.asymmetric.ed25519 import Ed25519PublicKey

FORMAT = "countersign.package/1"
MAX_BYTES = 64 * 1024 * 1024
DASH = "\u2014"
CLOCK_SKEW = timedelta(minutes=5)


class Refused(Exception):
    def __init__(self, code: str, message: str) -> None:
        super().__init__(message)
        self.code = code


def sha(data: bytes) -> str:
    return "sha256:" + hashlib.sha256(data).hexdigest()


def b64(text: str) -> bytes:
    return base64.b64decode(text.encode(), validate=True)


def ed25519(text: str) -> Ed25519PublicKey:
    raw = b64(text)
    if len(raw) != 32:
        raise ValueError("an Ed25519 public key has 32 bytes")
    return Ed25519PublicKey.from_public_bytes(raw)


def leaf(data: bytes) -> bytes:
    return hashlib.sha256(b"\x00" + data).digest()


def node(left: bytes, right: bytes) -> bytes:
    return hashlib.sha256(b"\x01" + left + right).digest()


def merkle_root(leaves: list[bytes]) -> bytes:
    """RFC 6962 tree head (pairs left to right, an odd last node carried up)."""
    if not leaves:
        return hashlib.sha256(b"").digest()
    level = leaves
    while len(level) > 1:
        nxt = [node(level[i], level[i + 1]) for i in range(0, len(level) - 1, 2)]
        if len(level) % 2:
            nxt.append(level[-1])
        level = nxt
    return level[0]


def included(leaf_hash: bytes, index: int, size: int, proof: list[bytes], root: bytes) -> bool:
    """RFC 9162 section 2.1.3.2 inclusion proof verification."""
    if not 0 <= index < size:
        return False
    fn, sn, r = index, size - 1, leaf_hash
    for p in proof:
        if sn == 0:
            return False
        if fn % 2 == 1 or fn == sn:
            r = node(p, r)
            while fn % 2 == 0 and fn != 0:
                fn >>= 1
                sn >>= 1
        else:
            r = node(r, p)
        fn >>= 1
        sn >>= 1
    return sn == 0 and r == root


def note_body(note: str, key: Ed25519PublicKey, raw: bytes
              ) -> tuple[str, int, bytes, int | None]:
    """(origin, size, root, timestamp) of a C2SP checkpoint signed by this key under its
    origin; timestamp is the Unix time of the log's own cosignature over it (None: none)."""
    body, sep, rest = note.partition("\n\n")
    body += "\n"
    lines = body.split("\n")
    if not sep or len(lines) < 4:
        raise ValueError("not a signed checkpoint note")
    origin = lines[0]
    want = hashlib.sha256(origin.encode() + b"\n\x01" + raw).digest()[:4]
    stamp_hash = hashlib.sha256(origin.encode() + b"\n\x04" + raw).digest()[:4]
    signed, stamp = False, None
    for line in rest.rstrip("\n").split("\n"):
        parts = line.split(" ")
        if len(parts) == 3 and parts[0] == DASH and parts[1] == origin:
            blob = b64(parts[2])
            if blob[:4] == want and not signed:
                key.verify(blob[4:], body.encode())
                signed = True
            elif blob[:4] == stamp_hash and stamp is None and len(blob) == 76:
                (time,) = struct.unpack(">Q", blob[4:12])
                key.verify(blob[12:], f"cosignature/v1\ntime {time}\n".encode() + body.encode())
                stamp = int(time)
    if not signed:
        raise ValueError(f"no signature by {origin} with this key")
    return origin, int(lines[1]), b64(lines[2]), stamp


def fresh(stamp: int | None, receipt: str, now: datetime, max_age: timedelta) -> None:
    if stamp is None:  # a package made before checkpoints carried timestamps
        if now - datetime.fromisoformat(receipt.replace("Z", "+00:00")) > max_age:
            raise Refused("EXPIRED", f"the checkpoint has no timestamp and covers nothing "
                          f"newer than {receipt}")
        return
    at = datetime.fromtimestamp(stamp, UTC)
    if at > now + CLOCK_SKEW:
        raise Refused("EXPIRED", f"the checkpoint is timestamped {at.isoformat()}, in the "
                      "future of this clock")
    if now - at > max_age:
        raise Refused("EXPIRED", f"the log timestamped the checkpoint at {at.isoformat()}, "
                      f"outside the last {max_age.total_seconds() / 86400:g} day(s)")


def receipt_time(text: str, *, origin: str, index: int, leaf_hex: str,
                 key: Ed25519PublicKey) -> str:
    data = json.loads(text)
    if (data["origin"], data["index"], data["leaf"]) != (origin, index, leaf_hex):
        raise ValueError("is a receipt for another entry")
    message = f"countersign-receipt/v1\n{origin}\n{index}\n{leaf_hex}\n{data['time']}\n"
    key.verify(b64(data["signature"]), message.encode())
    return str(data["time"])


FIXED = ("manifest.json", "orders.json", "approval.dsse.json", "log/entries.ndjson",
         "log/receipt.json", "log/head-receipt.json", "log/inclusion.json", "log/checkpoint")
MAX_MEMBERS = 64
NAME = re.compile(r"(?:(?:log|vehicle)/)?[A-Za-z0-9_][A-Za-z0-9_.:\-]{0,199}")


def canonical_tar(files: dict[str, bytes]) -> bytes:
    """The one tar a package is: sorted names, zero times and owners, mode 0644, USTAR."""
    out = io.BytesIO()
    with tarfile.open(fileobj=out, mode="w", format=tarfile.USTAR_FORMAT) as tar:
        for name in sorted(files):
            info = tarfile.TarInfo(name)
            info.size, info.mtime, info.mode = len(files[name]), 0, 0o644
            info.uid = info.gid = 0
            info.uname = info.gname = ""
            tar.addfile(info, io.BytesIO(files[name]))
    return out.getvalue()


def read_package(data: bytes) -> dict[str, bytes]:
    """The package's files, only when the bytes are exactly the canonical tar of them and the
    members are exactly the manifest's list (tar readers disagree on everything else)."""
    if len(data) > MAX_BYTES:
        raise ValueError("the package is too large")
    files: dict[str, bytes] = {}
    seen: set[str] = set()
    with tarfile.open(fileobj=io.BytesIO(data), mode="r:") as tar:
        while (member := tar.next()) is not None:
            name = member.name
            if len(files) == MAX_MEMBERS:
                raise ValueError(f"the package has more than {MAX_MEMBERS} members")
            if not member.isfile():
                raise ValueError(f"member {name[:80]!r} is not a regular file")
            if not NAME.fullmatch(name) or ".." in name:
                raise ValueError(f"member name {name[:80]!r} is not a package file name")
            if name.casefold() in seen:
                raise ValueError(f"the package holds {name[:80]!r} twice")
            seen.add(name.casefold())
            handle = tar.extractfile(member)
            assert handle is not None
            files[name] = handle.read()
    if canonical_tar(files) != data:
        raise ValueError("the package is not in its canonical tar layout (extra blocks, "
                         "headers or data besides its members)")
    listed = json.loads(files["manifest.json"])["files"]
    if not isinstance(listed, dict):
        raise ValueError("the manifest lists no files")
    missing = [n for n in FIXED if n not in files] + sorted(set(listed) - set(files))
    if missing:
        raise ValueError(f"the package lacks {missing[0][:80]!r}")
    for name, content in files.items():
        if name != "manifest.json" and listed.get(name) != sha(content):
            raise ValueError(f"member {name!r} is not the file its manifest lists")
    return files


def unpack(files: dict[str, bytes], target: str) -> None:
    """Write a verified package's files into a new directory `target` (never an existing one),
    each below it: names were checked by read_package, and files are created, never reused."""
    os.mkdir(target, 0o755)
    root = os.path.realpath(target)
    for name in sorted(files):
        path = os.path.realpath(os.path.join(root, name))
        if os.path.commonpath([root, path]) != root:
            raise ValueError(f"{name!r} would leave {target}")
        os.makedirs(os.path.dirname(path), exist_ok=True)
        fd = os.open(path, os.O_WRONLY | os.O_CREAT | os.O_EXCL | os.O_NOFOLLOW, 0o644)
        with os.fdopen(fd, "wb") as handle:
            handle.write(files[name])


def check(data: bytes, log_key: str, now: datetime, max_age: timedelta,
          trust_manifest: bool = False) -> str:
    try:
        files = read_package(data)
        manifest = json.loads(files["manifest.json"])
        if manifest.get("format") != FORMAT:
            raise ValueError(f"not a {FORMAT} package")
        mission, version = str(manifest["mission"]), int(manifest["version"])
        index = int(manifest["approval_index"])
        entries = files["log/entries.ndjson"].decode().splitlines()
        proof = json.loads(files["log/inclusion.json"])
        note = files["log/checkpoint"].decode()
    except (ValueError, KeyError, TypeError, OSError, tarfile.TarError) as exc:
        raise Refused("FORMAT", f"the package is not readable: {exc}") from None
    try:
        key, raw = ed25519(log_key), b64(log_key)
    except (ValueError, binascii.Error) as exc:
        raise Refused("LOG-KEY", f"the log key is unusable: {exc}") from None
    try:
        origin, size, root, stamp = note_body(note, key, raw)
    except (ValueError, InvalidSignature, binascii.Error) as exc:
        raise Refused("CHECKPOINT", f"the checkpoint does not verify under the log key: "
                      f"{exc or 'bad signature'}") from None
    leaves = [leaf(e.encode()) for e in entries]
    events: list[dict[str, Any]] = []
    prev = "0" * 64
    for i, text in enumerate(entries):
        entry = json.loads(text)
        if entry.get("index") != i or entry.get("prev") != prev:
            raise Refused("LOG", f"log entry {i} does not chain to the one before")
        events.append(entry["event"])
        prev = leaves[i].hex()
    if len(leaves) != size or merkle_root(leaves) != root:
        raise Refused("LOG", "the log entries do not hash to the checkpoint")
    if not 0 <= index < size:
        raise Refused("PROOF", f"the approval entry {index} is outside the checkpoint")
    try:
        proved = proof["index"] == index and proof["size"] == size and included(
            leaves[index], index, size, [bytes.fromhex(h) for h in proof["hashes"]], root)
    except (KeyError, TypeError, ValueError):
        proved = False
    if not proved:
        raise Refused("PROOF", f"the inclusion proof of entry {index} does not lead to the "
                      "checkpoint's root")
    time = ""
    for name, at in (("log/receipt.json", index), ("log/head-receipt.json", size - 1)):
        try:
            time = receipt_time(files[name].decode(), origin=origin, index=at,
                                leaf_hex=leaves[at].hex(), key=key)
        except (ValueError, KeyError, TypeError, InvalidSignature, binascii.Error) as exc:
            raise Refused("RECEIPT", f"log entry {at} has no valid receipt: "
                          f"{exc or 'bad signature'}") from None
    fresh(stamp, time, now, max_age)
    event = events[index]
    detail = event.get("detail") or {}
    envelope_bytes = files.get("approval.dsse.json", b"")
    if event.get("kind") != "approval.approved" or event.get("mission") != mission or \
            detail.get("version") != version or detail.get("envelope_digest") != sha(
                envelope_bytes):
        raise Refused("ENVELOPE", f"the envelope is not the logged approval of {mission} "
                      f"version {version}")
    try:
        envelope = json.loads(envelope_bytes)
        signature = envelope["signatures"][0]
        registered = [e for e in events if e.get("kind") == "key.registered"
                      and (e.get("detail") or {}).get("key_id") == signature["keyid"]]
        if not registered or len(envelope["signatures"]) != 1:
            raise ValueError("its key is not registered in the log")
        payload = b64(envelope["payload"])
        kind = envelope["payloadType"].encode()
        pae = b"DSSEv1 %d %s %d %s" % (len(kind), kind, len(payload), payload)
        ed25519(registered[0]["detail"]["public_key"]).verify(b64(signature["sig"]), pae)
        statement = json.loads(payload)
        signed = "sha256:" + statement["subject"][0]["digest"]["sha256"]
        predicate = statement["predicate"]
        if not isinstance(predicate, dict):
            raise ValueError("the statement has no predicate")
        signed_exports = signed_digests(predicate)
    except (ValueError, KeyError, TypeError, IndexError, InvalidSignature,
            binascii.Error) as exc:
        raise Refused("SIGNATURE", f"the approval envelope does not verify: "
                      f"{exc or 'bad signature'}") from None
    if sha(files.get("orders.json", b"")) != signed or detail.get("orders_digest") != signed:
        raise Refused("ORDERS", f"the orders are not the ones the approval signed ({signed})")
    try:
        problems = team_problems(json.loads(files["orders.json"]), predicate)
    except ValueError as exc:
        raise Refused("ORDERS", f"the signed orders are not JSON: {exc}") from None
    if problems:
        raise Refused("ORDERS", "; ".join(problems))
    for later in events[index + 1:]:
        if later.get("kind") == "approval.revoked" and \
                (later.get("detail") or {}).get("submission") == detail.get("submission"):
            raise Refused("REVOKED", "the approval was revoked, as of the checkpoint")
    vehicle = sorted(n for n in files if n.startswith("vehicle/"))
    if not vehicle:
        raise Refused("EXPORT", "the package holds no vehicle files")
    if signed_exports is not None:
        for name in vehicle:
            if signed_exports.get(name) != sha(files[name]):
                raise Refused("EXPORT", f"{name} is not the file the approval signed")
        missing = sorted(set(signed_exports) - set(vehicle))
        if missing:
            raise Refused("EXPORT", f"{missing[0]} is signed but not in the package")
    elif not trust_manifest:
        raise Refused("EXPORT", "the approval statement signs no export digests (signed "
                      "before they existed): only `countersign vehicle verify` can rebuild "
                      "the exports; --trust-manifest checks them against the manifest")
    else:
        manifest_only(files, manifest, vehicle, mission, version, signed, envelope_bytes)
    return (f"{mission} version {version}: approved, orders {signed}, log entry {index} in "
            f"checkpoint size {size}; vehicle files match")


# member_digests and team_problems are this file's copy of approvals/team_rules.py (the tool
# imports nothing of Countersign); tests/approvals/test_team_vectors.py holds both to the same
# problems on the shared team vectors.
def member_digests(orders: Any) -> dict[str, str] | None:
    """A team's member orders digests by vehicle (each member's orders alone, as
    countersign.orders/1, canonical JSON), or None when the orders hold no team."""
    members = orders.get("team") if isinstance(orders, dict) else None
    if not isinstance(members, list) or not all(
            isinstance(m, dict) and isinstance(m.get("orders"), dict) for m in members):
        return None
    return {str(m.get("vehicle")): sha(bytes(rfc8785.dumps(
        {**m["orders"], "format": "countersign.orders/1"}))) for m in members}


def team_problems(orders: Any, predicate: Any) -> list[str]:
    """A team's approval signs each member's digest (predicate.team): what disagrees with the
    orders, naming the member, in the words of `countersign vehicle verify`."""
    signed = predicate.get("team") if isinstance(predicate, dict) else None
    actual = member_digests(orders)
    if signed is None:
        return [] if actual is None else [
            "the orders hold a team but the statement signs no member digests (predicate.team)"]
    if actual is None:
        return ["the statement signs a team's member digests (predicate.team) but the orders "
                "hold no team"]
    if not isinstance(signed, dict) or not all(isinstance(v, str) for v in signed.values()):
        return ["the statement's predicate.team is not a map of vehicle to orders digest"]
    problems = [f"team member {vehicle}: the statement signs no digest for it"
                for vehicle in actual if vehicle not in signed]
    problems += [f"team member {vehicle}: the statement signs a digest for it but the team "
                 "has no such member" for vehicle in signed if vehicle not in actual]
    problems += [f"team member {vehicle}: the signed digest {signed[vehicle]} is not that of "
                 f"its orders ({digest})"
                 for vehicle, digest in actual.items()
                 if vehicle in signed and signed[vehicle] != digest]
    return problems


def signed_digests(predicate: dict[str, Any]) -> dict[str, str] | None:
    """The statement's export digests, None when it signs none. A signed statement of the
    wrong shape is a SIGNATURE fault, as `countersign vehicle verify` reads it: the signature
    holds, but over no approval statement."""
    if "exports" not in predicate:
        return None
    exports = predicate["exports"]
    if not isinstance(exports, dict) or not all(
            isinstance(k, str) and isinstance(v, str) for k, v in exports.items()):
        raise ValueError("statement.predicate.exports must be an object of strings")
    return exports


def manifest_only(files: dict[str, bytes], manifest: dict[str, Any], vehicle: list[str],
                  mission: str, version: int, signed: str, envelope_bytes: bytes) -> None:
    """The weak check of exports an old statement leaves: manifest digest and header."""
    approval = {"decision": "approved", "envelope_digest": sha(envelope_bytes)}
    imc = json.dumps({"approval": approval, "generator": "countersign", "mission": mission,
                      "orders_digest": signed, "version": version}, sort_keys=True).encode()
    header = f"// orders {signed}  plan {mission}@v{version}\n".encode()
    names = manifest.get("files") or {}
    for name in vehicle:
        content = files[name]
        if names.get(name) != sha(content):
            raise Refused("EXPORT", f"{name} is not the file the manifest lists")
        expected = imc if name.endswith(".imc") else header
        if expected not in content or (name.endswith(".bhv") and json.dumps(
                approval, sort_keys=True).encode() not in content):
            raise Refused("EXPORT", f"{name} is not the export of the approved orders")


def verify(data: bytes, log_key: str, now: datetime | None = None,
           max_age: timedelta = timedelta(days=7),
           trust_manifest: bool = False) -> tuple[bool, str, str]:
    """(ok, code, message): code is OK or the first failed check."""
    try:
        return True, "OK", check(data, log_key, now or datetime.now(UTC), max_age,
                                 trust_manifest)
    except Refused as refusal:
        return False, refusal.code, str(refusal)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("package")
    parser.add_argument("--log-key", required=True, help="the log's Ed25519 public key, base64")
    parser.add_argument("--max-age-days", type=float, default=7.0,
                        help="how old the checkpoint's timestamp may be (default 7)")
    parser.add_argument("--trust-manifest", action="store_true",
                        help="for approvals signed before statements carried export digests: "
                        "check the exports against the manifest only")
    parser.add_argument("--unpack", metavar="DIR", default=None,
                        help="after the package verifies (and only then), write its files "
                        "into DIR, a new directory; unpack packages this way, never with tar")
    args = parser.parse_args(argv)
    try:
        with open(args.package, "rb") as handle:
            data = handle.read(MAX_BYTES + 1)
    except OSError as exc:
        print(f"REFUSED FORMAT: cannot read {args.package}: {exc.strerror}")
        return 2
    ok, code, message = verify(data, args.log_key, max_age=timedelta(days=args.max_age_days),
                               trust_manifest=args.trust_manifest)
    print(f"OK {message}" if ok else f"REFUSED {code}: {message}")
    if ok and args.unpack:
        try:
            unpack(read_package(data), args.unpack)
        except OSError as exc:
            print(f"not unpacked: {args.unpack}: {exc.strerror}")
            return 2
        print(f"unpacked into {args.unpack}")
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
