"""Built-in example orders shipped with Countersign."""

from __future__ import annotations

from importlib import resources

from ..model import Orders
from ..reader import read_json


def example_names() -> list[str]:
    files = resources.files(__name__)
    return sorted(p.name.removesuffix(".json") for p in files.iterdir() if p.name.endswith(".json"))


def example_bytes(name: str) -> bytes:
    if name not in example_names():
        raise KeyError(f"no built-in example named {name!r}; choose one of {example_names()}")
    return resources.files(__name__).joinpath(f"{name}.json").read_bytes()


def load_example(name: str) -> Orders:
    return read_json(example_bytes(name))
