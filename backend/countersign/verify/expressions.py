"""The expression language of mission orders (DESIGN.md, Orders format): a safe parser, a type
checker with units, a partial evaluator and a translation to SMT-LIB for z3.

    depth_m >= 20 or lane_distance_m >= 1000
    not (behavior == 'surface' and context('shipping_lane'))
    battery_reserve_pct >= 20 implies speed_mps <= 2.5

Numbers, quoted strings, `true`/`false`, quantity names, `behavior`, `area`, `context('tag')`,
`+ - * /`, comparisons (`== != < <= > >=`, chains such as `3 <= altitude_m <= 12`), `not`,
`and`, `or` and `implies` (weakest, right-associative). Nothing is ever evaluated by Python's
`eval`: text becomes tokens, tokens become a small immutable tree, and the tree is checked
against the quantities the orders declare (plus a built-in maritime vocabulary).

Every error carries the 1-based column where it was found, so a finding can say
"C4, column 19: expected a value after '>='". Pathological input is bounded before it costs
anything: the text length, the nesting depth, the number of terms and the size of each number
are limited, and the tree is flat for long chains of `and`, `or`, `+` and `*`, so that no
later recursion goes deeper than the nesting the author wrote.
"""

from __future__ import annotations

import difflib
import math
import unicodedata
from collections.abc import Callable, Iterator, Mapping
from dataclasses import dataclass
from fractions import Fraction
from functools import lru_cache
from typing import Literal, cast

from ..orders.model import Orders, Quantity

MAX_LENGTH = 10_000
MAX_DEPTH = 40
MAX_TERMS = 1_000
MAX_TOKENS = 4 * MAX_TERMS
MAX_DIGITS = 30
MAX_EXPONENT = 30

Kind = Literal["boolean", "integer", "real", "string"]

# ---------------------------------------------------------------------------------------------
# Built-in maritime vocabulary: names, types, units and physical domains that orders may use
# without declaring them. An entry in the orders' own `quantities` replaces the built-in one.

MARITIME_QUANTITIES: dict[str, Quantity] = {
    name: Quantity.model_validate(spec)
    for name, spec in {
        "depth_m": {"unit": "m", "min": 0, "title": "depth"},
        "altitude_m": {"unit": "m", "min": 0, "title": "altitude above the seabed"},
        "speed_mps": {"unit": "m/s", "min": 0, "title": "speed"},
        "heading_deg": {"unit": "deg", "min": 0, "max": 360, "title": "heading"},
        "pitch_deg": {"unit": "deg", "min": -90, "max": 90, "title": "pitch"},
        "roll_deg": {"unit": "deg", "min": -180, "max": 180, "title": "roll"},
        "latitude_deg": {"unit": "deg", "min": -90, "max": 90, "title": "latitude"},
        "longitude_deg": {"unit": "deg", "min": -180, "max": 180, "title": "longitude"},
        "lane_distance_m": {"unit": "m", "min": 0,
                            "title": "distance to the nearest shipping lane"},
        "contact_distance_m": {"unit": "m", "min": 0,
                               "title": "distance to the nearest surface contact"},
        "contact_detection_range_m": {"unit": "m", "min": 0,
                                      "title": "surface contact detection range"},
        "contact_count": {"type": "integer", "min": 0, "title": "number of surface contacts"},
        "shore_distance_m": {"unit": "m", "min": 0, "title": "distance to shore"},
        "base_distance_m": {"unit": "m", "min": 0, "title": "distance to the recovery point"},
        "nav_error_m": {"unit": "m", "min": 0, "title": "navigation error"},
        "current_mps": {"unit": "m/s", "min": 0, "title": "water current"},
        "wave_height_m": {"unit": "m", "min": 0, "title": "wave height"},
        "sea_state": {"type": "integer", "min": 0, "max": 9, "title": "sea state"},
        "visibility_m": {"unit": "m", "min": 0, "title": "visibility"},
        "water_temperature_c": {"unit": "degC", "min": -5, "max": 45,
                                "title": "water temperature"},
        "battery_pct": {"unit": "%", "min": 0, "max": 100, "title": "battery charge"},
        "battery_reserve_pct": {"unit": "%", "min": 0, "max": 100, "title": "battery reserve"},
        "energy_wh": {"unit": "Wh", "min": 0, "title": "energy used"},
        "duration_s": {"unit": "s", "min": 0, "title": "elapsed time"},
        "elapsed_s": {"unit": "s", "min": 0, "title": "elapsed time"},
        "comms_ok": {"type": "boolean", "title": "communications link up"},
        "gps_fix": {"type": "boolean", "title": "GPS fix"},
        "surfaced": {"type": "boolean", "title": "surfaced"},
        "safety_equipment_ok": {"type": "boolean", "title": "safety equipment functional"},
        "mission_systems_ok": {"type": "boolean", "title": "mission systems operational"},
    }.items()
}


def quantity_table(orders: Orders) -> dict[str, Quantity]:
    """Every quantity an expression in these orders may read: the built-in vocabulary, then
    the orders' own declarations (which win), then names that only appear in an envelope or
    that a feature of the target vehicle measures (real numbers without a domain)."""
    table = dict(MARITIME_QUANTITIES)
    table.update(orders.quantities)
    implicit: list[str] = []
    for goal in orders.goals:
        implicit.extend(goal.envelope)
    vehicle = orders.target_vehicle()
    if vehicle is not None:
        implicit.extend(vehicle.envelope)
        for feature in vehicle.features:
            implicit.extend(feature.measures)
    for name in implicit:
        if name not in table:
            table[name] = Quantity()
    return table


# ---------------------------------------------------------------------------------------------
# Errors


