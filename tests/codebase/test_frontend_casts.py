"""The front end's types come from the OpenAPI document, so no production module
casts an answer through `unknown` (test files may build odd values on purpose)."""

from __future__ import annotations

from pathlib import Path

SOURCES = Path(__file__).resolve().parents[2] / "frontend" / "src"


def test_no_production_module_casts_through_unknown() -> None:
    found = []
    for path in sorted(SOURCES.rglob("*.ts*")):
        if ".test." in path.name or path.name.endswith(".d.ts"):
            continue
        for number, line in enumerate(path.read_text(encoding="utf-8").splitlines(), 1):
            if "as unknown as" in line:
                found.append(f"{path.relative_to(SOURCES)}:{number}")
    assert found == [], found
