"""The suite's parallel run keeps its workers apart (tests/workers.py): each xdist worker has a
PostgreSQL database of its own, and tests sharing a module's set-up run on one worker."""

from __future__ import annotations

import os
import re
import subprocess
import sys
import textwrap
from pathlib import Path

import pytest
from sqlalchemy import create_engine, text
from sqlalchemy.engine import make_url

from ..workers import POSTGRES_VARIABLE, create_database, worker_database_url, worker_id

REPO = Path(__file__).resolve().parents[2]
URL = "postgresql://postgres:secret@127.0.0.1:55432/cs_a"


def test_two_workers_get_two_databases_on_the_suites_server() -> None:
    first, second = (make_url(worker_database_url(URL, w)) for w in ("gw0", "gw1"))
    assert first.database != second.database
    assert {first.database, second.database}.isdisjoint({make_url(URL).database})
    for own in (first, second):
        assert (own.host, own.port, own.username, own.password) == (
            "127.0.0.1", 55432, "postgres", "secret")


def test_a_url_without_a_database_is_refused_naming_the_variable() -> None:
    with pytest.raises(ValueError, match=POSTGRES_VARIABLE):
        worker_database_url("postgresql://postgres@127.0.0.1:55432", "gw0")


def test_this_worker_uses_its_own_database() -> None:
    """In a parallel run with PostgreSQL, the variable every fixture reads names this
    worker's database (rewritten on the conftest's import)."""
    url, worker = os.environ.get(POSTGRES_VARIABLE), worker_id()
    if not url or not worker:
        pytest.skip("checked in a parallel run with COUNTERSIGN_TEST_POSTGRES_URL (-n 2)")
    assert str(make_url(url).database).endswith(f"_{worker}")


def test_a_workers_database_is_created_once() -> None:
    url = os.environ.get(POSTGRES_VARIABLE)
    if not url:
        pytest.skip("PostgreSQL tests need COUNTERSIGN_TEST_POSTGRES_URL (.ci/run sets it)")
    own = worker_database_url(url, "gwcheck")
    engine = create_engine(make_url(url).set(drivername="postgresql+psycopg"),
                           isolation_level="AUTOCOMMIT")
    name = make_url(own).database
    try:
        create_database(own, via=url)
        create_database(own, via=url)  # a second run finds it there
        with engine.connect() as connection:
            assert connection.execute(text("SELECT count(*) FROM pg_database WHERE datname = "
                                           ":name"), {"name": name}).scalar_one() == 1
    finally:
        with engine.connect() as connection:
            connection.execute(text(f'DROP DATABASE IF EXISTS "{name}"'))
        engine.dispose()


SHARED_MODULE = """
import os, pathlib, pytest

@pytest.fixture(scope="module")
def shared():
    with open(pathlib.Path(__file__).with_suffix(".setups"), "a") as out:
        out.write(os.environ.get("PYTEST_XDIST_WORKER", "main") + "\\n")

@pytest.mark.parametrize("n", range(6))
def test_uses_shared(shared, n):
    pass
"""
SCRIPT = REPO / "scripts" / "test"


def _parallel_options() -> list[str]:
    """The options ./scripts/test gives pytest for a parallel run."""
    found = re.search(r"^parallel=\((.*)\)$", SCRIPT.read_text(), re.MULTILINE)
    assert found, f"{SCRIPT} sets no parallel=(...) options"
    return [arg.replace('"$(nproc)"', "2") for arg in found.group(1).split()]


def test_a_modules_shared_setup_runs_once_in_a_parallel_run(tmp_path: Path) -> None:
    """./scripts/test's parallel options on two modules of six tests each sharing a module
    fixture: handed out test by test, both workers' first tests come from the first module
    and set it up twice (a MOOS-IvP flight of minutes, twice and side by side)."""
    for name in ("test_first.py", "test_second.py"):
        (tmp_path / name).write_text(textwrap.dedent(SHARED_MODULE))
    done = subprocess.run(
        [sys.executable, "-m", "pytest", "-q", "-p", "no:cacheprovider", *_parallel_options(),
         "-o", "addopts=", "--rootdir", str(tmp_path), str(tmp_path)],
        cwd=tmp_path, capture_output=True, text=True, timeout=600)
    assert done.returncode == 0, done.stdout + done.stderr
    assert "12 passed" in done.stdout
    for module in ("test_first", "test_second"):
        setups = (tmp_path / f"{module}.setups").read_text().split()
        assert len(setups) == 1, f"{module}'s module fixture was set up on {setups}"


ORDERED_MODULE = """
import os, pathlib

def test_{n}(n=0):
    with open(pathlib.Path(__file__).with_name("order"), "a") as out:
        out.write(pathlib.Path(__file__).stem + "\\n")
"""


def test_modules_are_handed_out_in_the_collections_order(tmp_path: Path) -> None:
    """./scripts/test's parallel options keep the collection's order of modules (tests/workers.py
    puts the long ones first there): by default xdist hands out the modules with the most tests
    first, and the browser modules, few tests of a minute each, ran last on both workers. One
    worker here, so that the order handed out is the order run."""
    for name, tests in (("test_a_few", 1), ("test_b_many", 6)):
        (tmp_path / f"{name}.py").write_text("".join(
            textwrap.dedent(ORDERED_MODULE).replace("{n}", str(n)) for n in range(tests)))
    options = [option if option != "2" else "1" for option in _parallel_options()]
    done = subprocess.run(
        [sys.executable, "-m", "pytest", "-q", "-p", "no:cacheprovider", *options,
         "-o", "addopts=", "--rootdir", str(tmp_path), str(tmp_path)],
        cwd=tmp_path, capture_output=True, text=True, timeout=600)
    assert done.returncode == 0, done.stdout + done.stderr
    order = (tmp_path / "order").read_text().split()
    assert order == ["test_a_few"] + ["test_b_many"] * 6, order


def test_every_long_module_named_first_exists() -> None:
    """A renamed or split module would drop out of HEAVY_FIRST silently and run wherever
    its name falls, perhaps last."""
    from ..workers import HEAVY_FIRST, TESTS

    missing = [entry for entry in HEAVY_FIRST if not (TESTS / entry).exists()]
    assert not missing, missing