class ExprError(ValueError):
    """A syntax or type error at a 1-based column of the expression text."""

    def __init__(self, message: str, column: int) -> None:
        super().__init__(message)
        self.message = message
        self.column = column

    def located(self, label: str) -> str:
        return f"{label}, column {self.column}: {self.message}"


# ---------------------------------------------------------------------------------------------
# Tree: small immutable nodes; `col` is the 1-based column where the node starts.


@dataclass(frozen=True, slots=True)
class Num:
    value: Fraction
    integral: bool
    col: int


@dataclass(frozen=True, slots=True)
class Text:
    value: str
    col: int


@dataclass(frozen=True, slots=True)
class Truth:
    value: bool
    col: int


@dataclass(frozen=True, slots=True)
class Name:
    """A quantity."""

    name: str
    col: int


@dataclass(frozen=True, slots=True)
class Special:
    """`behavior` or `area`: the goal's behaviour string or area id."""

    name: Literal["behavior", "area"]
    col: int


@dataclass(frozen=True, slots=True)
class Context:
    """`context('tag')`: true when the goal's area carries the tag."""

    tag: str
    col: int


@dataclass(frozen=True, slots=True)
class Neg:
    operand: Expr
    col: int


@dataclass(frozen=True, slots=True)
class Not:
    operand: Expr
    col: int


@dataclass(frozen=True, slots=True)
class Sum:
    """terms[0] is ('+', first); the rest are ('+' | '-', term), folded left."""

    terms: tuple[tuple[str, Expr], ...]
    col: int


@dataclass(frozen=True, slots=True)
class Product:
    """factors[0] is ('*', first); the rest are ('*' | '/', factor), folded left."""

    factors: tuple[tuple[str, Expr], ...]
    col: int


@dataclass(frozen=True, slots=True)
class Compare:
    """operands[0] ops[0] operands[1] ops[1] operands[2] ...: a chain means `and`."""

    operands: tuple[Expr, ...]
    ops: tuple[str, ...]
    col: int


@dataclass(frozen=True, slots=True)
class Logic:
    op: Literal["and", "or"]
    operands: tuple[Expr, ...]
    col: int


@dataclass(frozen=True, slots=True)
class Implies:
    """operands[0] implies (operands[1] implies (...))."""

    operands: tuple[Expr, ...]
    col: int


Expr = Num | Text | Truth | Name | Special | Context | Neg | Not | Sum | Product | Compare \
    | Logic | Implies

# ---------------------------------------------------------------------------------------------
# Tokens

_ASCII_LETTERS = frozenset("abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ_")
_ASCII_DIGITS = frozenset("0123456789")
_TWO_CHAR = {">=", "<=", "==", "!="}
_ONE_CHAR = set("+-*/<>(),")
_KEYWORDS = {"and", "or", "not", "implies", "true", "false"}
RESERVED = _KEYWORDS | {"behavior", "behaviour", "area", "context"}

# Characters people paste from documents, with what they meant.
_LOOKALIKES = {
    "≥": ">=", "≤": "<=", "≠": "!=", "＝": "==", "−": "-", "–": "-", "—": "-", "×": "*",
    "÷": "/", "⇒": "implies", "→": "implies", "∧": "and", "∨": "or", "¬": "not",
    "‘": "'", "’": "'", "“": '"', "”": '"', "（": "(", "）": ")", "＜": "<", "＞": ">",
    "＋": "+", "＊": "*", "／": "/", "，": ",",
}
_ASCII_HINTS = {
    "&&": "and", "||": "or", "=>": "implies", "->": "implies", "=": "==", "!": "not",
    "&": "and", "|": "or", "^": "nothing: powers are not supported", "%": "nothing: "
    "use / for division",
}


@dataclass(frozen=True, slots=True)
class Token:
    kind: Literal["num", "str", "name", "op", "end"]
    text: str
    col: int
    value: object = None


def _char_name(char: str) -> str:
    return unicodedata.name(char, f"U+{ord(char):04X}")


def _unexpected_char(char: str, col: int, source: str) -> ExprError:
    if char in _LOOKALIKES:
        return ExprError(
            f"{char!r} ({_char_name(char)}) is not allowed; write {_LOOKALIKES[char]!r}", col
        )
    pair = source[col - 1:col + 1]
    for text in (pair, char):
        if text in _ASCII_HINTS:
            return ExprError(f"{text!r} is not an operator here; use {_ASCII_HINTS[text]}", col)
    if unicodedata.category(char).startswith("L"):
        return ExprError(
            f"{char!r} ({_char_name(char)}) looks like a letter but is not ASCII; names use "
            "only the letters a-z and A-Z, digits and _",
            col,
        )
    if unicodedata.category(char).startswith("N"):
        return ExprError(f"{char!r} ({_char_name(char)}) is not an ASCII digit", col)
    if unicodedata.category(char) in {"Cc", "Cf", "Zl", "Zp", "Co", "Cs", "Cn"}:
        return ExprError(f"invisible or control character U+{ord(char):04X}", col)
    return ExprError(f"unexpected character {char!r} ({_char_name(char)})", col)


