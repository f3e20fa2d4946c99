"""Every collected test has an id of its own (tests/node_ids.py): pytest-xdist hands out tests
by id, and items sharing one ran as one (the API fuzz's 184 operations as two tests)."""

from __future__ import annotations

import subprocess
import sys
from collections import Counter
from pathlib import Path

REPO = Path(__file__).resolve().parents[2]


def _collected(*args: str) -> list[str]:
    run = subprocess.run(
        [sys.executable, "-m", "pytest", "--collect-only", "-q", "-p", "no:cacheprovider",
         "-p", "no:xdist", *args], cwd=REPO, capture_output=True, text=True, timeout=600)
    assert run.returncode == 0, run.stdout[-2000:] + run.stderr[-2000:]
    return [line for line in run.stdout.splitlines() if "::" in line]


def test_each_fuzzed_operation_is_a_test_of_its_own() -> None:
    ids = _collected("tests/web/test_fuzz.py")
    shared = {node: n for node, n in Counter(ids).items() if n > 1}
    assert not shared, shared
    # One test per operation and sweep, named by the operation (as the report names them).
    assert sum("[GET /api/health]" in node for node in ids) == 2, ids[:5]
    assert len(ids) > 100
