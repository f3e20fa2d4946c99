"""Test vectors for the browser's signing and verification code (frontend/src/crypto), computed
by the Python implementation the server and `countersign audit verify` use.

The vectors live in frontend/src/crypto/__fixtures__/vectors.json, which the Vitest tests read;
this test recomputes them and fails when the file differs, so the two implementations cannot
drift apart. Regenerate with
`COUNTERSIGN_UPDATE_VECTORS=1 pytest tests/approvals/test_browser_vectors.py`.
"""

from __future__ import annotations

import json
import os
from pathlib import Path
from typing import Any

from cryptography.hazmat.primitives.asymmetric.ed25519 import Ed25519PrivateKey

from countersign.approvals import dsse
from countersign.approvals.log import GENESIS, entry_bytes, sign_checkpoint
from countersign.approvals.merkle import Tree, leaf_hash
from countersign.approvals.statement import json_digest
from countersign.orders.examples import example_bytes

FIXTURE = (Path(__file__).resolve().parents[2] / "frontend" / "src" / "crypto" / "__fixtures__"
           / "vectors.json")
LEAVES = 7


def _key(seed: int) -> Ed25519PrivateKey:
    # A fixed test key (never used outside these vectors): 32 bytes derived from `seed`.
    return Ed25519PrivateKey.from_private_bytes(bytes((seed + i) % 256 for i in range(32)))


def vectors() -> dict[str, Any]:
    pae = [{"payloadType": t, "payload": dsse.b64(p), "pae": dsse.b64(dsse.pae(t, p))}
           for t, p in ((dsse.PAYLOAD_TYPE, b'{"a":1}'), ("text/plain", "ünïcode ✓".encode()),
                        (dsse.PAYLOAD_TYPE, b""))]
    # A hash-chained log of LEAVES entries, as the server writes it.
    entries, prev = [], GENESIS
    for index in range(LEAVES):
        text = entry_bytes(index, prev, {"id": index + 1, "kind": "test", "detail": {"n": index}})
        entries.append(text.decode())
        prev = leaf_hash(text).hex()
    tree = Tree(leaf_hash(e.encode()) for e in entries)
    merkle = {
        "entries": entries,
        "leaves": [leaf.hex() for leaf in tree.levels[0]],
        "roots": {str(size): tree.root(size).hex() for size in range(1, LEAVES + 1)},
        "proofs": [{"index": index, "size": size,
                    "hashes": [h.hex() for h in tree.inclusion_proof(index, size)]}
                   for size in range(1, LEAVES + 1) for index in range(size)],
    }
    signer = _key(7)
    payload = b'{"_type":"https://in-toto.io/Statement/v1"}'
    envelope = dsse.sign_envelope(payload, signer)
    checkpoint = sign_checkpoint(_key(42), LEAVES, tree.root())
    orders = json.loads(example_bytes("search-and-sample"))
    tricky = {"b": [1.5, 1e21, 1e-7, 100.0, -3], "a": {"é": "x\u2028\"\\", "A": None},
              "\u20ac": True, "\U0001f600": False, "aa": "tab\there"}
    return {
        "pae": pae,
        "merkle": merkle,
        "envelope": {"public_key": dsse.public_text(signer), "key_id": dsse.key_id(
            signer.public_key()), "text": json.dumps(envelope)},
        "checkpoint": checkpoint,
        "canonical": [{"value": orders, "digest": json_digest(orders)},
                      {"value": tricky, "digest": json_digest(tricky)}],
    }


def test_browser_vectors_match_the_python_implementation() -> None:
    wanted = json.dumps(vectors(), indent=1, ensure_ascii=False) + "\n"
    if os.environ.get("COUNTERSIGN_UPDATE_VECTORS") == "1":
        FIXTURE.write_text(wanted, encoding="utf-8")
    assert FIXTURE.read_text(encoding="utf-8") == wanted, (
        "frontend/src/crypto/__fixtures__/vectors.json is out of date: regenerate it with "
        "COUNTERSIGN_UPDATE_VECTORS=1 pytest tests/approvals/test_browser_vectors.py")
