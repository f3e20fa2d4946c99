"""Markers added by where a test lives and what it uses, so that a quick loop is one option:
`pytest -m "not browser and not slow"` (README, Testing). Registered in pyproject.toml.

- browser: every test under tests/e2e (Chromium and a real `countersign serve`).
- postgres: the PostgreSQL variant of a `database_url` test and every test using the
  `postgres` fixture (they skip without COUNTERSIGN_TEST_POSTGRES_URL).
- slow: the modules below, each of which costs a minute or more of a CI run on this 2-core
  machine (`--durations`); they still run in every full run."""

from __future__ import annotations

from pathlib import Path

import pytest

TESTS = Path(__file__).resolve().parent
BROWSER_FOLDERS = ("e2e",)
SLOW_MODULES = (
    "web/test_fuzz.py",  # schemathesis over every operation, roles and scenarios
    "campaigns/test_campaign_kill.py",  # real campaign processes killed and resumed
    "export/test_moos_helm.py",  # builds and runs MOOS-IvP's helm
)


def _where(item: pytest.Item) -> str:
    try:
        return Path(item.path).resolve().relative_to(TESTS).as_posix()
    except ValueError:
        return ""


def _postgres(item: pytest.Item) -> bool:
    callspec = getattr(item, "callspec", None)
    if callspec is not None and callspec.params.get("database_url") == "postgresql":
        return True
    return "postgres" in getattr(item, "fixturenames", ())


def mark_items(items: list[pytest.Item]) -> None:
    for item in items:
        where = _where(item)
        if where.split("/", 1)[0] in BROWSER_FOLDERS:
            item.add_marker(pytest.mark.browser)
        if where in SLOW_MODULES:
            item.add_marker(pytest.mark.slow)
        if _postgres(item):
            item.add_marker(pytest.mark.postgres)