def _number(source: str, start: int) -> tuple[Token, int]:
    i = start
    n = len(source)
    while i < n and source[i] in _ASCII_DIGITS:
        i += 1
    if i < n and source[i] == ".":
        i += 1
        while i < n and source[i] in _ASCII_DIGITS:
            i += 1
    mantissa = source[start:i]
    exponent = 0
    if i < n and source[i] in "eE":
        j = i + 1
        if j < n and source[j] in "+-":
            j += 1
        if j < n and source[j] in _ASCII_DIGITS:
            k = j
            while k < n and source[k] in _ASCII_DIGITS:
                k += 1
            digits = source[j:k]
            if len(digits) > 6 or int(digits) > MAX_EXPONENT:
                raise ExprError(
                    f"the number {source[start:k]} is out of range (exponents up to "
                    f"{MAX_EXPONENT})",
                    start + 1,
                )
            exponent = int(source[i + 1:k])
            i = k
    text = source[start:i]
    if mantissa in {".", ""}:
        raise ExprError("expected digits in a number", start + 1)
    significant = mantissa.replace(".", "").lstrip("0")
    if len(significant) > MAX_DIGITS:
        raise ExprError(
            f"the number {text[:20]}... has more than {MAX_DIGITS} digits", start + 1
        )
    value = Fraction(mantissa) * Fraction(10) ** exponent
    integral = "." not in mantissa and exponent >= 0
    if i < n and (source[i] in _ASCII_LETTERS or source[i] in _ASCII_DIGITS):
        raise ExprError(
            f"a number cannot run into a name ({source[start:i + 1]!r}); "
            "units belong in the quantity's name",
            start + 1,
        )
    return Token("num", text, start + 1, (value, integral)), i


def _string(source: str, start: int) -> tuple[Token, int]:
    quote = source[start]
    i = start + 1
    out: list[str] = []
    n = len(source)
    while i < n:
        char = source[i]
        if char == "\\" and i + 1 < n and source[i + 1] in (quote, "\\"):
            out.append(source[i + 1])
            i += 2
            continue
        if char == quote:
            return Token("str", source[start:i + 1], start + 1, "".join(out)), i + 1
        if char == "\n":
            break
        out.append(char)
        i += 1
    raise ExprError(f"the text starting with {quote} is never closed", start + 1)


def tokenize(source: str) -> Iterator[Token]:
    i = 0
    n = len(source)
    while i < n:
        char = source[i]
        if char in " \t\r\n":
            i += 1
            continue
        if char in _ASCII_DIGITS or (char == "." and i + 1 < n and source[i + 1] in _ASCII_DIGITS):
            token, i = _number(source, i)
            yield token
            continue
        if char in _ASCII_LETTERS:
            j = i + 1
            while j < n and (source[j] in _ASCII_LETTERS or source[j] in _ASCII_DIGITS):
                j += 1
            if j < n and unicodedata.category(source[j]).startswith("L") and source[j] > "\x7f":
                raise _unexpected_char(source[j], j + 1, source)
            yield Token("name", source[i:j], i + 1)
            i = j
            continue
        if char in "'\"":
            token, i = _string(source, i)
            yield token
            continue
        pair = source[i:i + 2]
        if pair in _TWO_CHAR:
            yield Token("op", pair, i + 1)
            i += 2
            continue
        if pair in {"=>", "->", "&&", "||"}:
            raise _unexpected_char(char, i + 1, source)
        if char in _ONE_CHAR:
            yield Token("op", char, i + 1)
            i += 1
            continue
        raise _unexpected_char(char, i + 1, source)
    yield Token("end", "", n + 1)


# ---------------------------------------------------------------------------------------------
# Parser: recursive descent, one function per precedence level, explicit depth and size limits.

_COMPARISONS = {"==", "!=", "<", "<=", ">", ">="}


def _describe(token: Token) -> str:
    if token.kind == "end":
        return "the end"
    return repr(token.text)


