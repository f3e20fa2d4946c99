"""What an expression reads: quantities, area tags, the goal's behaviour or area."""

from __future__ import annotations

from collections.abc import Iterator
from dataclasses import dataclass

from .errors import ExprError
from .parser import parse
from .tree import Context, Expr, Name, Special
from .visit import children


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
        stack.extend(reversed(children(node)))


def reads(expr: Expr) -> Reads:
    quantities: set[str] = set()
    tags: set[str] = set()
    behavior = area = False
    for node in walk(expr):  # a filter over every node: the kinds that read nothing are skipped
        match node:
            case Name(name=name):
                quantities.add(name)
            case Context(tag=tag):
                tags.add(tag)
            case Special(name="behavior"):
                behavior = True
            case Special():
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


def expression_quantities(source: str | None) -> list[str]:
    """The quantity names an expression reads, in order of first use (the MEO graph's
    `reads` links and the M6 explanation list them so). Text that does not parse reads
    nothing here; the EXPR finding reports it."""
    if not source:
        return []
    try:
        expr = parse(source)
    except ExprError:
        return []
    names = sorted((node for node in walk(expr) if isinstance(node, Name)),
                   key=lambda node: node.col)
    return list(dict.fromkeys(node.name for node in names))
