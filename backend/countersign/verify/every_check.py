"""Every check's code, loaded on import: for a process that validates many missions (the
server's validation processes, whose forkserver preloads this module).

`validate` itself loads the geometry stack (numpy, shapely, pyproj) for missions with areas,
z3 for a unit that bounds propagation cannot settle, and the checks of path patterns, outcome
probabilities and procedures for missions that have them, so that one validation on the command
line pays for what its mission needs only; a long-lived process pays for all of it once, before
its first job rather than during one.
"""

from __future__ import annotations

from importlib import import_module

ON_DEMAND = ("numpy", "shapely", "pyproj", "z3", "countersign.verify.report",
             "countersign.verify.land", "countersign.verify.patterns",
             "countersign.verify.probability", "countersign.verify.procedures",
             "countersign.verify.report_document")

for _name in ON_DEMAND:
    import_module(_name)
