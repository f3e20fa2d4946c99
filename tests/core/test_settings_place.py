"""Every COUNTERSIGN_* setting is read in one place, countersign/settings.py (pydantic).

Nothing else in the package touches the environment (no read, no write: the command line hands
gunicorn's workers their settings, not variables). Tests and tools may read only variables of
their own (TEST_ONLY, each with its reason), never a setting of the app. The variables keep the
names the README gives them; a bad value is refused naming the variable, a secret never shows.
"""

from __future__ import annotations

import ast
from collections.abc import Iterator
from pathlib import Path

import pytest

from countersign import settings
from countersign.cli import main

REPO = Path(__file__).resolve().parents[2]
PACKAGE = REPO / "backend" / "countersign"
SETTINGS = PACKAGE / "settings.py"

# Modules of the package allowed to touch os.environ, with the reason.
PLUMBING: dict[str, str] = {
    "countersign/cli/common.py": "the program sets two variables of libraries, not of Countersign "
                     "(OPENBLAS_NUM_THREADS, PYDANTIC_DISABLE_PLUGINS), unless given, before "
                     "they load: importing settings.py first would load pydantic, too early",
}
# Variables only the tests or scripts read: knobs of the suite, never of the app.
TEST_ONLY: dict[str, str] = {
    "COUNTERSIGN_TEST_POSTGRES_URL": "the PostgreSQL database the suite may use",
    "COUNTERSIGN_TEST_SUMMARY": "where the suite's summary plugin writes its report",
    "COUNTERSIGN_TEST_FLOOD_SECONDS": "how long the password-throttle floods last",
    "COUNTERSIGN_TEST_CAMPAIGN_N": "the size of the campaign kill test",
    "COUNTERSIGN_FUZZ_SCALE": "how many cases the API fuzz test draws",
    "COUNTERSIGN_HYPOTHESIS_PROFILE": "the Hypothesis profile of the suite",
    "COUNTERSIGN_IMC_XML": "the IMC.xml the strict IMC reader is generated from",
    "COUNTERSIGN_REQUIRE_IMC_XML": "a missing IMC.xml fails instead of skipping",
    "COUNTERSIGN_UPDATE_VECTORS": "rewrite the browser's crypto vectors",
    "COUNTERSIGN_CHROMIUM": "the browser the end-to-end suite drives",
    "COUNTERSIGN_REQUIRE_E2E": "a missing browser fails instead of skipping",
    "COUNTERSIGN_E2E_VIEWPORT": "the window size of browser tests that set none of their own",
}
# The variables of the app, as the README and the command line's help name them.
VARIABLES = {
    "COUNTERSIGN_DATA_DIR", "COUNTERSIGN_DATABASE_URL", "COUNTERSIGN_SECURE_COOKIES",
    "COUNTERSIGN_VALIDATION_PROCESSES", "COUNTERSIGN_MAP_TILES",
    "COUNTERSIGN_MAP_TILES_ATTRIBUTION", "COUNTERSIGN_LOG_KEY_DIR", "COUNTERSIGN_LOG_KEY",
    "COUNTERSIGN_PASSWORD_CHECKS_PER_MINUTE", "COUNTERSIGN_ONTOLOGY_DIR",
    "COUNTERSIGN_LAND_MASK_CACHE", "COUNTERSIGN_SERVER", "COUNTERSIGN_TOKEN",
    "COUNTERSIGN_DEBUG",
}
GROUPS = (settings.ServerEnvironment, settings.LogKeyEnvironment,
          settings.PasswordEnvironment, settings.InstallationEnvironment,
          settings.ClientEnvironment)


ENVIRONMENT = {"environ", "environb", "getenv", "putenv", "unsetenv"}


