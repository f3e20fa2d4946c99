"""Signed approvals: in-toto statements in DSSE envelopes, Ed25519 keys, the hash-chained
transparency log with RFC 6962 Merkle proofs and signed checkpoints, and offline bundle
verification. Pure functions: nothing here touches a database or the network."""