class _Parser:
    def __init__(self, source: str) -> None:
        self.tokens = list(_bounded_tokens(source))
        self.pos = 0
        self.depth = 0
        self.terms = 0

    @property
    def token(self) -> Token:
        return self.tokens[self.pos]

    def _advance(self) -> Token:
        token = self.tokens[self.pos]
        self.pos += 1
        return token

    def _is(self, kind: str, *texts: str) -> bool:
        token = self.token
        if token.kind != kind:
            return False
        if kind == "name":
            return token.text.lower() in texts
        return not texts or token.text in texts

    def _enter(self, col: int) -> None:
        self.depth += 1
        if self.depth > MAX_DEPTH:
            raise ExprError(f"the expression nests more than {MAX_DEPTH} levels deep", col)

    def parse(self) -> Expr:
        if self.token.kind == "end":
            raise ExprError("the expression is empty", 1)
        expr = self._implication()
        token = self.token
        if token.kind != "end":
            if token.text == ")":
                raise ExprError("this ')' closes nothing", token.col)
            previous = self.tokens[self.pos - 1]
            raise ExprError(
                f"expected an operator after {_describe(previous)}, found {_describe(token)}",
                token.col,
            )
        return expr

    def _operand_after(self, op: Token, parse: Callable[[], Expr]) -> Expr:
        token = self.token
        if token.kind == "end" or (token.kind == "op" and token.text not in "(-+") or (
            token.kind == "name" and token.text.lower() in {"and", "or", "implies"}
        ):
            raise ExprError(f"expected a value after {op.text!r}", token.col)
        return parse()

    def _implication(self) -> Expr:
        first = self._disjunction()
        operands = [first]
        while self._is("name", "implies"):
            op = self._advance()
            operands.append(self._operand_after(op, self._disjunction))
        if len(operands) == 1:
            return first
        return Implies(tuple(operands), first_col(first))

    def _disjunction(self) -> Expr:
        first = self._conjunction()
        operands = [first]
        while self._is("name", "or"):
            op = self._advance()
            operands.append(self._operand_after(op, self._conjunction))
        return first if len(operands) == 1 else Logic("or", tuple(operands), first_col(first))

    def _conjunction(self) -> Expr:
        first = self._negation()
        operands = [first]
        while self._is("name", "and"):
            op = self._advance()
            operands.append(self._operand_after(op, self._negation))
        return first if len(operands) == 1 else Logic("and", tuple(operands), first_col(first))

    def _negation(self) -> Expr:
        nots: list[Token] = []
        while self._is("name", "not"):
            nots.append(self._advance())
            self._enter(nots[-1].col)
        if nots:
            operand = self._operand_after(nots[-1], self._comparison)
            for token in reversed(nots):
                operand = Not(operand, token.col)
            self.depth -= len(nots)
            return operand
        return self._comparison()

    def _comparison(self) -> Expr:
        first = self._sum()
        operands = [first]
        ops: list[str] = []
        while self.token.kind == "op" and self.token.text in _COMPARISONS:
            op = self._advance()
            ops.append(op.text)
            operands.append(self._operand_after(op, self._sum))
        if not ops:
            return first
        return Compare(tuple(operands), tuple(ops), first_col(first))

    def _sum(self) -> Expr:
        first = self._product()
        terms: list[tuple[str, Expr]] = [("+", first)]
        while self.token.kind == "op" and self.token.text in "+-":
            op = self._advance()
            terms.append((op.text, self._operand_after(op, self._product)))
        return first if len(terms) == 1 else Sum(tuple(terms), first_col(first))

    def _product(self) -> Expr:
        first = self._unary()
        factors: list[tuple[str, Expr]] = [("*", first)]
        while self.token.kind == "op" and self.token.text in "*/":
            op = self._advance()
            factors.append((op.text, self._operand_after(op, self._unary)))
        return first if len(factors) == 1 else Product(tuple(factors), first_col(first))

    def _unary(self) -> Expr:
        signs: list[Token] = []
        while self.token.kind == "op" and self.token.text in "+-":
            signs.append(self._advance())
            self._enter(signs[-1].col)
        if signs:
            operand = self._operand_after(signs[-1], self._primary)
            for token in reversed(signs):
                if token.text == "-":
                    operand = Neg(operand, token.col)
            self.depth -= len(signs)
            return operand
        return self._primary()

    def _count_term(self, col: int) -> None:
        self.terms += 1
        if self.terms > MAX_TERMS:
            raise ExprError(f"the expression has more than {MAX_TERMS:,} terms", col)

    def _primary(self) -> Expr:
        token = self.token
        if token.kind == "num":
            self._advance()
            self._count_term(token.col)
            value, integral = cast(tuple[Fraction, bool], token.value)
            return Num(value, integral, token.col)
        if token.kind == "str":
            self._advance()
            self._count_term(token.col)
            return Text(str(token.value), token.col)
        if token.kind == "op" and token.text == "(":
            self._advance()
            self._enter(token.col)
            if self.token.kind == "op" and self.token.text == ")":
                raise ExprError("expected a value inside '()'", self.token.col)
            inner = self._implication()
            if not (self.token.kind == "op" and self.token.text == ")"):
                found = self.token
                if found.kind == "end":
                    raise ExprError(
                        f"the '(' at column {token.col} is never closed", found.col
                    )
                raise ExprError(
                    f"expected ')' to close the '(' at column {token.col}, found "
                    f"{_describe(found)}",
                    found.col,
                )
            self._advance()
            self.depth -= 1
            return inner
        if token.kind == "name":
            return self._name()
        if token.kind == "end":
            previous = self.tokens[self.pos - 1] if self.pos else token
            raise ExprError(f"expected a value after {previous.text!r}", token.col)
        raise ExprError(f"expected a value, found {_describe(token)}", token.col)

    def _name(self) -> Expr:
        token = self._advance()
        self._count_term(token.col)
        word = token.text
        lower = word.lower()
        if lower in {"true", "false"}:
            return Truth(lower == "true", token.col)
        if lower in {"and", "or", "implies"}:
            raise ExprError(f"expected a value before {word!r}", token.col)
        if word in {"behavior", "behaviour"}:
            return Special("behavior", token.col)
        if word == "area":
            return Special("area", token.col)
        if self.token.kind == "op" and self.token.text == "(":
            if word != "context":
                raise ExprError(
                    f"unknown function {word!r}; the only function is context('tag')", token.col
                )
            self._advance()
            argument = self.token
            if argument.kind != "str":
                raise ExprError(
                    "context() takes one quoted area tag, e.g. context('shipping_lane')",
                    argument.col,
                )
            self._advance()
            if not (self.token.kind == "op" and self.token.text == ")"):
                raise ExprError(
                    "context() takes one quoted area tag and then ')'", self.token.col
                )
            self._advance()
            return Context(str(argument.value), token.col)
        if word == "context":
            raise ExprError("context needs a tag: context('shipping_lane')", token.col)
        return Name(word, token.col)


def _bounded_tokens(source: str) -> Iterator[Token]:
    if len(source) > MAX_LENGTH:
        raise ExprError(f"the expression is longer than {MAX_LENGTH:,} characters", 1)
    for count, token in enumerate(tokenize(source), 1):
        if count > MAX_TOKENS:
            raise ExprError(
                f"the expression is too long: more than {MAX_TOKENS:,} symbols", token.col
            )
        yield token


def first_col(expr: Expr) -> int:
    return expr.col


@lru_cache(maxsize=4096)
def _parse_cached(source: str) -> Expr | ExprError:
    try:
        return _Parser(source).parse()
    except ExprError as exc:
        return exc
    except RecursionError:
        return ExprError("the expression nests too deeply", 1)


def parse(source: str) -> Expr:
    """The tree of an expression, or ExprError with the column of the first problem."""
    result = _parse_cached(source)
    if isinstance(result, ExprError):
        raise ExprError(result.message, result.column)
    return result


# ---------------------------------------------------------------------------------------------
# What an expression reads


@dataclass(frozen=True)
class Reads:
    quantities: frozenset[str]
    tags: frozenset[str]
    behavior: bool
    area: bool


