"""No dead code: vulture reads backend/countersign alone, so a function, method, class,
property, import, variable or attribute that only tests use, or that nothing uses, is reported.
Code that only tests need lives under tests/.

What a library reads is alive where vulture cannot see it. Fields declared in the body of a
pydantic model or settings class, or of a SQLAlchemy table or type (`LIBRARY_BASES`, followed
through the package's own subclasses), are read by their library and are not judged. Every
other name used from outside the Python code vulture reads is in WHITELIST, grouped by who
uses it and why."""

from __future__ import annotations

import ast
from functools import cache
from pathlib import Path

import vulture  # in the dev extras of pyproject.toml

ROOT = Path(__file__).resolve().parents[2] / "backend" / "countersign"
KINDS = {"function", "method", "class", "property", "import", "unreachable_code", "variable",
         "attribute"}
# Decorators whose functions a framework calls (routes, exception handlers, validators).
# viser calls its GUI handlers (`@slider.on_update def _(...)`).
DECORATORS = ["@router.*", "@viewer.*", "@app.*", "@*.exception_handler", "@*.on_click",
              "@*.on_update", "@field_validator", "@model_validator", "@*.listens_for"]
# Classes whose body's names a library reads: pydantic serialises and validates the fields
# (response models are the OpenAPI contract), SQLAlchemy maps the columns and reads a type
# decorator's `impl` and `cache_ok`.
LIBRARY_BASES = {"BaseModel", "BaseSettings", "RootModel", "DeclarativeBase", "TypeDecorator"}

# Who uses each name from outside the Python code vulture reads: {why: {(file, name), ...}},
# files under backend/countersign.
ALLOWED: dict[str, set[tuple[str, str]]] = {
    "SQLAlchemy calls a TypeDecorator's hooks": {
        ("store/tables.py", "process_bind_param"),
        ("store/tables.py", "process_result_value"),
    },
    "pydantic calls __get_pydantic_json_schema__ with the core schema, unused here": {
        ("web/routes/schemas.py", "schema"),
    },
    "gunicorn's BaseApplication calls load_config, and load in each worker": {
        ("web/gunicorn_server.py", "load_config"),
        ("web/gunicorn_server.py", "load"),
    },
    "Python's import system calls a module's __getattr__ (PEP 562 lazy imports)": {
        ("verify/__init__.py", "__getattr__"),
    },
    "scripts/export-openapi writes frontend/src/roles.gen.ts with it": {
        ("web/roles_ts.py", "roles_typescript"),
    },
    "the migrations under migrations/versions make these tables append-only": {
        ("store/tables.py", "APPEND_ONLY_TABLES"),
        ("store/tables.py", "APPEND_ONLY_TABLES_0003"),
        ("store/tables.py", "APPEND_ONLY_TABLES_0004"),
    },
    "a column SQLAlchemy writes to the database": {
        ("store/approvals/keys.py", "revoke_reason"),
    },
    "tarfile writes a member's header from these": {
        ("approved_package/build.py", "mtime"),
        ("approved_package/build.py", "uid"),
        ("approved_package/build.py", "uname"),
        ("approved_package/build.py", "gname"),
    },
    "imcpy serialises the fields set on an IMC message": {
        ("export/imc.py", name) for name in (
            "speed_units", "z_units", "access", "start_man_id", "maneuver_id", "source_man",
            "dest_man", "conditions", "end_z", "start_z", "end_z_units", "start_z_units",
            "bearing", "hstep", "cross_angle", "alternation", "direction")
    },
    "viser reads its handles' attributes; request_share_url keeps viser's signature": {
        ("rehearse/scene.py", "look_at"),
        ("rehearse/scene.py", "wxyz"),
        ("rehearse/scene.py", "request_share_url"),
        ("rehearse/scene.py", "verbose"),
        ("rehearse/team_scene.py", "look_at"),
        ("rehearse/team_scene.py", "wxyz"),
    },
    "sqlite3 reads the connection's isolation_level (no implicit BEGIN)": {
        ("store/db.py", "isolation_level"),
    },
    "anyio reads its thread limiter's total_tokens": {
        ("web/app.py", "total_tokens"),
    },
    "inspect.signature, and so FastAPI's dependency injection, reads __signature__": {
        ("web/deps.py", "__signature__"),
    },
    # The tests and benchmarks observe through these that work is done once, or in the right
    # place, where no output shows it; counting it anywhere else would need the code's insides.
    "counters and last-seen state that tests and benchmarks read": {
        ("verify/logic/cache.py", "misses"),
        ("verify/parts.py", "misses"),
        ("verify/logic/screen.py", "calls"),
        ("verify/logic/session.py", "calls"),
        ("web/validation_pool.py", "last_pid"),
        ("web/app.py", "validation_pool"),
        ("web/viser_proxy.py", "to_server"),
        ("web/viser_proxy.py", "to_browser"),
        ("web/viser_proxy.py", "dropped_share"),
        ("rules/engine.py", "inferences"),
        ("verify/logic/bounds.py", "propagated"),
    },
    # It reads the check's private product, so it stays beside it.
    "tests/bench/bench_team.py prints the size of the joint product the team check explores": {
        ("verify/team.py", "joint_positions"),
    },
}
WHITELIST = {item: why for why, items in ALLOWED.items() for item in items}


