"""Literals of a default theory: `atom`, `atom(arg)`, `not atom(arg)`; read without eval.

An argument that starts with an upper-case letter is a variable (`safety_sensor_failure(X)`);
rules holding variables are grounded over the constants the theory and the observations name.
"""

from __future__ import annotations

import re
from dataclasses import dataclass

_LITERAL = re.compile(
    r"\s*(?P<neg>(?:not\s+|¬\s*|~\s*))?(?P<name>[a-z_][A-Za-z0-9_]*)"
    r"(?:\s*\(\s*(?P<arg>[A-Za-z0-9_]+)\s*\))?\s*"
)
MAX_LITERAL = 200


class LiteralSyntaxError(ValueError):
    pass


@dataclass(frozen=True, slots=True)
class Literal:
    name: str
    arg: str | None = None
    positive: bool = True

    @property
    def atom(self) -> str:
        return self.name if self.arg is None else f"{self.name}({self.arg})"

    @property
    def has_variable(self) -> bool:
        return self.arg is not None and is_variable(self.arg)

    def negated(self) -> Literal:
        return Literal(self.name, self.arg, not self.positive)

    def bind(self, variable: str, constant: str) -> Literal:
        if self.arg != variable:
            return self
        return Literal(self.name, constant, self.positive)

    def __str__(self) -> str:
        return self.atom if self.positive else f"not {self.atom}"


def is_variable(arg: str) -> bool:
    return arg[:1].isupper()


def parse_literal(text: object) -> Literal:
    """One literal; raises LiteralSyntaxError saying what is wrong (the caller adds the path)."""
    if not isinstance(text, str):
        raise LiteralSyntaxError(f"expected a literal as text, got {type(text).__name__}")
    if len(text) > MAX_LITERAL:
        raise LiteralSyntaxError(f"a literal may have at most {MAX_LITERAL} characters")
    match = _LITERAL.fullmatch(text)
    if match is None:
        raise LiteralSyntaxError(
            f"{text[:60]!r} is not a literal: write atom, atom(arg) or not atom(arg) "
            "(names start with a lower-case letter or _)"
        )
    return Literal(match["name"], match["arg"], match["neg"] is None)


def parse_atom(text: object) -> Literal:
    """An atom (no negation), e.g. an observation key or an observable declaration."""
    literal = parse_literal(text)
    if not literal.positive:
        raise LiteralSyntaxError(f"{text!r}: expected an atom without `not`")
    return literal
