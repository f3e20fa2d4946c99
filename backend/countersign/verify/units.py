"""Units as people write them in orders ("1 km", "4 knots", "2 nm") and as quantities declare
them (`unit: "m/s"`, or a name ending `_m`, `_mps`, `_wh`), read and converted by pint.

pint is imported and its registry built on first use only: they cost about a second, which
`countersign --help` and the other light commands must not pay. The units people write most
are known without pint (KNOWN, pint's own names for them, held equal to pint's reading by
tests/verify/test_text_units.py), and a number in the unit its condition reads needs no
conversion: text like the exemplar's ("1000 meters" over `depth_m`) is checked without
importing pint (about a sixth of a `countersign validate` process).
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    import pint

# Relative tolerance when a converted number meets the condition's: a limit converted and
# rounded to three significant figures is within 0.5 % ("2 knots" over `<= 1.03` m/s passes),
# while a limit given in the wrong unit is far outside ("4 knots" over `<= 2` m/s is 2.9 % off).
REL_TOL = 0.01

# Spellings pint reads otherwise or not at all. In orders "nm" is the nautical mile, never
# pint's nanometre; `_mps`/`_pct`/`_wh` are the name suffixes of the built-in quantities.
_ALIASES: dict[str, str] = {
    "nm": "nautical_mile", "NM": "nautical_mile", "Nm": "nautical_mile",
    "nmi": "nautical_mile", "NMI": "nautical_mile",
    "nautical mile": "nautical_mile", "nautical miles": "nautical_mile",
    "mps": "m/s", "pct": "percent", "wh": "Wh", "kwh": "kWh", "c": "degC", "°c": "degC",
}

# English words (and pi) that pint would read as units ("3 in a row" is not three inches).
_NOT_UNITS = frozenset({"a", "am", "are", "as", "at", "e", "he", "in", "me", "pi", "pm", "point",
                        "points", "us"})


# Words (after _ALIASES) and the name pint gives the unit each reads (str of its pint.Unit).
KNOWN: dict[str, str] = {
    "m": "meter", "meter": "meter", "meters": "meter", "metre": "meter", "metres": "meter",
    "km": "kilometer", "kilometer": "kilometer", "kilometers": "kilometer",
    "kilometre": "kilometer", "kilometres": "kilometer", "nautical_mile": "nautical_mile",
    "ft": "foot", "feet": "foot", "foot": "foot", "m/s": "meter / second",
    "knot": "knot", "knots": "knot", "kn": "knot", "kt": "knot",
    "s": "second", "second": "second", "seconds": "second", "sec": "second",
    "min": "minute", "minute": "minute", "minutes": "minute",
    "h": "hour", "hr": "hour", "hour": "hour", "hours": "hour",
    "Wh": "watt_hour", "kWh": "kilowatt_hour", "W": "watt", "percent": "percent",
    "degC": "degree_Celsius", "°C": "degree_Celsius",
}


@dataclass(frozen=True)
class Unit:
    """A unit as read from a word: pint's name for it, and the word pint reads it from."""

    name: str
    word: str = field(compare=False)
    parsed: pint.Unit | None = field(default=None, compare=False, repr=False)

    @property
    def pint_unit(self) -> pint.Unit:
        return self.parsed if self.parsed is not None else registry().parse_units(self.word)


@functools.cache
def registry() -> pint.UnitRegistry[Any]:
    import pickle

    import pint

    # Parsing pint's definitions costs ~0.4 s of CPU on every `countersign validate`; pint's own
    # disk cache (a pickle of the parsed definitions, keyed by their hash) cuts that to ~0.02 s.
    # The cache is written without locking, so a half-written file read by a concurrent process,
    # or a folder that cannot be written, falls back to parsing as before.
    try:
        return pint.UnitRegistry(cache_folder=pint_cache_folder())
    except (OSError, EOFError, pickle.UnpicklingError, AttributeError, ValueError):
        return pint.UnitRegistry()


def pint_cache_folder() -> Path:
    """Where pint keeps its parsed definitions: the user's cache folder for Countersign."""
    import platformdirs

    folder = platformdirs.user_cache_path(appname="countersign", appauthor=False) / "pint"
    folder.mkdir(parents=True, exist_ok=True)
    return folder


# Bounded: the words come from user text, and a server reads many orders.
@functools.lru_cache(maxsize=1024)
def parse_unit(word: str) -> Unit | None:
    """The unit a word names, or None when it names none (or reads as an English word)."""
    word = " ".join(word.split())
    if word.startswith("°"):
        word = word.replace(" ", "")  # "° C" is "°C"
    if not word or word.lower() in _NOT_UNITS:
        return None
    name = _ALIASES.get(word) or _ALIASES.get(word.lower()) or word
    if name in KNOWN:
        return Unit(KNOWN[name], name)
    import pint

    try:
        unit: pint.Unit = registry().parse_units(name)
    except (pint.errors.PintError, AttributeError, TypeError, ValueError, SyntaxError):
        return None
    return Unit(str(unit), name, unit)


def unit_of_quantity(name: str, declared: str) -> Unit | None:
    """A quantity's unit: the one declared (in the orders or the built-in vocabulary), else the
    one its name ends with (`lane_distance_m`, `transit_time_min`)."""
    if declared:
        return parse_unit(declared)
    head, sep, suffix = name.rpartition("_")
    return parse_unit(suffix) if sep and head else None


def convert(value: float, source: Unit, target: Unit) -> float | None:
    """`value` in `source` expressed in `target`, or None when they measure different things."""
    if source.name == target.name:
        return float(value)  # what pint gives too: the value unchanged
    import pint

    try:
        magnitude = registry().Quantity(value, source.pint_unit).to(target.pint_unit).magnitude
    except pint.errors.DimensionalityError:
        return None
    return float(magnitude)


def same_number(a: float, b: float) -> bool:
    return math.isclose(a, b, rel_tol=REL_TOL, abs_tol=1e-12)
