"""`countersign validate` loads a heavy library only for missions that need it: the geometry
stack (numpy, shapely, pyproj) for areas, z3 for a unit that bounds propagation cannot settle,
rdflib and owlrl for --explain. Each is a large part of a short command's CPU
(tests/bench/bench_startup.py)."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path
from typing import Any

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
