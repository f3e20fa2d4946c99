"""Recursive descent, one function per precedence level, explicit depth and size limits."""

from __future__ import annotations

from collections.abc import Callable, Iterator
from fractions import Fraction
from functools import lru_cache
from typing import cast

from .errors import MAX_DEPTH, MAX_LENGTH, MAX_TERMS, MAX_TOKENS, ExprError
from .lexer import Token, tokenize
from .tree import (
    Compare,
    Context,
    Expr,
    Implies,
    Logic,
    Name,
    Neg,
    Not,
    Num,
    Product,
    Special,
    Sum,
    Text,
    Truth,
)

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