def _environment_uses(tree: ast.AST) -> Iterator[int]:
    """The line of each use of os.environ, os.getenv, os.putenv or os.unsetenv, imported
    from os or used as an attribute of it."""
    for node in ast.walk(tree):
        imported = isinstance(node, ast.ImportFrom) and node.module == "os" and any(
            alias.name in ENVIRONMENT for alias in node.names)
        used = isinstance(node, ast.Attribute) and node.attr in ENVIRONMENT and isinstance(
            node.value, ast.Name) and node.value.id == "os"
        if imported or used:
            yield node.lineno


def _literal_reads(tree: ast.AST) -> Iterator[tuple[int, str]]:
    """(line, name) of each read of a COUNTERSIGN_ variable by a literal name:
    os.environ.get("X"), os.environ["X"], os.getenv("X")."""
    for node in ast.walk(tree):
        key: ast.AST | None = None
        if isinstance(node, ast.Call) and node.args:
            func = node.func
            if isinstance(func, ast.Attribute) and (
                    (func.attr == "get" and ast.unparse(func.value) == "os.environ")
                    or ast.unparse(func) == "os.getenv"):
                key = node.args[0]
        elif isinstance(node, ast.Subscript) and isinstance(node.ctx, ast.Load) and \
                ast.unparse(node.value) == "os.environ":
            key = node.slice
        if isinstance(key, ast.Constant) and isinstance(key.value, str) and \
                key.value.startswith("COUNTERSIGN_"):
            yield node.lineno, key.value


def package_violations(root: Path = PACKAGE) -> list[str]:
    found = []
    for path in sorted(root.rglob("*.py")):
        where = str(path.relative_to(root.parent))
        if path == root / "settings.py" or where in PLUMBING:
            continue
        for line in _environment_uses(ast.parse(path.read_text(encoding="utf-8"))):
            found.append(f"{where}:{line} uses the environment (read it in settings.py)")
    return found


def outside_violations(paths: list[Path], base: Path = REPO) -> list[str]:
    found = []
    for path in paths:
        tree = ast.parse(path.read_text(encoding="utf-8"))
        for line, name in _literal_reads(tree):
            if name not in TEST_ONLY:
                found.append(f"{path.relative_to(base)}:{line} reads {name}")
    return found


def test_only_settings_py_touches_the_environment() -> None:
    assert package_violations() == []


def test_tests_and_tools_read_only_their_own_variables() -> None:
    # Writing a child's environment (`{**os.environ, "COUNTERSIGN_...": ...}`) is plumbing.
    paths = sorted((REPO / "tests").rglob("*.py")) + sorted((REPO / "tools").rglob("*.py"))
    assert outside_violations(paths) == []
    assert not set(TEST_ONLY) & VARIABLES


def test_the_checks_see_a_read_elsewhere(tmp_path: Path) -> None:
    package = tmp_path / "countersign"
    (package / "store").mkdir(parents=True)
    (package / "settings.py").write_text("import os\nX = os.environ.get('COUNTERSIGN_X')\n")
    (package / "store" / "a.py").write_text("import os\nX = os.environ['COUNTERSIGN_X']\n")
    (package / "b.py").write_text("from os import getenv\n")
    (package / "c.py").write_text("import os\nos.environ['COUNTERSIGN_X'] = '1'\n")
    assert package_violations(package) == [
        "countersign/b.py:1 uses the environment (read it in settings.py)",
        "countersign/c.py:2 uses the environment (read it in settings.py)",
        "countersign/store/a.py:2 uses the environment (read it in settings.py)",
    ]
    source = ("import os\nA = os.environ.get('COUNTERSIGN_DATA_DIR')\n"
              "B = os.getenv('COUNTERSIGN_FUZZ_SCALE')\nC = os.environ['COUNTERSIGN_TOKEN']\n"
              "D = {**os.environ, 'COUNTERSIGN_DATABASE_URL': ''}\n")
    probe = tmp_path / "probe.py"
    probe.write_text(source)
    assert outside_violations([probe], base=tmp_path) == [
        "probe.py:2 reads COUNTERSIGN_DATA_DIR", "probe.py:4 reads COUNTERSIGN_TOKEN"]


