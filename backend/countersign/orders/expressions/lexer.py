"""Tokens of the expression language, with lookalike characters named and explained."""

from __future__ import annotations

import unicodedata
from collections.abc import Iterator
from dataclasses import dataclass
from fractions import Fraction
from typing import Literal

from .errors import MAX_DIGITS, MAX_EXPONENT, ExprError

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
