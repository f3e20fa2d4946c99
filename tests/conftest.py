"""The suite's root: markers, ids and worker order for every test (below), and where tests live.

Folders mirror the packages: tests/<package> holds the tests of backend/countersign/<package>,
by the package a module exercises (the one its docstring is about; a module spanning several
without one subject goes to the outermost). tests/web holds the API tests (its conftest.py gives
them the `world`); tests/core the top-level modules (errors, limits, settings, strict_json,
ontology_files); tests/codebase rules over the whole code and the suite; tests/e2e, bench and
oracles keep folders of their own. tests/codebase/test_suite_layout.py holds this, with the
reason for each exception. Helpers sit beside the tests that use them, or here at the top."""

from __future__ import annotations

import os
from pathlib import Path

import pytest
from hypothesis import settings

from .cheap_hashing import _cheap_password_hashing  # noqa: F401
from .markers import mark_items
from .node_ids import unique_ids
from .workers import heavy_first, separate_postgres

REPO = Path(__file__).resolve().parents[1]

# Property tests: a developer's run draws new cases every time ("explore"); CI's run
# (.ci/run sets COUNTERSIGN_HYPOTHESIS_PROFILE=ci) draws the same ones for the same code, so a
# landing does not hang on a case no one has seen yet. Cases a run finds become @example's.
settings.register_profile("explore", print_blob=True)
settings.register_profile("ci", derandomize=True, print_blob=True)
settings.load_profile(os.environ.get("COUNTERSIGN_HYPOTHESIS_PROFILE", "explore"))

# Here, on import, not in a hook: a sub-folder's conftest or a test module named on the command
# line is imported before pytest_configure, and reads the variable on import (tests/workers.py).
separate_postgres()


@pytest.fixture(scope="session")
def repo() -> Path:
    return REPO


def pytest_collection_modifyitems(config: pytest.Config, items: list[pytest.Item]) -> None:
    """The markers postgres, browser and slow (pyproject.toml), added by where a test lives and
    what it uses (tests/markers.py); under xdist, the order of tests/workers.py. Ids made
    unique first (tests/node_ids.py): xdist hands out tests by id."""
    unique_ids(items)
    mark_items(items)
    heavy_first(items)


def pytest_terminal_summary(terminalreporter: pytest.TerminalReporter) -> None:
    if hasattr(terminalreporter.config, "workerinput"):
        return  # an xdist worker: the controller receives every worker's reports and writes it
    from .summary_plugin import write_summary

    write_summary(terminalreporter)
