"""Limits shared by several parts of Countersign are named once, in countersign/limits.py.

The literals they replaced (a second CLOCK_SKEW, reasons of 2000 characters, 8 and 9 MiB,
64 MiB packages) may not come back anywhere else in the package: each use goes by name. The
standalone package verifier (tools/verify_package.py) may not import Countersign, so its copy
of the clock allowance is held equal here instead.
"""

from __future__ import annotations

import re
from pathlib import Path

from countersign import limits
from countersign.settings import Settings

from ..standalone_tool import standalone_verifier

REPO = Path(__file__).resolve().parents[2]
PACKAGE = REPO / "backend" / "countersign"
MIB = r"(?:\*\s*1024\s*\*\s*1024|\*\s*2\s*\*\*\s*20|\*\s*MIB)\b"

# Each limit: what its literal looks like outside limits.py.
LITERALS: dict[str, list[str]] = {
    "CLOCK_SKEW": [r"timedelta\(\s*minutes\s*=\s*5\s*\)", r"\bCLOCK_SKEW\s*=",
                   r"\btimedelta\(\s*seconds\s*=\s*300\s*\)"],
    "MAX_REASON": [r"\bMAX_REASON\s*=", r"reason.*\b2_?000\b", r"max_length\s*=\s*2_?000\b"],
    "MAX_INPUT_BYTES": [rf"\b8\s*{MIB}", r"\b8_?388_?608\b", r"\bMAX_INPUT_BYTES\s*="],
    "MAX_BODY_BYTES": [rf"\b9\s*{MIB}", r"\b9_?437_?184\b"],
    "MAX_PACKAGE_BYTES": [rf"\b64\s*{MIB}", r"\b67_?108_?864\b", r"\bMAX_PACKAGE_BYTES\s*="],
}
# Literals that look like a limit but are another bound, with the reason.
OTHER_BOUNDS = {
    ("web/routes/missions.py", "cursor: Annotated[str | None, Query(max_length=2000)]"):
        "a page cursor's length, not a reason",
    ("web/viser_proxy.py", "size > 64 * 1024 * 1024"):
        "the largest viser message the proxy decodes, not a package",
}


def repeated_literals(root: Path = PACKAGE) -> list[str]:
    found = []
    for path in sorted(root.rglob("*.py")):
        where = str(path.relative_to(root))
        if where == "limits.py":
            continue
        for number, line in enumerate(path.read_text(encoding="utf-8").splitlines(), 1):
            for name, patterns in LITERALS.items():
                if any(re.search(p, line) for p in patterns) and not any(
                        where == place and text in line for place, text in OTHER_BOUNDS):
                    found.append(f"{where}:{number} repeats {name}: {line.strip()}")
    return found


def test_shared_limits_are_used_by_name() -> None:
    assert repeated_literals() == []


def test_the_check_sees_a_repeated_limit(tmp_path: Path) -> None:
    (tmp_path / "store").mkdir()
    (tmp_path / "store" / "a.py").write_text(
        "CLOCK_SKEW = timedelta(minutes=5)\nreason: str = Field(max_length=2000)\n")
    (tmp_path / "b.py").write_text("LIMIT = 9 * 1024 * 1024\nOTHER = 8 * 2**20\n")
    assert repeated_literals(tmp_path) == [
        "b.py:1 repeats MAX_BODY_BYTES: LIMIT = 9 * 1024 * 1024",
        "b.py:2 repeats MAX_INPUT_BYTES: OTHER = 8 * 2**20",
        "store/a.py:1 repeats CLOCK_SKEW: CLOCK_SKEW = timedelta(minutes=5)",
        "store/a.py:2 repeats MAX_REASON: reason: str = Field(max_length=2000)",
    ]


def test_the_values_and_their_users() -> None:
    from countersign.approved_package import build as package
    from countersign.approved_package import verify as package_verify
    from countersign.orders import reader
    from countersign.store.approvals import common as decisions  # check_signed_time

    assert limits.MAX_INPUT_BYTES == 8 * 1024 * 1024
    assert limits.MAX_BODY_BYTES == 9 * 1024 * 1024
    assert limits.MAX_PACKAGE_BYTES == 64 * 1024 * 1024
    assert limits.MAX_REASON == 2000 and limits.CLOCK_SKEW.total_seconds() == 300
    assert Settings(data_dir=Path("."), database_url="sqlite://").max_body_bytes \
        == limits.MAX_BODY_BYTES
    assert reader.MAX_INPUT_BYTES is limits.MAX_INPUT_BYTES
    assert package.MAX_PACKAGE_BYTES is limits.MAX_PACKAGE_BYTES
    assert package_verify.CLOCK_SKEW is decisions.CLOCK_SKEW is limits.CLOCK_SKEW


def test_the_standalone_verifier_allows_the_same_clock_skew() -> None:
    tool = standalone_verifier()
    assert tool.CLOCK_SKEW == limits.CLOCK_SKEW
    assert tool.MAX_BYTES == limits.MAX_PACKAGE_BYTES