def walk(expr: Expr) -> Iterator[Expr]:
    """Every node, parents before children (iterative: never deeper than the Python stack)."""
    stack: list[Expr] = [expr]
    while stack:
        node = stack.pop()
        yield node
        if isinstance(node, Neg | Not):
            stack.append(node.operand)
        elif isinstance(node, Sum):
            stack.extend(term for _, term in reversed(node.terms))
        elif isinstance(node, Product):
            stack.extend(factor for _, factor in reversed(node.factors))
        elif isinstance(node, Compare | Logic | Implies):
            stack.extend(reversed(node.operands))


def reads(expr: Expr) -> Reads:
    quantities: set[str] = set()
    tags: set[str] = set()
    behavior = area = False
    for node in walk(expr):
        if isinstance(node, Name):
            quantities.add(node.name)
        elif isinstance(node, Context):
            tags.add(node.tag)
        elif isinstance(node, Special):
            if node.name == "behavior":
                behavior = True
            else:
                area = True
    return Reads(frozenset(quantities), frozenset(tags), behavior, area)


def identifiers(expr: Expr | str) -> frozenset[str]:
    """The quantity names an expression reads (not `behavior`, `area` or context tags).
    Text that does not parse reads nothing here; the EXPR finding reports it."""
    if isinstance(expr, str):
        try:
            expr = parse(expr)
        except ExprError:
            return frozenset()
    return reads(expr).quantities


# ---------------------------------------------------------------------------------------------
# Types and units


@dataclass(frozen=True, slots=True)
class Typed:
    kind: Kind
    unit: str | None  # None: no unit to compare (a literal, a product, an undeclared unit)


_NUMERIC = ("integer", "real")
_KIND_WORD = {"boolean": "a condition", "integer": "a number", "real": "a number",
              "string": "text"}


def _numeric(kind: Kind) -> bool:
    return kind in _NUMERIC


def _join_units(units: list[tuple[str | None, int]], verb: str) -> str | None:
    known = [(u, col) for u, col in units if u]
    if not known:
        return None
    first, _ = known[0]
    for unit, col in known[1:]:
        if unit != first:
            raise ExprError(f"{verb} {first} with {unit}: the units differ", col)
    return first


class TypeChecker:
    """Checks an expression against a quantity table. Unknown names and type or unit errors
    raise ExprError with the column of the offending part."""

    def __init__(self, quantities: Mapping[str, Quantity]) -> None:
        self.quantities = quantities

    def condition(self, expr: Expr) -> None:
        typed = self.check(expr)
        if typed.kind != "boolean":
            raise ExprError(
                f"this is {_KIND_WORD[typed.kind]}, not a condition (compare it with "
                "something, e.g. depth_m >= 20)",
                expr.col,
            )

    def check(self, expr: Expr) -> Typed:
        if isinstance(expr, Num):
            return Typed("integer" if expr.integral else "real", None)
        if isinstance(expr, Text):
            return Typed("string", None)
        if isinstance(expr, Truth | Context):
            return Typed("boolean", None)
        if isinstance(expr, Special):
            return Typed("string", None)
        if isinstance(expr, Name):
            return self._name(expr)
        if isinstance(expr, Neg):
            inner = self._require_number(expr.operand, "'-'")
            return inner
        if isinstance(expr, Not):
            self._require_condition(expr.operand, "not")
            return Typed("boolean", None)
        if isinstance(expr, Sum):
            return self._sum(expr)
        if isinstance(expr, Product):
            return self._product(expr)
        if isinstance(expr, Compare):
            return self._compare(expr)
        if isinstance(expr, Logic):
            for operand in expr.operands:
                self._require_condition(operand, expr.op)
            return Typed("boolean", None)
        for operand in expr.operands:
            self._require_condition(operand, "implies")
        return Typed("boolean", None)

    def _name(self, expr: Name) -> Typed:
        quantity = self.quantities.get(expr.name)
        if quantity is None:
            hint = ""
            if expr.name.lower() in RESERVED:
                hint = f" (write {expr.name.lower()!r} in lower case)"
            else:
                close = difflib.get_close_matches(expr.name, list(self.quantities), n=1)
                if close:
                    hint = f" (did you mean {close[0]!r}?)"
            raise ExprError(f"unknown quantity {expr.name!r}{hint}", expr.col)
        kind: Kind = "real"
        if quantity.type == "integer":
            kind = "integer"
        elif quantity.type == "boolean":
            kind = "boolean"
        return Typed(kind, quantity.unit or None)

    def _require_number(self, expr: Expr, where: str) -> Typed:
        typed = self.check(expr)
        if not _numeric(typed.kind):
            raise ExprError(f"{where} needs a number, but this is {_KIND_WORD[typed.kind]}",
                            expr.col)
        return typed

    def _require_condition(self, expr: Expr, where: str) -> None:
        typed = self.check(expr)
        if typed.kind != "boolean":
            raise ExprError(
                f"{where!r} needs a condition, but this is {_KIND_WORD[typed.kind]}", expr.col
            )

    def _sum(self, expr: Sum) -> Typed:
        kinds: list[Kind] = []
        units: list[tuple[str | None, int]] = []
        for op, term in expr.terms:
            typed = self._require_number(term, f"{op!r}")
            kinds.append(typed.kind)
            units.append((typed.unit, term.col))
        unit = _join_units(units, "adds")
        return Typed("integer" if all(k == "integer" for k in kinds) else "real", unit)

    def _product(self, expr: Product) -> Typed:
        kinds: list[Kind] = []
        units: list[str | None] = []
        for op, factor in expr.factors:
            typed = self._require_number(factor, f"{op!r}")
            kinds.append(typed.kind)
            units.append(typed.unit)
            if op == "/" and isinstance(factor, Num) and factor.value == 0:
                raise ExprError("division by zero", factor.col)
        divides = any(op == "/" for op, _ in expr.factors)
        kind: Kind = "integer" if all(k == "integer" for k in kinds) and not divides else "real"
        # Scaling by literals keeps the unit (2 * depth_m and depth_m / 2 are in metres);
        # anything else is a derived unit that is not compared.
        scaled = [(op, unit) for (op, factor), unit in zip(expr.factors, units, strict=True)
                  if not isinstance(factor, Num)]
        unit = scaled[0][1] if len(scaled) == 1 and scaled[0][0] == "*" else None
        return Typed(kind, unit)

    def _compare(self, expr: Compare) -> Typed:
        typed = [self.check(operand) for operand in expr.operands]
        for index, op in enumerate(expr.ops):
            left, right = typed[index], typed[index + 1]
            node = expr.operands[index + 1]
            if op in {"==", "!="}:
                if _numeric(left.kind) and _numeric(right.kind):
                    _join_units([(left.unit, 0), (right.unit, node.col)], "compares")
                    continue
                if left.kind != right.kind:
                    raise ExprError(
                        f"{op!r} compares {_KIND_WORD[left.kind]} with "
                        f"{_KIND_WORD[right.kind]}",
                        node.col,
                    )
                continue
            for side, operand in ((left, expr.operands[index]), (right, node)):
                if not _numeric(side.kind):
                    hint = " (text can only be compared with == or !=)" \
                        if side.kind == "string" else ""
                    raise ExprError(
                        f"{op!r} needs numbers, but this is {_KIND_WORD[side.kind]}{hint}",
                        operand.col,
                    )
            _join_units([(left.unit, 0), (right.unit, node.col)], "compares")
        return Typed("boolean", None)


