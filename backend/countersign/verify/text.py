"""TEXT (warning): a constraint's or norm's text and its checked condition disagree.

The supervisor reads the text; the vehicle tests the condition. When the text names a number
the condition does not contain ("at least 2 m" over `altitude_m >= 0.5`), or a quantity in
a unit that gives another number once converted to the unit the condition reads ("20 feet" over
`depth_m >= 20`, "4 knots" over `speed_mps <= 4`), or a unit of another kind than any quantity
the condition reads ("20 minutes" over `depth_m >= 20`), the two say different things and the
supervisor must be told before signing. "1 km" over `lane_distance_m >= 1000` says the same.
Converted numbers meet within `units.REL_TOL`, so limits rounded after conversion still agree.
"""

from __future__ import annotations

import re
from collections.abc import Iterator, Mapping
from dataclasses import dataclass
from fractions import Fraction
from typing import TYPE_CHECKING

from ..orders.expressions import number_words, with_unit
from ..orders.findings import Finding, warning
from ..orders.model import Orders, Quantity
from .expressions import ExprError, Name, Num, parse, quantity_table, walk

if TYPE_CHECKING:
    from .units import Unit

# A number as people write it ("1000", "1,000", "2.5"), then an optional unit ("km", "m/s",
# "°C", "nautical miles"); whether that word is a unit at all is for pint to say.
_NUMBER = re.compile(
    r"(?<![\w.])(\d{1,3}(?:,\d{3})+|\d+(?:\.\d+)?)"
    r"(?:\s*(%|°\s*[CcFf](?![A-Za-z])|°|nautical\s+miles?|[A-Za-z]+(?:/[A-Za-z]+)?))?"
)


@dataclass(frozen=True)
class _Condition:
    numbers: frozenset[Fraction]
    # The units of the quantities it reads, each as declared (for the message) and as read.
    units: tuple[tuple[str, Unit], ...] = ()


def _parsed(source: str) -> tuple[frozenset[Fraction], frozenset[str]] | None:
    """The numbers a condition contains and the names it reads."""
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
    return frozenset(numbers), frozenset(names)


def _units(names: frozenset[str], quantities: Mapping[str, Quantity]) -> dict[str, Unit]:
    from .units import unit_of_quantity

    units: dict[str, Unit] = {}
    for name in sorted(names):
        spec = quantities.get(name)
        declared = spec.unit if spec is not None else ""
        unit = unit_of_quantity(name, declared)
        if unit is not None:
            units.setdefault(declared or name.rpartition("_")[2], unit)
    return units


@dataclass(frozen=True)
class _Written:
    raw: str  # the number as written
    said: str  # the number and its unit as written
    value: Fraction
    word: str | None


def _written(text: str) -> Iterator[_Written]:
    for match in _NUMBER.finditer(text):
        raw = match.group(1)
        yield _Written(raw, " ".join(match.group(0).split()), Fraction(raw.replace(",", "")),
                       match.group(2))


def _problem(written: _Written, condition: _Condition) -> str | None:
    """Why the number written disagrees with the condition, or None when it agrees."""
    from .units import convert, parse_unit, same_number

    raw, said, value, word = written.raw, written.said, written.value, written.word
    unit = parse_unit(word) if word is not None and condition.units else None
    if unit is None:
        # No unit to convert (or nothing to convert it to): the number itself must be there.
        if value in condition.numbers:
            return None
        return f"the text says {raw} but the condition contains no {raw}"
    converted = [(name, v) for name, target in condition.units
                 if (v := convert(float(value), unit, target)) is not None]
    if not converted:
        reads = ", ".join(name for name, _ in condition.units)
        return (f"the text says {said} but the condition reads only quantities in {reads}, "
                f"which {word} cannot be converted to")
    if any(same_number(v, float(n)) for _, v in converted for n in condition.numbers):
        return None
    name, v = converted[0]
    if same_number(v, float(value)):
        return f"the text says {said} but the condition contains no {raw}"
    amount = number_words(float(f"{v:.4g}"))
    return (f"the text says {said}, which is {with_unit(amount, name)}, but the condition "
            f"contains no {amount}")


def disagreements(
    text: str, source: str | None, quantities: Mapping[str, Quantity]
) -> list[str]:
    """What the text says that the condition does not: one phrase per mismatch."""
    if not text.strip() or source is None:
        return []
    parsed = _parsed(source)
    if parsed is None:
        return []
    numbers, names = parsed
    written = list(_written(text))
    # Units (and pint) only when the text writes one.
    units = _units(names, quantities) if any(w.word for w in written) else {}
    condition = _Condition(numbers, tuple(units.items()))
    problems = [p for w in written if (p := _problem(w, condition)) is not None]
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
