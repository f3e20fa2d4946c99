"""`countersign validate` loads a heavy library only for missions that need it: the geometry
stack (numpy, shapely, pyproj) for areas, z3 for a unit that bounds propagation cannot settle,
rdflib and owlrl for --explain. Each is a large part of a short command's CPU
(tests/bench/bench_startup.py)."""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path
from typing import Any

import pytest

GEOMETRY = ("numpy", "shapely", "pyproj")
HEAVY = (*GEOMETRY, "z3", "rdflib", "owlrl", "pyoxigraph", "networkx", "pint")


def _orders(**extra: Any) -> dict[str, Any]:
    """Two transits and a mission-wide constraint that the vehicle's envelope leaves open."""
    return {
        "format": "countersign.orders/1", "id": "plain", "vehicle": "v", "start": "G1",
        "goals": [
            {"id": "G1", "title": "Transit out", "behavior": "transit", "requires": ["transit"],
             "envelope": {"depth_m": [5, 20]},
             "next": {"succeed": "G2", "fail": "ABORT", "violate": "ABORT"}},
            {"id": "G2", "title": "Return", "behavior": "transit", "requires": ["transit"],
             "next": {"succeed": "COMPLETE", "fail": "ABORT", "violate": "ABORT"}},
        ],
        "constraints": [{"id": "C1", "text": "Deeper than 2 m", "applies_to": "mission",
                         "expr": "depth_m >= 2"}],
        "quantities": {"depth_m": {"unit": "m", "min": 0}},
        "vehicles": [{"id": "v", "envelope": {"depth_m": [0, 100]},
                      "features": [{"id": "nav", "fulfills": ["transit"],
                                    "measures": ["depth_m"]}]}],
        **extra,
    }


def _heavy_after_validate(source: str) -> tuple[str, list[str]]:
    """The output of `countersign validate SOURCE`, run as the program runs it, and the heavy
    libraries loaded by then."""
    code = ("import contextlib, io, json, runpy, sys\n"
            f"sys.argv = ['countersign', 'validate', {source!r}]\n"
            "out = io.StringIO()\n"
            "with contextlib.suppress(SystemExit), contextlib.redirect_stdout(out):\n"
            "    runpy.run_module('countersign.cli', run_name='__main__')\n"
            f"print(json.dumps([out.getvalue(), sorted(set({HEAVY!r}) & set(sys.modules))]))\n")
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                          check=True, timeout=300)
    output, loaded = json.loads(done.stdout.strip().splitlines()[-1])
    return output, loaded


def test_orders_without_areas_load_no_geometry_nor_solver(tmp_path: Path) -> None:
    path = tmp_path / "plain.json"
    path.write_text(json.dumps(_orders()))
    output, loaded = _heavy_after_validate(str(path))
    assert "OK: 0 error(s), 0 warning(s)." in output  # it validated, constraint and all
    assert loaded == []


def test_orders_with_an_area_load_the_geometry_and_still_no_solver(tmp_path: Path) -> None:
    orders = _orders(areas=[{"id": "A", "polygon": [[36.70, -121.90], [36.70, -121.87],
                                                    [36.695, -121.87], [36.695, -121.90]]}])
    orders["goals"][0]["area"] = "A"
    path = tmp_path / "area.json"
    path.write_text(json.dumps(orders))
    output, loaded = _heavy_after_validate(str(path))
    assert "OK: 0 error(s)" in output
    assert loaded == sorted(GEOMETRY)


def test_a_unit_bounds_cannot_settle_loads_the_solver(tmp_path: Path) -> None:
    # A product of two quantities is z3's to decide (verify/logic/bounds.py).
    orders = _orders(quantities={"depth_m": {"unit": "m", "min": 0}, "k": {}})
    orders["constraints"][0]["expr"] = "depth_m * k >= 2"
    orders["vehicles"][0]["features"][0]["measures"] = ["depth_m", "k"]
    path = tmp_path / "product.json"
    path.write_text(json.dumps(orders))
    _, loaded = _heavy_after_validate(str(path))
    assert loaded == ["z3"]



def _process_after_validate(environment: dict[str, str]) -> tuple[int, str | None, list[str]]:
    """Of a `countersign validate` process of the exemplar: its threads at the end (the
    kernel's count, native ones too), the OPENBLAS_NUM_THREADS it ran with, and the entry-point
    groups searched (each search reads every installed distribution's metadata)."""
    code = ("import contextlib, io, json, os, runpy, sys\n"
            "import importlib.metadata as metadata\n"
            "searched, search = [], metadata.entry_points\n"
            "def recording(**selection):\n"
            "    searched.append(selection.get('group', '*'))\n"
            "    return search(**selection)\n"
            "metadata.entry_points = recording\n"
            "sys.argv = ['countersign', 'validate', 'example:search-and-sample']\n"
            "out = io.StringIO()\n"
            "with contextlib.suppress(SystemExit), contextlib.redirect_stdout(out):\n"
            "    runpy.run_module('countersign.cli', run_name='__main__')\n"
            "assert 'OK: 0 error(s)' in out.getvalue() and 'numpy' in sys.modules\n"
            "print(json.dumps([len(os.listdir('/proc/self/task')),\n"
            "                  os.environ.get('OPENBLAS_NUM_THREADS'), searched]))\n")
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                          check=True, timeout=300, env=environment)
    threads, blas_threads, searched = json.loads(done.stdout.strip().splitlines()[-1])
    return threads, blas_threads, searched


def _environment_without(*names: str) -> dict[str, str]:
    return {k: v for k, v in os.environ.items() if k not in names}


@pytest.mark.skipif(not Path("/proc/self/task").is_dir(), reason="threads counted in /proc")
def test_validating_starts_no_blas_threads() -> None:
    # numpy's OpenBLAS otherwise starts a thread per core as numpy loads, and they spin: more
    # CPU than the validation's own wall time on two cores (tests/bench/bench_startup.py).
    threads, blas_threads, _ = _process_after_validate(
        _environment_without("OPENBLAS_NUM_THREADS"))
    assert (threads, blas_threads) == (1, "1")


def test_validating_searches_no_installed_distribution_for_plugins() -> None:
    _, _, searched = _process_after_validate(_environment_without("PYDANTIC_DISABLE_PLUGINS"))
    assert searched == []


def test_the_variables_given_are_kept() -> None:
    environment = {**os.environ, "OPENBLAS_NUM_THREADS": "2", "PYDANTIC_DISABLE_PLUGINS": ""}
    _, blas_threads, searched = _process_after_validate(environment)
    assert (blas_threads, searched) == ("2", ["pydantic"])