def check_condition(expr: Expr, quantities: Mapping[str, Quantity]) -> None:
    TypeChecker(quantities).condition(expr)


# ---------------------------------------------------------------------------------------------
# Partial evaluation: what the facts of one goal (behaviour, area, area tags) already decide.


@dataclass(frozen=True)
class Facts:
    behavior: str | None
    area: str | None
    tags: frozenset[str]


class _Unknown:
    __slots__ = ()

    def __repr__(self) -> str:
        return "UNKNOWN"


UNKNOWN = _Unknown()
_NO_STRING = object()  # the behaviour or area of a goal that names none: equal to no text

_CMP: dict[str, Callable[[object, object], bool]] = {
    "==": lambda a, b: a == b,
    "!=": lambda a, b: a != b,
    "<": lambda a, b: a < b,  # type: ignore[operator]
    "<=": lambda a, b: a <= b,  # type: ignore[operator]
    ">": lambda a, b: a > b,  # type: ignore[operator]
    ">=": lambda a, b: a >= b,  # type: ignore[operator]
}


def fold(expr: Expr, facts: Facts) -> bool | None:
    """True or False when the goal's facts alone decide a (type-checked) condition, None
    when the answer depends on quantities."""
    value = _evaluate(expr, facts)
    return value if isinstance(value, bool) else None


def _evaluate(expr: Expr, facts: Facts) -> object:
    if isinstance(expr, Num):
        return expr.value
    if isinstance(expr, Text):
        return expr.value
    if isinstance(expr, Truth):
        return expr.value
    if isinstance(expr, Name):
        return UNKNOWN
    if isinstance(expr, Special):
        named = facts.behavior if expr.name == "behavior" else facts.area
        return _NO_STRING if named is None else named
    if isinstance(expr, Context):
        return expr.tag in facts.tags
    if isinstance(expr, Not):
        inner = _evaluate(expr.operand, facts)
        return UNKNOWN if inner is UNKNOWN else not inner
    if isinstance(expr, Neg):
        inner = _evaluate(expr.operand, facts)
        return UNKNOWN if inner is UNKNOWN else -inner  # type: ignore[operator]
    if isinstance(expr, Logic):
        decisive = expr.op == "or"
        unknown = False
        for operand in expr.operands:
            value = _evaluate(operand, facts)
            if value is UNKNOWN:
                unknown = True
            elif value is decisive:
                return decisive
        return UNKNOWN if unknown else not decisive
    if isinstance(expr, Implies):
        result: object = _evaluate(expr.operands[-1], facts)
        for operand in reversed(expr.operands[:-1]):
            premise = _evaluate(operand, facts)
            if premise is False or result is True:
                result = True
            elif premise is True:
                pass
            else:
                result = UNKNOWN
        return result
    if isinstance(expr, Compare):
        values = [_evaluate(operand, facts) for operand in expr.operands]
        unknown = False
        for index, op in enumerate(expr.ops):
            left, right = values[index], values[index + 1]
            if left is UNKNOWN or right is UNKNOWN:
                unknown = True
                continue
            if not _CMP[op](left, right):
                return False
        return UNKNOWN if unknown else True
    if isinstance(expr, Sum):
        total: Fraction = Fraction(0)
        for op, term in expr.terms:
            value = _evaluate(term, facts)
            if value is UNKNOWN:
                return UNKNOWN
            total = total + value if op == "+" else total - value  # type: ignore[operator]
        return total
    product: Fraction = Fraction(1)
    for op, factor in expr.factors:
        value = _evaluate(factor, facts)
        if value is UNKNOWN:
            return UNKNOWN
        if op == "/":
            if value == 0:
                return UNKNOWN
            product = product / value  # type: ignore[operator]
        else:
            product = product * value  # type: ignore[operator]
    return product


# ---------------------------------------------------------------------------------------------
# Translation to SMT-LIB (and to z3 terms through z3's own SMT-LIB reader).


def smt_real(value: Fraction) -> str:
    magnitude = abs(value)
    if magnitude.denominator == 1:
        text = f"{magnitude.numerator}.0"
    else:
        text = f"(/ {magnitude.numerator}.0 {magnitude.denominator}.0)"
    return f"(- {text})" if value < 0 else text


