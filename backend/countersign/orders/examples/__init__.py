"""Built-in example orders shipped with Countersign.

Team examples (orders with a `team`, verify/team.py) live in `teams/`: they are loaded by
name like the others, but `example_names()` lists only single-vehicle orders, because the
vehicle formats (AVCL, IMC, MOOS-IvP, Turtle) carry one vehicle's MEA.
"""

from __future__ import annotations

from importlib import resources

from ..model import Orders
from ..reader import read_json


def _names(package: str) -> list[str]:
    files = resources.files(package)
    return sorted(p.name.removesuffix(".json") for p in files.iterdir() if p.name.endswith(".json"))


def example_names() -> list[str]:
    return _names(__name__)


def team_example_names() -> list[str]:
    return _names(f"{__name__}.teams")


def example_bytes(name: str) -> bytes:
    # The teams' folder is listed only for a name that is not among the others.
    for package, names in ((__name__, example_names),
                           (f"{__name__}.teams", team_example_names)):
        if name in names():
            return resources.files(package).joinpath(f"{name}.json").read_bytes()
    choices = example_names() + team_example_names()
    raise KeyError(f"no built-in example named {name!r}; choose one of {choices}")


def load_example(name: str) -> Orders:
    return read_json(example_bytes(name))
