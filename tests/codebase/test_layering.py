"""Dependencies point inward (DESIGN.md, Layout): read every import under backend/countersign and
check that each package imports only packages of inner rings.

DESIGN.md's order: `orders` imports nothing of ours; `rules` imports `orders`; `verify` imports
`orders` and `rules`; `rehearse`, `plan`, `export` and `approvals` import those (and not one
another); `store`, `web` and `cli` are the outer ring. Packages DESIGN.md does not list sit
where their imports put them (README, Development): `campaigns` (many seeded rehearsals) and
`approved_package` (vehicle files from `export` beside the evidence from `approvals`) each join
packages of the ring below, so they sit right above it; `jobs` runs campaigns and stores their
results, so it sits between `store` and `web`; so do the domain services (`services`), which
the routes call and which read the store. Inside the outer ring the web app reads the
store, and the command line starts the web app (only `serve`, in cli/server.py, reaches into
`web`).

Leaves (the top-level modules such as strict_json, errors, limits, settings, ontology_files, and
the package's `__init__` with its __version__) import nothing of ours but other leaves, so any
layer may use them."""

from __future__ import annotations

import ast
from collections.abc import Iterator
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2] / "backend" / "countersign"

# Inner to outer: a package may import its own modules, leaves and packages of inner rings.
RINGS: list[set[str]] = [
    {"orders"},
    {"rules"},
    {"verify"},
    {"rehearse", "plan", "export", "approvals"},
    {"campaigns", "approved_package"},
    # The outer ring, in its own order.
    {"store"},
    {"services"},
    {"jobs"},
    {"web"},
    {"cli"},
]
RING = {package: index for index, ring in enumerate(RINGS) for package in ring}
# Top-level modules that import nothing of ours; "" is countersign/__init__.py (and
# `from countersign import __version__`).
LEAVES = {"", "__version__", "errors", "strict_json", "ontology_files", "pool_lifetime",
          "limits", "settings", "map_tiles"}
# The store validates through verify; it never runs simulations.
STORE_FORBIDDEN = {"rehearse", "campaigns"}
# The only CLI module that may import the web app: `countersign serve` starts it.
CLI_SERVES_WEB = {"cli/server.py"}
# Known breaks waiting for their fix, as (file, imported module); none today. Delete an entry
# when its import is gone: a stale one would hide the same import written again.
PENDING: set[tuple[str, str]] = set()


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
                if name == "countersign":
                    for alias in node.names:
                        yield f"{name}.{alias.name}", node.lineno
                    continue
            yield name, node.lineno
        elif isinstance(node, ast.Import):
            for alias in node.names:
                yield alias.name, node.lineno


def _layer(module: str) -> str:
    pieces = module.split(".")
    return pieces[1] if len(pieces) > 1 else ""


def _allowed(source: str, target: str, where: str) -> bool:
    if target == source:
        return True
    if source in LEAVES:
        # A leaf imports nothing of ours but other leaves (settings reads limits); cycles
        # among them are test_code_shape's.
        return target in LEAVES
    if target in LEAVES:
        return True
    if source not in RING or target not in RING:
        return False  # a package with no place in the order (see unplaced())
    if source == "store" and target in STORE_FORBIDDEN:
        return False
    if source == "cli" and target == "web":
        return where in CLI_SERVES_WEB
    return RING[target] < RING[source]


def violations(root: Path = ROOT, pending: set[tuple[str, str]] = PENDING) -> list[str]:
    found = []
    for path in sorted(root.rglob("*.py")):
        relative = path.relative_to(root).as_posix()
        source = _layer(".".join(path.relative_to(root.parent).with_suffix("").parts))
        if source == "__init__":
            source = ""
        for module, line in _imports(path, root):
            if module.split(".")[0] != "countersign":
                continue
            target = _layer(module)
            if _allowed(source, target, relative) or (relative, module) in pending:
                continue
            found.append(f"countersign/{relative}:{line} imports {module}")
    return found


def unplaced(root: Path = ROOT) -> list[str]:
    """Packages and top-level modules that are neither in a ring nor a leaf."""
    names = {p.name for p in root.iterdir() if p.is_dir() and (p / "__init__.py").exists()}
    names |= {p.stem for p in root.glob("*.py") if p.stem != "__init__"}
    return sorted(names - set(RING) - LEAVES)


def test_dependencies_point_inward() -> None:
    assert violations() == []


def test_every_package_has_a_place_in_the_order() -> None:
    assert unplaced() == []


def _write(package: Path, name: str, text: str) -> None:
    path = package / name
    path.parent.mkdir(parents=True, exist_ok=True)
    (path.parent / "__init__.py").touch()
    path.write_text(text)


def test_the_check_sees_an_outward_import(tmp_path: Path) -> None:
    package = tmp_path / "countersign"
    _write(package, "orders/bad.py", "from ..verify.report import validate\n")
    _write(package, "store/bad.py", "from countersign.rehearse import sim\n")
    _write(package, "export/bad.py", "from ..approvals.dsse import parse_envelope\n")
    _write(package, "campaigns/bad.py", "from ..store import db\n")
    _write(package, "jobs/bad.py", "from ..web import app\n")
    _write(package, "cli/bad.py", "from ..web.settings import Settings\n")
    _write(package, "strict_json.py", "from .orders import model\n")
    _write(package, "rules/ok.py", "from ..orders import model\nfrom .. import strict_json\n")
    _write(package, "cli/server.py", "from ..web.app import create_app\n")
    assert violations(package, pending=set()) == [
        "countersign/campaigns/bad.py:1 imports countersign.store",
        "countersign/cli/bad.py:1 imports countersign.web.settings",
        "countersign/export/bad.py:1 imports countersign.approvals.dsse",
        "countersign/jobs/bad.py:1 imports countersign.web",
        "countersign/orders/bad.py:1 imports countersign.verify.report",
        "countersign/store/bad.py:1 imports countersign.rehearse",
        "countersign/strict_json.py:1 imports countersign.orders",
    ]


def test_the_check_sees_an_unplaced_package(tmp_path: Path) -> None:
    package = tmp_path / "countersign"
    _write(package, "orders/model.py", "")
    _write(package, "newthing/x.py", "")
    (package / "helpers.py").write_text("")
    assert unplaced(package) == ["helpers", "newthing"]


@pytest.mark.parametrize("module", ["countersign.rules", "countersign.orders",
                                    "countersign.approved_package.build"])
def test_inner_packages_are_listed(module: str) -> None:
    assert _layer(module) in RING
