"""The GRAVITAS scenario (seed 001 section 8) as planning problems.

Three survey areas, lower-left (LL), upper-right (UR) and lower-right (LR), with rewards
22807, 51918 and 31313 and an energy level of 60000 (read as Wh; 1 Wh per metre of transit).
The geometry is ours (the paper gives none): it reproduces the paper's story. Initially all
three areas fit. After the first survey (LL) used 23284 instead of the expected 14400, the
consumption rate rose by 62%; re-planned from LL's exit with the energy left, only LR fits
(UR, the most rewarding, is out of reach), and LR is expected to cost 27216.

`gravitas-currency` adds a common currency (seed 001 section 5.3): each Wh is worth 2 reward
units, so LL (reward 22807, about 11,900 Wh more) is no longer worth surveying.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

from .model import PlanProblem

RISE = 1.62
USED_IN_LL = 23284.0


def _passes(entry: list[float], exit_: list[float], survey: float) -> list[dict[str, Any]]:
    # A lawn-mower pattern can be flown either way round: entry and exit swap.
    return [
        {"entry": entry, "exit": exit_, "survey_wh": survey, "title": "forward"},
        {"entry": exit_, "exit": entry, "survey_wh": survey, "title": "reverse"},
    ]


def gravitas_data(replan: bool = False, level: int = 2) -> dict[str, Any]:
    factor = RISE if replan else 1.0
    areas = [
        {"id": "LL", "title": "Lower left", "reward": 22807,
         "passes": _passes([1000, 1000], [3000, 1000], 13000 * factor)},
        {"id": "UR", "title": "Upper right", "reward": 51918,
         "passes": _passes([6000, 7000], [8000, 9000], 12000 * factor)},
        {"id": "LR", "title": "Lower right", "reward": 31313,
         "passes": _passes([6000, 1000], [8000, 2000], 11800 * factor)},
    ]
    battery = 60000.0
    start = [0.0, 0.0]
    if replan:
        areas = areas[1:]
        battery -= USED_IN_LL
        start = [3000.0, 1000.0]
    return {
        "format": "countersign.plan/1",
        "level": level,
        "start": start,
        "recovery": [8000.0, 0.0],
        "vehicle": {"transit_wh_per_m": 1.0 * factor, "battery_wh": battery, "reserve_wh": 2000},
        "areas": areas,
    }


EXAMPLES: dict[str, Callable[[], dict[str, Any]]] = {
    "gravitas": lambda: gravitas_data(False),
    "gravitas-replan": lambda: gravitas_data(True),
    "gravitas-level1": lambda: gravitas_data(False, level=1),
    "gravitas-currency": lambda: {
        **gravitas_data(False),
        "conversion": {"energy_wh": {"kind": "linear", "rate": 2.0}},
    },
}


def example_problem(name: str) -> PlanProblem:
    try:
        factory = EXAMPLES[name]
    except KeyError:
        raise KeyError(
            f"no example problem {name!r}; examples: {', '.join(sorted(EXAMPLES))}"
        ) from None
    return PlanProblem.model_validate(factory())