def smt_int(value: int) -> str:
    return f"(- {-value})" if value < 0 else str(value)


class Translator:
    """Translates type-checked expressions to SMT-LIB terms.

    Quantities become constants `|q:name|` (Real, Int or Bool by their declared type),
    `behavior` and `area` Int constants whose values are codes of interned strings, and
    `context('tag')` a Bool constant per tag. A suffix (e.g. "@G1") gives each goal its own
    copy of the state. `symbols` collects every constant used, with its sort, so that a caller
    can declare them before asserting the terms.
    """

    def __init__(self, quantities: Mapping[str, Quantity], strings: dict[str, int] | None = None,
                 suffix: str = "") -> None:
        self.quantities = quantities
        self.strings = strings if strings is not None else {}
        self.suffix = suffix
        self.symbols: dict[str, str] = {}

    def with_suffix(self, suffix: str) -> Translator:
        other = Translator(self.quantities, self.strings, suffix)
        other.symbols = self.symbols
        return other

    # Symbols -----------------------------------------------------------------------------

    def string_code(self, value: str | None) -> int:
        if value is None:
            return -1
        code = self.strings.get(value)
        if code is None:
            code = self.strings[value] = len(self.strings)
        return code

    def quantity(self, name: str) -> tuple[str, Kind]:
        spec = self.quantities.get(name)
        kind: Kind = "real"
        sort = "Real"
        if spec is not None and spec.type == "integer":
            kind, sort = "integer", "Int"
        elif spec is not None and spec.type == "boolean":
            kind, sort = "boolean", "Bool"
        symbol = f"|q:{name}{self.suffix}|"
        self.symbols[symbol] = sort
        return symbol, kind

    def special(self, name: str) -> str:
        symbol = f"|{name}{self.suffix}|"
        self.symbols[symbol] = "Int"
        return symbol

    def context(self, tag: str) -> str:
        symbol = f"|ctx:{self.string_code(tag)}{self.suffix}|"
        self.symbols[symbol] = "Bool"
        return symbol

    def declarations(self, skip: set[str] | None = None) -> str:
        return "".join(
            f"(declare-const {symbol} {sort})"
            for symbol, sort in self.symbols.items()
            if skip is None or symbol not in skip
        )

    # Terms -------------------------------------------------------------------------------

    def condition(self, expr: Expr) -> str:
        text, _ = self.term(expr)
        return text

    def term(self, expr: Expr) -> tuple[str, Kind]:
        if isinstance(expr, Num):
            if expr.integral:
                return smt_int(int(expr.value)), "integer"
            return smt_real(expr.value), "real"
        if isinstance(expr, Text):
            return smt_int(self.string_code(expr.value)), "string"
        if isinstance(expr, Truth):
            return ("true" if expr.value else "false"), "boolean"
        if isinstance(expr, Name):
            return self.quantity(expr.name)
        if isinstance(expr, Special):
            return self.special(expr.name), "string"
        if isinstance(expr, Context):
            return self.context(expr.tag), "boolean"
        if isinstance(expr, Not):
            return f"(not {self.condition(expr.operand)})", "boolean"
        if isinstance(expr, Neg):
            inner, inner_kind = self.term(expr.operand)
            return f"(- {inner})", inner_kind
        if isinstance(expr, Logic):
            parts = " ".join(self.condition(o) for o in expr.operands)
            return f"({expr.op} {parts})", "boolean"
        if isinstance(expr, Implies):
            text = self.condition(expr.operands[-1])
            for operand in reversed(expr.operands[:-1]):
                text = f"(=> {self.condition(operand)} {text})"
            return text, "boolean"
        if isinstance(expr, Compare):
            return self._compare(expr), "boolean"
        if isinstance(expr, Sum):
            items = [(op, *self.term(t)) for op, t in expr.terms]
            kind: Kind = "integer" if all(k == "integer" for _, _, k in items) else "real"
            text = self._coerce(items[0][1], items[0][2], kind)
            for op, term, term_kind in items[1:]:
                text = f"({op} {text} {self._coerce(term, term_kind, kind)})"
            return text, kind
        factors = [(op, *self.term(f)) for op, f in expr.factors]
        divides = any(op == "/" for op, _, _ in factors)
        kind = "integer" if all(k == "integer" for _, _, k in factors) and not divides \
            else "real"
        text = self._coerce(factors[0][1], factors[0][2], kind)
        for op, factor, factor_kind in factors[1:]:
            text = f"({op} {text} {self._coerce(factor, factor_kind, kind)})"
        return text, kind

    @staticmethod
    def _coerce(text: str, kind: Kind, target: Kind) -> str:
        if target == "real" and kind == "integer":
            return f"(to_real {text})"
        return text

    def _compare(self, expr: Compare) -> str:
        terms = [self.term(operand) for operand in expr.operands]
        parts: list[str] = []
        for index, op in enumerate(expr.ops):
            (left, left_kind), (right, right_kind) = terms[index], terms[index + 1]
            if {left_kind, right_kind} == {"integer", "real"}:
                left = self._coerce(left, left_kind, "real")
                right = self._coerce(right, right_kind, "real")
            if op == "==":
                parts.append(f"(= {left} {right})")
            elif op == "!=":
                parts.append(f"(not (= {left} {right}))")
            else:
                parts.append(f"({op} {left} {right})")
        return parts[0] if len(parts) == 1 else f"(and {' '.join(parts)})"


def to_smtlib(expr: Expr, quantities: Mapping[str, Quantity]) -> tuple[str, str]:
    """(declarations, term) of a type-checked condition, as SMT-LIB text."""
    translator = Translator(quantities)
    term = translator.condition(expr)
    return translator.declarations(), term


