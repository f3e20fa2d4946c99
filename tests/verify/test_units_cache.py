"""pint's parsed definitions are cached on disk (verify/units.py): a second process reads the
cache instead of parsing, and a cache another process left half-written, or a folder that
cannot be written, never stops the TEXT check."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

READ_KNOT = (
    "from countersign.verify import units\n"
    "print(units.convert(2.0, units.parse_unit('knots'), units.parse_unit('m/s')))\n"
)


def _run(cache_home: Path) -> str:
    env = {**os.environ, "XDG_CACHE_HOME": str(cache_home)}
    done = subprocess.run([sys.executable, "-c", READ_KNOT], env=env, capture_output=True,
                          text=True, timeout=300, check=True)
    return done.stdout.strip()


def _pickles(cache_home: Path) -> list[Path]:
    return sorted((cache_home / "countersign" / "pint").glob("*.pickle"))


def test_the_parsed_definitions_are_cached_and_reused(tmp_path: Path) -> None:
    assert _run(tmp_path).startswith("1.0288")
    written = _pickles(tmp_path)
    assert written, "pint wrote no cache"
    stamps = [p.stat().st_mtime_ns for p in written]
    assert _run(tmp_path).startswith("1.0288")
    assert [p.stat().st_mtime_ns for p in _pickles(tmp_path)] == stamps  # read, not rewritten


def test_a_half_written_cache_falls_back_to_parsing(tmp_path: Path) -> None:
    _run(tmp_path)
    for pickle_file in _pickles(tmp_path):
        pickle_file.write_bytes(pickle_file.read_bytes()[:100])
    assert _run(tmp_path).startswith("1.0288")


def test_a_cache_folder_that_cannot_be_made_falls_back_to_parsing(tmp_path: Path) -> None:
    blocked = tmp_path / "file-not-folder"
    blocked.write_text("")
    assert _run(blocked).startswith("1.0288")
