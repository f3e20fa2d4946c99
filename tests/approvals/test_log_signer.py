"""The log signer (approvals/signer.py) and C2SP notes (approvals/note.py), without a database:
it signs only consistent extensions of its last head whose every new entry it receipted, and
two signers sharing one directory (two server processes) share one history."""

from __future__ import annotations

import os
import stat
from pathlib import Path

import pytest

from countersign.approvals import dsse
from countersign.approvals.log import verify_checkpoint_head
from countersign.approvals.merkle import Tree, leaf_hash
from countersign.approvals.note import (
    COSIGNATURE,
    cosign,
    key_hash,
    parse_verifier_key,
    verifier_key,
    verify_cosignature,
    verify_note,
)
from countersign.approvals.signer import LogSigner, SignerError, SignerRefused


def _tree(items: list[bytes]) -> Tree:
    return Tree(leaf_hash(i) for i in items)


def _receipts(signer: LogSigner, tree: Tree, start: int = 0) -> dict[int, str]:
    return {i: signer.receipt(i, tree.levels[0][i].hex(), "2026-12-01T00:00:00Z")
            for i in range(start, tree.size)}


def test_key_file_is_private_and_origin_unique(tmp_path: Path) -> None:
    first, second = LogSigner(tmp_path / "a"), LogSigner(tmp_path / "b")
    assert stat.S_IMODE((tmp_path / "a" / "log-key.pem").stat().st_mode) == 0o600
    assert first.origin != second.origin
    assert LogSigner(tmp_path / "a").origin == first.origin  # kept with the key
    os.chmod(tmp_path / "a" / "log-key.pem", 0o640)
    with pytest.raises(SignerError, match="may be read by others"):
        LogSigner(tmp_path / "a")


def test_signs_consistent_extensions_only(tmp_path: Path) -> None:
    signer = LogSigner(tmp_path)
    items = [bytes([i]) for i in range(7)]
    tree = _tree(items[:5])
    receipts = _receipts(signer, tree)
    signed = signer.sign_head(tree, receipts)
    head = verify_checkpoint_head(signed, signer.public)
    assert (head.origin, head.size, head.root) == (signer.origin, 5, tree.root())
    assert verify_note(signed["signed_note"], signer.origin, signer.public) == signed["note"]
    last = f"size 5, root {tree.root().hex()}"

    longer = _tree(items)
    assert signer.sign_head(longer, {**receipts, **_receipts(signer, longer, 5)})["size"] == 7

    forked = _tree([*items[:3], b"X", *items[4:]])
    with pytest.raises(SignerRefused, match="not a consistent extension of the last: the signer's "
                       f"last head is size 7, root {longer.root().hex()}, the new head is "
                       f"size 7, root {forked.root().hex()}|the log forks"):
        signer.sign_head(forked, _receipts(signer, forked))
    with pytest.raises(SignerRefused, match=f"the log would roll back: the signer's last head is "
                       f"size 7, root {longer.root().hex()}, the new head is {'size 5'}"):
        signer.sign_head(tree, receipts)
    rewritten = _tree([*items[:3], b"X", *items[4:], b"8"])
    with pytest.raises(SignerRefused, match="not a consistent extension"):
        signer.sign_head(rewritten, _receipts(signer, rewritten))
    assert last  # the heads named are size and root


def test_refuses_entries_it_did_not_receipt(tmp_path: Path) -> None:
    signer, other = LogSigner(tmp_path / "s"), LogSigner(tmp_path / "o")
    tree = _tree([b"a", b"b", b"c"])
    receipts = _receipts(signer, tree)
    del receipts[1]
    with pytest.raises(SignerRefused, match="log entry 1 carries no receipt from the log signer"):
        signer.sign_head(tree, receipts)
    receipts[1] = _receipts(other, tree)[1]
    with pytest.raises(SignerRefused, match="log entry 1 has a receipt for another entry"):
        signer.sign_head(tree, receipts)
    assert signer.head().size == 0  # nothing was signed


def test_two_processes_share_one_history(tmp_path: Path) -> None:
    one, two = LogSigner(tmp_path), LogSigner(tmp_path)
    tree = _tree([b"a", b"b", b"c"])
    one.sign_head(tree, _receipts(one, tree))
    other = _tree([b"a", b"b", b"X"])
    with pytest.raises(SignerRefused, match="the log forks"):
        two.sign_head(other, _receipts(two, other))
    longer = _tree([b"a", b"b", b"c", b"d"])
    assert two.sign_head(longer, _receipts(two, longer, 3))["size"] == 4


def test_verifier_keys_and_cosignatures() -> None:
    key = dsse.generate_key()
    raw = dsse.raw_public(key.public_key())
    text = verifier_key("witness.example", raw, COSIGNATURE)
    assert parse_verifier_key(text) == ("witness.example", COSIGNATURE, raw)
    assert text.split("+")[1] == key_hash("witness.example", raw, COSIGNATURE).hex()
    body = "example.com/log\n3\n" + dsse.b64(b"\x00" * 32) + "\n"
    line = cosign(body, "witness.example", key, 1_700_000_000)
    assert line.startswith("\u2014 witness.example ")
    assert verify_cosignature(line, body, "witness.example", raw) == 1_700_000_000
    with pytest.raises(dsse.SignatureError, match="invalid"):
        verify_cosignature(line, body.replace("3", "4"), "witness.example", raw)