def test_settings_import_only_leaves() -> None:
    """The command line and every layer take their settings from here: no web, no store."""
    ours = {f"{node.module}" for node in ast.walk(ast.parse(SETTINGS.read_text()))
            if isinstance(node, ast.ImportFrom) and node.level}
    assert ours <= {"limits", "map_tiles"}


def test_the_variables_keep_their_names_and_are_documented() -> None:
    names = {str(field.validation_alias) for group in GROUPS
             for field in group.model_fields.values()}
    assert names == VARIABLES
    documented = (REPO / "README.md").read_text(encoding="utf-8") + \
        (PACKAGE / "cli" / "server.py").read_text(encoding="utf-8")
    for name in VARIABLES - {"COUNTERSIGN_SERVER", "COUNTERSIGN_ONTOLOGY_DIR",
                             "COUNTERSIGN_DEBUG"}:  # named in the commands' help and errors
        assert name in documented, name


def test_defaults_and_empty_values(monkeypatch: pytest.MonkeyPatch, tmp_path: Path) -> None:
    for name in VARIABLES:
        monkeypatch.delenv(name, raising=False)
    monkeypatch.setenv("COUNTERSIGN_DATABASE_URL", "")  # empty: not set, as before
    monkeypatch.setenv("COUNTERSIGN_MAP_TILES", " ")
    found = settings.Settings.from_environment(tmp_path)
    assert found.database_url == f"sqlite:///{tmp_path.resolve() / 'countersign.db'}"
    assert (found.validation_processes, found.secure_cookies, found.map_tiles) == (2, False, None)
    monkeypatch.setenv("COUNTERSIGN_DATA_DIR", str(tmp_path / "data"))
    monkeypatch.setenv("COUNTERSIGN_SECURE_COOKIES", "Yes")
    monkeypatch.setenv("COUNTERSIGN_MAP_TILES_ATTRIBUTION", "  " + "x" * 300)
    found = settings.Settings.from_environment()
    assert found.data_dir == (tmp_path / "data").resolve() and found.secure_cookies
    assert found.map_tiles_attribution == "x" * 200
    assert settings.Settings.from_environment(tmp_path, validation_processes=0) \
        .validation_processes == 0
    client = settings.read(settings.ClientEnvironment)
    assert (client.server, client.token, client.debug) == ("http://127.0.0.1:8000", None, False)


def test_a_bad_value_is_named_and_a_secret_is_not_shown(
        monkeypatch: pytest.MonkeyPatch, tmp_path: Path) -> None:
    monkeypatch.setenv("COUNTERSIGN_VALIDATION_PROCESSES", "65")
    with pytest.raises(settings.SettingsError) as refused:
        settings.Settings.from_environment(tmp_path)
    assert str(refused.value) == ("COUNTERSIGN_VALIDATION_PROCESSES must be a whole number "
                                  "from 0 to 64, not '65'")
    # Another group's bad variable is no concern of this one.
    assert settings.read(settings.InstallationEnvironment).ontology_dir is None
    monkeypatch.setenv("COUNTERSIGN_TOKEN", "cst_secret-token")
    assert "cst_secret-token" not in repr(settings.read(settings.ClientEnvironment))


def test_the_command_line_names_a_bad_variable_without_a_trace(
        monkeypatch: pytest.MonkeyPatch, tmp_path: Path,
        capsys: pytest.CaptureFixture[str]) -> None:
    monkeypatch.setenv("COUNTERSIGN_VALIDATION_PROCESSES", "many")
    code = main(["users", "create", "--username", "admin", "--role", "admin",
                 "--data-dir", str(tmp_path)])
    assert code == 2
    assert capsys.readouterr().err == ("countersign: COUNTERSIGN_VALIDATION_PROCESSES must be "
                                       "a whole number from 0 to 64, not 'many'\n")
