"""The logic check's limits, version and item kinds."""

from __future__ import annotations

import re
from typing import Literal

VERSION = "countersign.logic/1"
DEFAULT_TIMEOUT_MS = 2_000
DEFAULT_TOTAL_S = 60.0
MAX_CORES_PER_UNIT = 3
# Longer expressions are cut short in explanations (the finding's details keep the ids).
MAX_WORDS = 240
ItemKind = Literal[
    "envelope", "behavior", "area", "context", "constraint", "vehicle", "domain", "norm",
    "breach", "negation", "goal", "property",
]
GOAL_KINDS = frozenset({"envelope", "behavior", "area", "context", "goal"})
_KIND_ORDER = {
    "goal": 0, "envelope": 0, "behavior": 1, "area": 1, "context": 2, "constraint": 3,
    "negation": 3, "property": 3, "norm": 4, "breach": 4, "vehicle": 5, "domain": 6,
}
_IDENTIFIER = re.compile(r"[A-Za-z_][A-Za-z0-9_]*")
