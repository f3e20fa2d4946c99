"""Edge crossings of the editor's auto layout (ELK layered) against the linear layered layout,
for the exemplar, a generated 100-goal mission and Pirates (NPS AVCL, read by our reader):
writes Pirates as JSON orders to a temporary file and runs frontend/src/editor/crossings.test.ts
with COUNTERSIGN_LAYOUT_ORDERS naming it, which prints the counts.

    .venv/bin/python -m tests.bench.bench_layout_crossings
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
import tempfile
from pathlib import Path

from countersign.orders.reader import read_file

REPO = Path(__file__).resolve().parents[2]


def _pirates() -> Path | None:
    for root in REPO.parents:
        path = (root / "shared" / "reference" / "nps-ethical-control" / "missions" / "avcl"
                / "PiratesSeizingMerchantDefense.xml")
        if path.is_file():
            return path
    return None


def main() -> int:
    pirates = _pirates()
    with tempfile.TemporaryDirectory() as folder:
        names = []
        if pirates is not None:
            orders = read_file(pirates).orders.model_dump(mode="json", exclude_none=True)
            target = Path(folder) / "pirates.json"
            target.write_text(json.dumps(orders))
            names.append(str(target))
        env = {**os.environ, "COUNTERSIGN_LAYOUT_ORDERS": ":".join(names)}
        done = subprocess.run(["npx", "vitest", "run", "src/editor/crossings.test.ts"],
                              cwd=REPO / "frontend", env=env, check=False)
        return done.returncode


if __name__ == "__main__":
    sys.exit(main())