def to_z3(expr: Expr, quantities: Mapping[str, Quantity], ctx: object | None = None) -> object:
    """A z3 BoolRef for a type-checked condition (read back through z3's SMT-LIB parser, so the
    solver sees exactly the text the logic checks assert)."""
    import z3

    declarations, term = to_smtlib(expr, quantities)
    vector = z3.parse_smt2_string(f"{declarations}(assert {term})", ctx=ctx)
    return vector[0]


# ---------------------------------------------------------------------------------------------
# Plain words for explanations: names become titles, numbers compared with a quantity get its
# unit.

_WORD_OPS = {"==": "is", "!=": "is not"}


def quantity_words(name: str, quantities: Mapping[str, Quantity]) -> str:
    spec = quantities.get(name)
    title = spec.title if spec is not None and spec.title else name
    if len(title) > 1 and title[0].isupper() and not title[1].isupper():
        title = title[0].lower() + title[1:]
    return title


def number_words(value: Fraction | float) -> str:
    number = float(value)
    if not math.isfinite(number):
        return str(number)
    if number == int(number) and abs(number) < 1e15:
        return f"{int(number):,}"
    return f"{number:,.6g}"


def with_unit(value: str, unit: str) -> str:
    if not unit:
        return value
    return f"{value} {unit}" if unit not in {"%", "deg"} else (
        f"{value} %" if unit == "%" else f"{value}°"
    )


def tag_words(tag: str) -> str:
    return tag.replace("_", " ")


def with_article(words: str) -> str:
    return f"an {words}" if words[:1].lower() in "aeiou" else f"a {words}"


# Tags that name a kind of place read "a shipping lane"; others ("coastal") describe one.
_PLACE_NOUNS = frozenset({
    "area", "lane", "zone", "channel", "approach", "reserve", "sanctuary", "park", "harbor",
    "harbour", "port", "corridor", "range", "box", "anchorage", "field", "ground", "grounds",
    "site", "route", "passage", "strait", "bay", "basin", "reef", "wreck", "waters", "region",
})


def _is_place(tag: str) -> bool:
    words = tag_words(tag).split()
    return bool(words) and words[-1].lower() in _PLACE_NOUNS


def tag_state(tag: str, holds: bool = True) -> str:
    """'is a shipping lane' / 'is coastal' (or their negations)."""
    words = tag_words(tag)
    if _is_place(tag):
        words = with_article(words)
    return f"is {words}" if holds else f"is not {words}"


def in_tag(tag: str) -> str:
    """'in a shipping lane' / 'in a coastal area'."""
    words = tag_words(tag)
    return f"in {with_article(words)}" if _is_place(tag) else f"in {with_article(words)} area"


def describe(expr: Expr, quantities: Mapping[str, Quantity], unit: str = "") -> str:
    """The expression in words a supervisor reads, e.g. 'depth >= 20 m'."""
    if isinstance(expr, Num):
        return with_unit(number_words(expr.value), unit)
    if isinstance(expr, Text):
        return repr(expr.value)
    if isinstance(expr, Truth):
        return "true" if expr.value else "false"
    if isinstance(expr, Name):
        return quantity_words(expr.name, quantities)
    if isinstance(expr, Special):
        return expr.name
    if isinstance(expr, Context):
        return in_tag(expr.tag)
    if isinstance(expr, Not):
        return f"not {_grouped(expr.operand, quantities, 'not')}"
    if isinstance(expr, Neg):
        return f"-{_grouped(expr.operand, quantities, 'arith', unit)}"
    if isinstance(expr, Logic):
        return f" {expr.op} ".join(_grouped(o, quantities, expr.op) for o in expr.operands)
    if isinstance(expr, Implies):
        return " implies ".join(_grouped(o, quantities, "implies") for o in expr.operands)
    if isinstance(expr, Compare):
        unit = _unit_of(expr.operands, quantities)
        words = describe(expr.operands[0], quantities, unit)
        for op, operand in zip(expr.ops, expr.operands[1:], strict=True):
            words += f" {_WORD_OPS.get(op, op)} {_grouped(operand, quantities, 'compare', unit)}"
        return words
    if isinstance(expr, Sum):
        unit = unit or _unit_of([t for _, t in expr.terms], quantities)
        words = _grouped(expr.terms[0][1], quantities, "sum", unit)
        for op, term in expr.terms[1:]:
            words += f" {op} {_grouped(term, quantities, 'sum', unit)}"
        return words
    words = _grouped(expr.factors[0][1], quantities, "product")
    for op, factor in expr.factors[1:]:
        words += f" {op} {_grouped(factor, quantities, 'product')}"
    return words


# Which children need parentheses inside which parents.
_GROUP = {
    "not": (Logic, Implies, Compare),
    "and": (Logic, Implies),
    "or": (Logic, Implies),
    "implies": (Implies,),
    "compare": (Compare, Logic, Implies),
    "sum": (Sum, Compare, Logic, Implies),
    "product": (Sum, Product, Compare, Logic, Implies),
    "arith": (Sum, Product, Compare, Logic, Implies),
}


def _grouped(expr: Expr, quantities: Mapping[str, Quantity], parent: str, unit: str = "") -> str:
    text = describe(expr, quantities, unit)
    if isinstance(expr, _GROUP[parent]) and not (
        isinstance(expr, Logic) and expr.op == parent
    ):
        return f"({text})"
    return text


def _unit_of(operands: tuple[Expr, ...] | list[Expr], quantities: Mapping[str, Quantity]) -> str:
    for operand in operands:
        if isinstance(operand, Name):
            spec = quantities.get(operand.name)
            if spec is not None and spec.unit:
                return spec.unit
    return ""
