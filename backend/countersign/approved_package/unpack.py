"""Unpacking an approved package on the vehicle: only after it verifies, only into a new
directory, only the files of its canonical layout (`read_tar`), each created below that
directory. Vehicles unpack with this, never with tar: tar tools differ on what a hostile
archive means, the verifier's reading is the one that was checked."""

from __future__ import annotations

import os
from datetime import datetime, timedelta
from pathlib import Path

from .build import read_tar
from .verify import DEFAULT_MAX_AGE, Verdict, verify_package


def unpack_package(data: bytes, target: Path, *, log_key: str, now: datetime | None = None,
                   max_age: timedelta = DEFAULT_MAX_AGE) -> Verdict:
    """Verify, then write the package's files into `target`, which must not exist yet (its
    parent must). Nothing is written when the verdict is a refusal."""
    verdict = verify_package(data, log_key=log_key, now=now, max_age=max_age)
    if not verdict.ok:
        return verdict
    files = read_tar(data)
    target.mkdir(mode=0o755)
    root = target.resolve()
    for name in sorted(files):
        path = (root / name).resolve()
        if not path.is_relative_to(root):
            raise ValueError(f"the package member {name!r} would leave {target}")
        path.parent.mkdir(parents=True, exist_ok=True)
        descriptor = os.open(path, os.O_WRONLY | os.O_CREAT | os.O_EXCL | os.O_NOFOLLOW, 0o644)
        with os.fdopen(descriptor, "wb") as handle:
            handle.write(files[name])
    return verdict