def _base_name(node: ast.expr) -> str:
    """`BaseModel` of `BaseModel`, `pydantic.BaseModel` and `RootModel[...]`."""
    if isinstance(node, ast.Subscript):
        return _base_name(node.value)
    if isinstance(node, ast.Attribute):
        return node.attr
    return node.id if isinstance(node, ast.Name) else ""


def _field_lines(body: list[ast.stmt]) -> set[int]:
    return {stmt.lineno for stmt in body if isinstance(stmt, ast.Assign | ast.AnnAssign)}


@cache
def library_fields(root: Path = ROOT) -> frozenset[tuple[str, int]]:
    """(file, line) of every name declared in the body of a class that derives, through
    classes of the package, from one of LIBRARY_BASES."""
    classes: list[tuple[str, str, set[str], set[int]]] = []
    for source in sorted(root.rglob("*.py")):
        path = source.relative_to(root).as_posix()
        for node in ast.walk(ast.parse(source.read_text(), str(source))):
            if isinstance(node, ast.ClassDef):
                classes.append((path, node.name, {_base_name(b) for b in node.bases},
                                _field_lines(node.body)))
    library = set(LIBRARY_BASES)
    grown = True
    while grown:
        before = len(library)
        library |= {name for _, name, bases, _ in classes if bases & library}
        grown = len(library) > before
    return frozenset((path, line) for path, name, bases, lines in classes
                     if bases & library for line in lines)


@cache
def unused(root: Path = ROOT) -> tuple[tuple[str, int, str, str], ...]:
    """(file, line, kind, name) of everything vulture finds unused under `root`."""
    finder = vulture.Vulture(ignore_decorators=DECORATORS)
    finder.scavenge([str(root)])
    return tuple((Path(item.filename).resolve().relative_to(root.resolve()).as_posix(),
                  item.first_lineno, item.typ, item.name)
                 for item in finder.get_unused_code(min_confidence=60))


def dead_code(root: Path = ROOT) -> list[str]:
    fields = library_fields(root)
    return [f"{path}:{line}: unused {kind} {name!r}" for path, line, kind, name in unused(root)
            if kind in KINDS and (path, name) not in WHITELIST
            and not (kind == "variable" and (path, line) in fields)]


def test_no_dead_code() -> None:
    assert dead_code() == [], "remove it, or move what only tests use under tests/"


def test_the_whitelist_names_only_what_exists() -> None:
    """A whitelisted name that is gone (or now used from Python) leaves the list."""
    assert set(WHITELIST) - {(path, name) for path, _, _, name in unused(ROOT)} == set()


def test_the_check_sees_a_dead_function(tmp_path: Path) -> None:
    package = tmp_path / "countersign"
    package.mkdir()
    (package / "__init__.py").write_text("from .used import used\n\n__all__ = ['used']\n")
    (package / "used.py").write_text(
        "import os\n\n\ndef used() -> int:\n    return 1\n\n\ndef dead() -> int:\n"
        "    return used()\n\n\n@router.get('/x')\ndef route() -> None:\n    pass\n")
    assert dead_code(package) == ["used.py:1: unused import 'os'",
                                  "used.py:8: unused function 'dead'"]


def test_the_check_sees_a_dead_field_but_not_a_models(tmp_path: Path) -> None:
    package = tmp_path / "countersign"
    package.mkdir()
    (package / "__init__.py").write_text("from .parts import Part, Out\n\n"
                                         "__all__ = ['Part', 'Out']\n")
    (package / "parts.py").write_text(
        "from dataclasses import dataclass\n\nfrom pydantic import BaseModel\n\n\n"
        "class Shared(BaseModel):\n    kept: int\n\n\n"
        "class Out(Shared):\n    shown: int\n\n\n"
        "@dataclass\nclass Part:\n    name: str\n    forgotten: int = 0\n\n\n"
        "def name(part: Part) -> str:\n    return part.name\n\n\n__all__ = ['name']\n")
    assert dead_code(package) == ["parts.py:17: unused variable 'forgotten'"]
