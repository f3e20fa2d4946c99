"""The app's services are given, not looked up: routes get one AppServices object through a
FastAPI dependency (web/deps.py, `Services`) and pass what a domain service needs as keyword
arguments (`reports=`, `signer=`). Three rules, read from the source with `ast`:

1. No module but store/db.py (which opens sessions and records their database) reads a
   service out of a session's `info` (`info["database"]`, `info.get("log_signer")`, ...).
2. Routes and domain services (web/, services/) never reach a service through a session or
   the database object (`database_of(db).reports`, `app.state.database.log_signer`): only
   the app factory's wiring may.
3. Inside the store, nothing reads a service off the database object, and the one accessor
   that still finds one through a session (store/db.py: the log's tree cache) is used only
   where it is used today; a new use must take the service as an argument instead. The log
   signer is always an argument (`record(..., signer=)`, `decision_refusal_from_log`)."""

from __future__ import annotations

import ast
from collections.abc import Iterator
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2] / "backend" / "countersign"

SERVICE_KEYS = {"database", "write", "reports", "log_signer", "signer", "log_tree_cache",
                "log_trees", "settings", "services"}
SERVICE_ATTRIBUTES = {"reports", "log_signer", "log_tree_cache"}
# log_signer_of is gone (the signer is an argument); named here so that it cannot return.
LOOKUPS = {"database_of", "log_signer_of", "log_trees_of"}
INFO_ALLOWED = {"store/db.py"}
# The app factory and the services object itself wire the database's services together.
WIRING = {"web/app.py", "services/log_signer.py", "services/app.py"}
STORE_LOOKUPS_ALLOWED = {
    "store/approvals/log.py": {"log_trees_of"},
}


def _constants(tree: ast.Module) -> dict[str, str]:
    """Module-level names bound to a string (keys are often named: `_PENDING = "..."`)."""
    found = {}
    for node in tree.body:
        if (isinstance(node, ast.Assign) and isinstance(node.value, ast.Constant)
                and isinstance(node.value.value, str)):
            for target in node.targets:
                if isinstance(target, ast.Name):
                    found[target.id] = node.value.value
    return found


def _key(node: ast.expr, constants: dict[str, str]) -> str | None:
    if isinstance(node, ast.Constant) and isinstance(node.value, str):
        return node.value
    if isinstance(node, ast.Name):
        return constants.get(node.id)
    return None


def _is_info(node: ast.expr) -> bool:
    return isinstance(node, ast.Attribute) and node.attr == "info"


def info_lookups(source: str) -> Iterator[tuple[int, str]]:
    """(line, key) of each read of a service key out of an `info` mapping."""
    tree = ast.parse(source)
    constants = _constants(tree)
    for node in ast.walk(tree):
        if isinstance(node, ast.Subscript) and _is_info(node.value):
            key = _key(node.slice, constants)
        elif (isinstance(node, ast.Call) and isinstance(node.func, ast.Attribute)
              and _is_info(node.func.value) and node.args):
            key = _key(node.args[0], constants)
        else:
            continue
        if key in SERVICE_KEYS:
            yield node.lineno, key


def service_reaches(source: str) -> Iterator[tuple[int, str]]:
    """(line, what) of each lookup call (`database_of(...)`) and each service attribute read
    off something other than the `services` object."""
    for node in ast.walk(ast.parse(source)):
        if isinstance(node, ast.Call):
            name = node.func.id if isinstance(node.func, ast.Name) else (
                node.func.attr if isinstance(node.func, ast.Attribute) else None)
            if name in LOOKUPS:
                yield node.lineno, f"{name}()"
        elif (isinstance(node, ast.Attribute) and node.attr in SERVICE_ATTRIBUTES
              and not (isinstance(node.value, ast.Name) and node.value.id == "services")):
            yield node.lineno, f".{node.attr}"


def _modules() -> Iterator[tuple[str, str]]:
    for path in sorted(ROOT.rglob("*.py")):
        yield path.relative_to(ROOT).as_posix(), path.read_text(encoding="utf-8")


def violations() -> list[str]:
    found = []
    for name, source in _modules():
        if name not in INFO_ALLOWED:
            found += [f"{name}:{line} reads {key!r} from a session's info"
                      for line, key in info_lookups(source)]
        if name.split("/")[0] in ("web", "services") and name not in WIRING:
            found += [f"{name}:{line} reaches a service through {what}; take it from "
                      "AppServices (the Services dependency) instead"
                      for line, what in service_reaches(source)]
        if name.startswith("store/") and name != "store/db.py":
            allowed = STORE_LOOKUPS_ALLOWED.get(name, set())
            # database_of() opens a short session beside a request's: not a service.
            found += [f"{name}:{line} finds a service through {what}; pass it as an argument"
                      for line, what in service_reaches(source)
                      if what not in ("database_of()", *(f"{f}()" for f in allowed))]
    return found


def test_services_are_given_not_looked_up() -> None:
    assert violations() == []


def test_the_checks_see_each_kind_of_lookup() -> None:
    looked_up = (
        "_KEY = 'log_signer'\n"
        "def f(db, request):\n"
        "    a = db.info['database']\n"
        "    b = getattr(db.info.get('database'), 'log_signer', None)\n"
        "    c = db.info.get(_KEY)\n"
        "    d = db.info.get('countersign_pending_log')\n"  # transaction state: allowed
    )
    assert sorted(info_lookups(looked_up)) == [(3, "database"), (4, "database"),
                                                (5, "log_signer")]
    reached = (
        "def g(db, request, services):\n"
        "    a = database_of(db).reports\n"
        "    b = request.app.state.database.log_signer\n"
        "    c = services.reports\n"  # the one way in
    )
    assert sorted(what for _, what in service_reaches(reached)) == [
        ".log_signer", ".reports", "database_of()"]


def _signer_parameter(source: str, function: str) -> ast.arg | None:
    """The keyword-only `signer` parameter of `function`, if it has one without a default."""
    for node in ast.walk(ast.parse(source)):
        if isinstance(node, ast.FunctionDef) and node.name == function:
            for arg, default in zip(node.args.kwonlyargs, node.args.kw_defaults, strict=True):
                if arg.arg == "signer" and default is None:
                    return arg
    return None


def test_event_appends_are_given_their_signer() -> None:
    """record() and append_to_log() take the signer as a required keyword: a default would
    let a caller append an entry without a receipt by forgetting it."""
    source = (ROOT / "store" / "events.py").read_text(encoding="utf-8")
    for function in ("record", "append_to_log"):
        assert _signer_parameter(source, function) is not None, function
    assert _signer_parameter("def record(db, *, signer=None): ...", "record") is None
