"""Pure parts of approvals/: DSSE, Merkle proofs against a reference implementation, and bundle
verification of forks (no database)."""

from __future__ import annotations

import hashlib
import json
from datetime import UTC, datetime
from typing import Any

import pytest
from hypothesis import given
from hypothesis import strategies as st

from countersign.approvals import dsse
from countersign.approvals.bundle import BUNDLE_FORMAT, verify_bundle
from countersign.approvals.log import GENESIS, entry_bytes, entry_leaf, event_data, sign_checkpoint
from countersign.approvals.merkle import (
    EMPTY_ROOT,
    Tree,
    leaf_hash,
    node_hash,
    root_of,
    verify_consistency,
    verify_inclusion,
)
from countersign.approvals.receipt import make_receipt


def _reference_root(leaves: list[bytes]) -> bytes:
    """RFC 6962 section 2.1 MTH, literally."""
    if not leaves:
        return hashlib.sha256(b"").digest()
    if len(leaves) == 1:
        return leaves[0]
    k = 1
    while k * 2 < len(leaves):
        k *= 2
    return node_hash(_reference_root(leaves[:k]), _reference_root(leaves[k:]))


def test_rfc6962_known_root() -> None:
    # The empty tree and a single leaf as in RFC 6962 / certificate-transparency-go tests.
    assert EMPTY_ROOT.hex() == "e3b0c44298fc1c149afbf4c8996fb92427ae41e4649b934ca495991b7852b855"
    assert leaf_hash(b"").hex() == \
        "6e340b9cffb37a989ca544e6bb780a2c78901d3fb33738768511a30617afa01d"


@given(st.integers(min_value=1, max_value=70), st.data())
def test_proofs_match_the_reference(size: int, data: st.DataObject) -> None:
    leaves = [leaf_hash(i.to_bytes(4, "big")) for i in range(size)]
    tree = Tree(leaves)
    assert tree.root() == _reference_root(leaves) == root_of(leaves)
    index = data.draw(st.integers(0, size - 1))
    proof = tree.inclusion_proof(index)
    assert verify_inclusion(leaves[index], index, size, proof, tree.root())
    assert not verify_inclusion(leaf_hash(b"other"), index, size, proof, tree.root())
    if proof:
        assert not verify_inclusion(leaves[index], index, size, proof[:-1], tree.root())
    first = data.draw(st.integers(1, size))
    consistency = tree.consistency_proof(first)
    assert verify_consistency(first, size, consistency, tree.root(first), tree.root())
    assert not verify_consistency(first, size, consistency, leaf_hash(b"x"), tree.root())


def test_dsse_pae_matches_the_spec_example() -> None:
    # DSSE protocol.md: PAE("http://example.com/HelloWorld", "hello world")
    assert dsse.pae("http://example.com/HelloWorld", b"hello world") == \
        b"DSSEv1 29 http://example.com/HelloWorld 11 hello world"


def test_envelopes_verify_only_under_their_key() -> None:
    key, other = dsse.generate_key(), dsse.generate_key()
    envelope = dsse.sign_envelope(b'{"a":1}', key)
    assert dsse.verify_envelope(envelope, key.public_key()) == b'{"a":1}'
    with pytest.raises(dsse.SignatureError, match="does not verify"):
        dsse.verify_envelope(envelope, other.public_key())
    assert dsse.envelope_key_id(envelope) == dsse.key_id(dsse.public_text(key))


def _log(kinds: list[str]) -> list[str]:
    texts, prev = [], GENESIS
    for index, kind in enumerate(kinds):
        data = entry_bytes(index, prev, event_data(
            id=index + 1, at=datetime(2026, 1, 1, tzinfo=UTC), actor="a", kind=kind,
            mission="m", before=None, after=None, detail={"n": index}))
        texts.append(data.decode())
        prev = entry_leaf(data)
    return texts


def _bundle(texts: list[str], log_key: Any) -> dict[str, Any]:
    leaves = [leaf_hash(t.encode()) for t in texts]
    checkpoint = sign_checkpoint(log_key, len(texts), Tree(leaves).root())
    receipts = [make_receipt(log_key, checkpoint["origin"], i, leaf.hex(), "2026-01-01T00:00:00Z")
                for i, leaf in enumerate(leaves)]
    return {"format": BUNDLE_FORMAT, "log_key": {"public_key": checkpoint["public_key"]},
            "entries": texts, "checkpoints": [checkpoint], "receipts": receipts, "keys": [],
            "orders": {}, "approvals": []}


def test_a_log_that_forks_from_a_published_checkpoint_fails() -> None:
    log_key = dsse.generate_key()
    honest = _log(["a", "b", "c", "d", "e"])
    published = _bundle(honest, log_key)["checkpoints"][0]
    # Later the server rewrites entry 2 and re-signs a consistent-looking longer log.
    forked = _log(["a", "b", "X", "d", "e", "f"])
    bundle = _bundle(forked, log_key)
    alone = verify_bundle(bundle, trusted_log_key=dsse.public_text(log_key))
    assert alone.ok, alone.problems  # self-consistent on its own...
    report = verify_bundle(bundle, trusted_log_key=dsse.public_text(log_key),
                           published=[published])
    assert len(report.problems) == 1, report.problems
    assert report.problems[0].startswith(
        f"the log forks from the checkpoint seen before (size 5, root {published['root']}); "
        f"the log now has size 6, root {bundle['checkpoints'][0]['root']}")
    extended = verify_bundle(_bundle(_log(["a", "b", "c", "d", "e", "f"]), log_key),
                             published=[published])
    assert extended.ok, extended.problems
    shorter = verify_bundle(_bundle(honest[:3], log_key), published=[published])
    assert any("rolled back (truncated)" in p for p in shorter.problems)


def test_checkpoints_signed_by_another_key_fail() -> None:
    texts = _log(["a", "b"])
    bundle = _bundle(texts, dsse.generate_key())
    report = verify_bundle(bundle, trusted_log_key=dsse.public_text(dsse.generate_key()))
    assert "the bundle's log key is not the pinned log key" in report.problems
    assert any("not signed by the log key" in p for p in report.problems)


def test_not_a_bundle() -> None:
    assert not verify_bundle(json.loads('{"format": "x"}')).ok


@given(st.recursive(
    st.none() | st.booleans() | st.integers(-10**12, 10**12)
    | st.floats(allow_nan=False, allow_infinity=False) | st.text(max_size=8),
    lambda children: st.lists(children, max_size=4)
    | st.dictionaries(st.text(max_size=6), children, max_size=4), max_leaves=20))
def test_fast_orders_digest_agrees_with_rfc8785(value: Any) -> None:
    from countersign.approvals.bundle import orders_match
    from countersign.approvals.statement import json_digest as orders_digest

    try:
        signed = orders_digest(value)
    except Exception:  # rfc8785 refuses some values (e.g. lone surrogates)
        return
    assert orders_match(value, signed)
    assert not orders_match(value, "sha256:" + "0" * 64)
