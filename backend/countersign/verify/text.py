"""TEXT (warning): a constraint's or norm's text and its checked condition disagree.

The supervisor reads the text; the vehicle tests the condition. When the text names a number
the condition does not contain ("at least 2 m" over `altitude_m >= 0.5`), or a unit that no
quantity the condition reads is measured in ("20 feet" over `depth_m >= 20`), the two say
different things and the supervisor must be told before signing.
"""

from __future__ import annotations

import re
from collections.abc import Iterator, Mapping
from fractions import Fraction

from ..orders.findings import Finding, warning
from ..orders.model import Orders, Quantity
from .expressions import ExprError, Name, Num, parse, quantity_table, walk

# A number as people write it ("1000", "1,000", "2.5"), then an optional unit word.
_NUMBER = re.compile(r"(?<![\w.])(\d{1,3}(?:,\d{3})+|\d+(?:\.\d+)?)(?:\s*(%|°|[A-Za-z]+))?")

# Unit words of the text, by the unit symbol a quantity declares.
_UNITS: dict[str, str] = {}
for _symbol, _words in {
    "m": ("m", "meter", "meters", "metre", "metres"),
    "km": ("km", "kilometer", "kilometers", "kilometre", "kilometres"),
    "nmi": ("nmi", "nm", "nautical"),
    "ft": ("ft", "foot", "feet"),
    "s": ("s", "sec", "second", "seconds"),
    "min": ("min", "minute", "minutes"),
    "h": ("h", "hr", "hour", "hours"),
    "kn": ("kn", "kt", "kts", "knot", "knots"),
    "m/s": ("mps",),
    "Wh": ("wh",),
    "kWh": ("kwh",),
    "W": ("w", "watt", "watts"),
    "%": ("%", "percent"),
    "deg": ("°", "deg", "degree", "degrees"),
    "C": ("celsius",),
}.items():
    for _word in _words:
        _UNITS[_word.lower()] = _symbol


def _numbers_in(source: str) -> tuple[set[Fraction], set[str]] | None:
    """The numbers a condition contains and the units of the quantities it reads."""
    try:
        expr = parse(source)
    except ExprError:
        return None  # EXPR reports it
    numbers: set[Fraction] = set()
    names: set[str] = set()
    for node in walk(expr):
        if isinstance(node, Num):
            numbers.add(node.value)
        elif isinstance(node, Name):
            names.add(node.name)
    return numbers, names


def _written(text: str) -> Iterator[tuple[str, Fraction, str | None]]:
    for match in _NUMBER.finditer(text):
        raw, unit_word = match.group(1), match.group(2)
        unit = _UNITS.get(unit_word.lower()) if unit_word else None
        yield raw, Fraction(raw.replace(",", "")), unit


def disagreements(
    text: str, source: str | None, quantities: Mapping[str, Quantity]
) -> list[str]:
    """What the text says that the condition does not: one phrase per mismatch."""
    if not text.strip() or source is None:
        return []
    found = _numbers_in(source)
    if found is None:
        return []
    numbers, names = found
    units = {quantities[n].unit for n in names if n in quantities and quantities[n].unit}
    problems: list[str] = []
    for raw, value, unit in _written(text):
        if value not in numbers:
            problems.append(f"the text says {raw} but the condition contains no {raw}")
        elif unit is not None and units and unit not in units:
            problems.append(
                f"the text says {raw} in {unit} but the condition reads "
                f"{', '.join(sorted(units))}"
            )
    return list(dict.fromkeys(problems))


def check_text(orders: Orders) -> list[Finding]:
    quantities = quantity_table(orders)
    findings: list[Finding] = []
    for constraint in orders.constraints:
        problems = disagreements(constraint.text, constraint.expr, quantities)
        if problems:
            findings.append(warning(
                "TEXT", [constraint.id],
                f"Constraint {constraint.id}: {'; '.join(problems)} (`{constraint.expr}`). "
                "The supervisor reads the text; the vehicle tests the condition.",
                problems=problems,
            ))
    for norm in orders.norms:
        rule = norm.forbidden or norm.obligated or norm.permitted
        problems = disagreements(norm.text, rule, quantities)
        if problems:
            findings.append(warning(
                "TEXT", [norm.id],
                f"Norm {norm.id}: {'; '.join(problems)} (`{rule}`). "
                "The supervisor reads the text; the vehicle tests the condition.",
                problems=problems,
            ))
    return findings
