"""Dependencies point inward (DESIGN.md, Layout): read every import under backend/countersign and
check no package reaches outward. Leaf modules that import nothing of ours (strict_json,
ontology_files, the package's __version__) may be used by any layer."""

from __future__ import annotations

import ast
from collections.abc import Iterator
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2] / "backend" / "countersign"

LEAVES = {"", "strict_json", "ontology_files", "pool_lifetime"}
# What each inner package may import besides itself and the leaves.
ALLOWED: dict[str, set[str]] = {
    "orders": set(),
    "rules": {"orders"},
    "verify": {"orders", "rules"},
    "rehearse": {"orders", "rules", "verify"},
    # Campaigns run the rehearsal simulation headless; their jobs (countersign.jobs) store.
    "campaigns": {"orders", "rules", "verify", "rehearse", "errors"},
    "plan": {"orders", "rules", "verify"},
    # An approved package holds approvals' envelope, receipt and proofs, and its verifier
    # checks them; approvals never imports export (checked below through this table).
    "export": {"orders", "rules", "verify", "approvals"},
    "approvals": {"orders", "rules", "verify"},
}
# Packages the store may not import: validation goes through verify, never rehearse; the
# domain services (countersign.services) are built on the store.
STORE_FORBIDDEN = {"rehearse", "web", "cli", "services"}
# The domain services sit between the store and the routes: they never import HTTP or the CLI.
SERVICES_FORBIDDEN = {"web", "cli"}


def _imports(path: Path, root: Path) -> Iterator[tuple[str, int]]:
    """(absolute module, line) of each import in one file."""
    parts = list(path.relative_to(root.parent).with_suffix("").parts)
    package = parts[:-1]
    for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
        if isinstance(node, ast.ImportFrom):
            if node.level:
                base = package[: len(package) - (node.level - 1)]
                name = ".".join([*base, *([node.module] if node.module else [])])
                # `from .. import strict_json` names modules in the imported names.
                if node.module is None:
                    for alias in node.names:
                        yield f"{name}.{alias.name}", node.lineno
                    continue
            else:
                name = node.module or ""
            yield name, node.lineno
        elif isinstance(node, ast.Import):
            for alias in node.names:
                yield alias.name, node.lineno


def _layer(module: str) -> str:
    pieces = module.split(".")
    return pieces[1] if len(pieces) > 1 else ""


def violations(root: Path = ROOT) -> list[str]:
    found = []
    for path in sorted(root.rglob("*.py")):
        source = _layer(".".join(path.relative_to(root.parent).with_suffix("").parts))
        for module, line in _imports(path, root):
            if module.split(".")[0] != "countersign":
                continue
            target = _layer(module)
            if target in (source, *LEAVES):
                continue
            where = f"{path.relative_to(root.parent)}:{line} imports {module}"
            outward = source in ALLOWED and target not in ALLOWED[source]
            if (outward or (source == "store" and target in STORE_FORBIDDEN)
                    or (source == "services" and target in SERVICES_FORBIDDEN)):
                found.append(where)
    return found


def test_dependencies_point_inward() -> None:
    assert violations() == []


def test_the_check_sees_an_outward_import(tmp_path: Path) -> None:
    package = tmp_path / "countersign"
    (package / "orders").mkdir(parents=True)
    (package / "orders" / "bad.py").write_text("from ..verify.report import validate\n")
    (package / "store").mkdir()
    (package / "store" / "bad.py").write_text("from countersign.rehearse import sim\n")
    assert violations(package) == [
        "countersign/orders/bad.py:1 imports countersign.verify.report",
        "countersign/store/bad.py:1 imports countersign.rehearse",
    ]


@pytest.mark.parametrize("module", ["countersign.rules", "countersign.orders"])
def test_inner_packages_are_listed(module: str) -> None:
    assert _layer(module) in ALLOWED
