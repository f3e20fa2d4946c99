"""A process that validates many missions loads every check up front (verify/every_check.py,
the validation processes' preload): what `validate` loads on demand for one mission is then
loaded already, so no job pays for it."""

from __future__ import annotations

import json
import subprocess
import sys

# What validate loads only for the missions that need it (tests/cli/test_validate_imports.py).
ON_DEMAND = ("numpy", "shapely", "pyproj", "z3", "countersign.verify.land",
             "countersign.verify.land_mask", "countersign.verify.patterns",
             "countersign.verify.probability", "countersign.verify.procedures",
             "countersign.verify.report_document")
PROBE = """
import json, sys
import countersign.verify.every_check
before = set(sys.modules)
from countersign.orders.examples import example_names, load_example
from countersign.verify.logic import LogicCache
from countersign.verify.parts import PartsCache
from countersign.verify.report import validate
from countersign.orders.model import Orders
missions = [load_example(name) for name in example_names()]
# and one with outcome probabilities, which no example declares
chances = {"succeed": 0.8, "fail": 0.1, "violate": 0.1}
data = missions[0].model_dump(exclude_unset=True)
data["goals"] = [{**goal, "p": chances} for goal in data["goals"]]
missions.append(Orders.model_validate(data))
for orders in missions:
    validate(orders, logic_cache=LogicCache(), parts=PartsCache()).to_json()
print(json.dumps(sorted(set(sys.modules) - before)))
"""


def test_after_every_check_validating_loads_nothing_on_demand() -> None:
    done = subprocess.run([sys.executable, "-c", PROBE], capture_output=True, text=True,
                          check=True, timeout=600)
    loaded_later = json.loads(done.stdout.strip().splitlines()[-1])
    on_demand = [m for m in loaded_later
                 if any(m == name or m.startswith(f"{name}.") for name in ON_DEMAND)]
    assert on_demand == []
