"""No dead functions: vulture reads backend/countersign alone, so a function, method,
class, property or import that only tests use, or that nothing uses, is reported. Code that
only tests need lives under tests/.

Not judged here: variables and attributes. Pydantic and SQLAlchemy fields, dataclass fields
filled for JSON, and attributes set on library objects (tar headers, IMC messages, viser
handles) are read by the libraries, where vulture cannot see it.

WHITELIST names what is used from outside the Python code vulture reads, each with its user."""

from __future__ import annotations

from functools import cache
from pathlib import Path

import vulture  # in the dev extras of pyproject.toml

ROOT = Path(__file__).resolve().parents[2] / "backend" / "countersign"
KINDS = {"function", "method", "class", "property", "import", "unreachable_code"}
# Decorators whose functions a framework calls (routes, exception handlers, validators).
# viser calls its GUI handlers (`@slider.on_update def _(...)`).
DECORATORS = ["@router.*", "@viewer.*", "@app.*", "@*.exception_handler", "@*.on_click",
              "@*.on_update", "@field_validator", "@model_validator", "@*.listens_for"]
# (file under backend/countersign, name): who uses it.
WHITELIST: dict[tuple[str, str], str] = {
    # SQLAlchemy calls a TypeDecorator's hooks.
    ("store/tables.py", "process_bind_param"): "SQLAlchemy",
    ("store/tables.py", "process_result_value"): "SQLAlchemy",
    # gunicorn's BaseApplication calls load_config; the workers import the factory by name.
    ("web/gunicorn_server.py", "load_config"): "gunicorn",
    # PEP 562 module attribute hook (lazy imports).
    ("verify/__init__.py", "__getattr__"): "Python's import system",
    # Read by scripts/export-openapi to write frontend/src/roles.gen.ts.
    ("web/roles_ts.py", "roles_typescript"): "scripts/export-openapi",
    # The examples' public reader; tests and benchmarks read examples as Orders with it.
    # The size of the joint product the team check explores, printed by tests/bench/bench_team.py;
    # it reads the check's private product, so it stays beside it.
    ("verify/team.py", "joint_positions"): "tests/bench/bench_team.py",
}


@cache
def unused(root: Path = ROOT) -> tuple[tuple[str, int, str, str], ...]:
    """(file, line, kind, name) of everything vulture finds unused under `root`."""
    finder = vulture.Vulture(ignore_decorators=DECORATORS)
    finder.scavenge([str(root)])
    return tuple((Path(item.filename).resolve().relative_to(root.resolve()).as_posix(),
                  item.first_lineno, item.typ, item.name)
                 for item in finder.get_unused_code(min_confidence=60))


def dead_code(root: Path = ROOT) -> list[str]:
    return [f"{path}:{line}: unused {kind} {name!r}" for path, line, kind, name in unused(root)
            if kind in KINDS and (path, name) not in WHITELIST]


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
