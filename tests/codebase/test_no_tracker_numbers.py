"""The code does not carry the tracker: no "issue 37" in a comment, docstring or string of the
backend, its migrations and project file, the front end's source, the tests or the scripts, nor
one broken over two lines of a comment. What a comment says must stand on its
own (why the code is so), not send the reader to a tracker the repository does not hold."""

from __future__ import annotations

import re
from pathlib import Path

REPO = Path(__file__).resolve().parents[2]
FOLDERS = ("backend/countersign", "frontend/src", "tests", "scripts", ".ci", "migrations")
FILES = ("pyproject.toml",)
SUFFIXES = {".py", ".ts", ".tsx", ".css", ".sh", ""}
# Generated files, and this test (whose examples are tracker numbers).
LEFT_OUT = {"schema.d.ts", Path(__file__).name}
# The number may start the next line of the comment ("(issue" / "# 15: ...").
TRACKER = re.compile(r"\b[Ii]ssues?(?: |\n[ \t]*(?:#|//|\*)?[ \t]*)?#?\d+")


def _sources() -> list[Path]:
    found = [REPO / name for name in FILES]
    for folder in FOLDERS:
        for path in (REPO / folder).rglob("*"):
            if (path.is_file() and path.suffix in SUFFIXES and path.name not in LEFT_OUT
                    and "node_modules" not in path.parts and "__pycache__" not in path.parts):
                found.append(path)
    return found


def test_no_tracker_numbers_in_the_code() -> None:
    found = []
    for path in _sources():
        try:
            text = path.read_text(encoding="utf-8")
        except UnicodeDecodeError:
            continue
        for match in TRACKER.finditer(text):
            number = text.count("\n", 0, match.start()) + 1
            line = text.splitlines()[number - 1]
            found.append(f"{path.relative_to(REPO)}:{number}: {line.strip()[:100]}")
    assert not found, "tracker numbers in the code:\n" + "\n".join(found)


def test_the_check_sees_a_tracker_number() -> None:
    assert TRACKER.search("# the 8 MiB cap (issue 15)")
    assert TRACKER.search("/** Issue 37 in the editor */")
    assert not TRACKER.search("# an issued certificate, 37 of them")
    assert TRACKER.search("# the solver budget (issue\n# 15: 76 s)")
    assert TRACKER.search(" * the band layout. Issue\n * 32 measured it")
    assert not TRACKER.search("# one issue\nLIMIT = 15")
