"""The suite's folders mirror the packages: a test module lives in tests/<package> for the
backend package it exercises (backend/countersign/<package>), or in one of the folders named
below with the reason it stands apart; and every package has a folder of tests, or is named
below with the place its tests live. A change to a package then finds its tests in one place."""

from __future__ import annotations

from pathlib import Path

TESTS = Path(__file__).resolve().parents[1]
PACKAGES = TESTS.parent / "backend" / "countersign"

# Folders of tests that are not one package's, and why.
OWN_FOLDERS = {
    "core": "the top-level modules of countersign (errors.py, limits.py, settings.py, "
            "strict_json.py, ontology_files.py), which belong to no package",
    "codebase": "rules over the whole code and the suite itself (layering, code shape, dead "
                "code, private APIs, this layout)",
    "e2e": "browser tests: Chromium against a real server; the `browser` marker is given by "
           "this folder (tests/markers.py)",
    "bench": "benchmarks (bench_*.py), run by ./scripts/bench, not by pytest",
    "oracles": "independent reference implementations the tests of several packages compare with",
}

# Packages whose tests live elsewhere, and where.
TESTED_ELSEWHERE = {
    "approved_package": "built from a real approval and verified offline over the API: "
                        "tests/web/test_packages.py, tests/web/test_package_layout.py",
    "jobs": "the campaign queue's back ends, exercised with the campaigns that use them: "
            "tests/campaigns/test_campaign_queues.py",
    "services": "the domain services the routes call, tested through the API in tests/web",
}


def packages() -> set[str]:
    """The sub-packages of countersign that hold code."""
    return {path.parent.name for path in PACKAGES.glob("*/__init__.py")}


def folders_of_tests(tests: Path = TESTS) -> dict[str, list[str]]:
    """Each top-level folder of the suite holding test modules, with those modules."""
    found: dict[str, list[str]] = {}
    for module in sorted(tests.rglob("test_*.py")):
        relative = module.relative_to(tests)
        folder = relative.parts[0] if len(relative.parts) > 1 else "."
        found.setdefault(folder, []).append(relative.as_posix())
    return found


def misplaced(tests: Path = TESTS, known: set[str] | None = None) -> list[str]:
    """Test modules in a folder that is neither a package's nor one of OWN_FOLDERS."""
    allowed = (packages() if known is None else known) | set(OWN_FOLDERS)
    return sorted(module for folder, modules in folders_of_tests(tests).items()
                  if folder not in allowed for module in modules)


def untested(tests: Path = TESTS, known: set[str] | None = None) -> list[str]:
    """Packages with no folder of tests that are not named in TESTED_ELSEWHERE."""
    present = set(folders_of_tests(tests))
    return sorted((packages() if known is None else known) - present - set(TESTED_ELSEWHERE))


def test_every_test_module_lives_in_a_package_folder_or_a_named_one() -> None:
    assert misplaced() == [], (
        "test modules outside tests/<package> and the folders of tests/codebase/"
        "test_suite_layout.py: move them to the package they exercise")


def test_every_package_has_a_folder_of_tests() -> None:
    assert untested() == [], \
        "packages without tests/<package>: add one or name it in TESTED_ELSEWHERE"


def test_the_named_exceptions_are_still_needed() -> None:
    folders, known = set(folders_of_tests()), packages()
    assert not set(OWN_FOLDERS) & known, "a folder of its own shares a package's name"
    assert set(TESTED_ELSEWHERE) <= known, "TESTED_ELSEWHERE names a package that is gone"
    assert not set(TESTED_ELSEWHERE) & folders, \
        "a package in TESTED_ELSEWHERE now has tests/<package>: take it off the list"


def test_every_folder_of_tests_is_a_package() -> None:
    """Helpers beside the tests are imported relatively (`from .readers import ...`), and two
    folders may hold modules of the same name: each folder needs its __init__.py."""
    missing = [folder for folder in folders_of_tests() if folder != "."
               and not (TESTS / folder / "__init__.py").is_file()]
    assert missing == []


def test_the_layout_rules_catch_a_stray_module_and_a_missing_folder(tmp_path: Path) -> None:
    (tmp_path / "orders").mkdir()
    (tmp_path / "orders" / "test_reading.py").touch()
    (tmp_path / "unit").mkdir()
    (tmp_path / "unit" / "test_anything.py").touch()
    (tmp_path / "test_at_the_top.py").touch()
    assert misplaced(tmp_path, known={"orders", "verify"}) == [
        "test_at_the_top.py", "unit/test_anything.py"]
    assert untested(tmp_path, known={"orders", "verify"}) == ["verify"]
