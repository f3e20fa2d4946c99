"""The checker fingerprint: which checking code and ontology made a validation report.

A stored report is keyed by it and carries it, and an approval statement names it, so that an
upgrade that changes a check makes every older report stale at once (DESIGN.md, Approval record)
without anyone keeping a version number by hand.

What it covers - everything that decides what a report says:
- every file of the packages `countersign.orders` (the reader, canonical digest and defaults the
  checks see), `countersign.rules` (the contingency rules and their data) and
  `countersign.verify` (the checks), Python sources and data files alike, except compiled
  bytecode (`*.pyc`, `*.pyo`, in `__pycache__`), which follows from the sources;
- `countersign/ontology_files.py`, which loads the ontology;
- every `*.ttl` file of the ontology folder in use (`ontology_files.ontology_dir()`).

The value is `sha256:` and the SHA-256 of, for each file in the order of its name
(`countersign/...` for package files, `ontology/...` for ontology files): the name's UTF-8
bytes, a NUL byte, the content's length as 8 big-endian bytes and the content. It is computed
once per process, on first use (a few milliseconds) - the web app asks for it when it starts,
so it describes the code the process loaded rather than files replaced under it later.
"""

from __future__ import annotations

import hashlib
from collections.abc import Iterator
from functools import cache
from pathlib import Path

from ..ontology_files import ontology_dir

PACKAGES = ("orders", "rules", "verify")
MODULES = ("ontology_files.py",)
ONTOLOGY_PATTERN = "*.ttl"
_BYTECODE = {".pyc", ".pyo"}


def _package_root() -> Path:
    return Path(__file__).resolve().parents[1]


def checked_files(package_root: Path | None = None,
                  ontology: Path | None = None) -> Iterator[tuple[str, Path]]:
    """(name, path) of every file the fingerprint covers, sorted by name."""
    root = package_root if package_root is not None else _package_root()
    folder = ontology if ontology is not None else ontology_dir()
    found: list[tuple[str, Path]] = []
    for package in PACKAGES:
        for path in (root / package).rglob("*"):
            if path.is_file() and path.suffix not in _BYTECODE:
                found.append((f"countersign/{path.relative_to(root).as_posix()}", path))
    found.extend((f"countersign/{name}", root / name) for name in MODULES)
    found.extend((f"ontology/{path.name}", path) for path in folder.glob(ONTOLOGY_PATTERN)
                 if path.is_file())
    return iter(sorted(found))


def compute_fingerprint(package_root: Path | None = None, ontology: Path | None = None) -> str:
    """The fingerprint of the files as they are on disk now."""
    digest = hashlib.sha256()
    for name, path in checked_files(package_root, ontology):
        content = path.read_bytes()
        digest.update(name.encode())
        digest.update(b"\0")
        digest.update(len(content).to_bytes(8, "big"))
        digest.update(content)
    return "sha256:" + digest.hexdigest()


@cache
def checker_fingerprint() -> str:
    """The fingerprint of the checks this process runs (computed once, then cached)."""
    return compute_fingerprint()
