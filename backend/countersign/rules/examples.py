"""Built-in default theories shipped as data (rules/*.json)."""

from __future__ import annotations

import json
from importlib import resources

from .theory import DefaultTheory, parse_theory

_PACKAGE = "countersign.rules.data"


def theory_names() -> list[str]:
    files = resources.files(_PACKAGE)
    return sorted(p.name.removesuffix(".json") for p in files.iterdir() if p.name.endswith(".json"))


def load_theory(name: str) -> DefaultTheory:
    if name not in theory_names():
        raise KeyError(f"no built-in theory named {name!r}; choose one of {theory_names()}")
    data = json.loads(resources.files(_PACKAGE).joinpath(f"{name}.json").read_text("utf-8"))
    return parse_theory(data.get("rules", data), f"{name}.rules")
