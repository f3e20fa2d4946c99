"""The one way to interpret an expression tree: a visitor with one method per node kind, and the
one dispatch that picks the method.

Every interpreter of the language (the plain words, what an expression reads, the type checker,
partial evaluation, the SMT translation, the rehearsal's monitors, the MOOS-IvP helm conditions)
is an `ExprVisitor`. Exhaustiveness is checked twice by mypy, so adding a node kind to
`tree.Expr` cannot be forgotten anywhere:

- `ExprVisitor.visit` matches every kind and ends in `assert_never`: a kind added to the union
  but not matched here is a type error in this file;
- each kind has an abstract `visit_*` method: an interpreter that does not handle a kind cannot
  be instantiated (mypy: "Cannot instantiate abstract class"; at run time: TypeError).

An interpreter that has nothing to say about a kind still writes its method (returning its
"cannot say" value), so the choice is explicit. `tests/orders/test_expression_visitor.py` checks
both properties.
"""

from __future__ import annotations

from abc import ABC, abstractmethod
from typing import Generic, TypeVar, assert_never

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

R = TypeVar("R")


class ExprVisitor(ABC, Generic[R]):
    """Interprets an expression as an R; `visit` dispatches on the node kind."""

    __slots__ = ()

    def visit(self, node: Expr) -> R:
        match node:
            case Num():
                return self.visit_num(node)
            case Text():
                return self.visit_text(node)
            case Truth():
                return self.visit_truth(node)
            case Name():
                return self.visit_name(node)
            case Special():
                return self.visit_special(node)
            case Context():
                return self.visit_context(node)
            case Neg():
                return self.visit_neg(node)
            case Not():
                return self.visit_not(node)
            case Sum():
                return self.visit_sum(node)
            case Product():
                return self.visit_product(node)
            case Compare():
                return self.visit_compare(node)
            case Logic():
                return self.visit_logic(node)
            case Implies():
                return self.visit_implies(node)
            case _:
                assert_never(node)

    @abstractmethod
    def visit_num(self, node: Num) -> R: ...

    @abstractmethod
    def visit_text(self, node: Text) -> R: ...

    @abstractmethod
    def visit_truth(self, node: Truth) -> R: ...

    @abstractmethod
    def visit_name(self, node: Name) -> R: ...

    @abstractmethod
    def visit_special(self, node: Special) -> R: ...

    @abstractmethod
    def visit_context(self, node: Context) -> R: ...

    @abstractmethod
    def visit_neg(self, node: Neg) -> R: ...

    @abstractmethod
    def visit_not(self, node: Not) -> R: ...

    @abstractmethod
    def visit_sum(self, node: Sum) -> R: ...

    @abstractmethod
    def visit_product(self, node: Product) -> R: ...

    @abstractmethod
    def visit_compare(self, node: Compare) -> R: ...

    @abstractmethod
    def visit_logic(self, node: Logic) -> R: ...

    @abstractmethod
    def visit_implies(self, node: Implies) -> R: ...


class _Children(ExprVisitor[tuple[Expr, ...]]):
    __slots__ = ()

    def visit_num(self, node: Num) -> tuple[Expr, ...]:
        return ()

    def visit_text(self, node: Text) -> tuple[Expr, ...]:
        return ()

    def visit_truth(self, node: Truth) -> tuple[Expr, ...]:
        return ()

    def visit_name(self, node: Name) -> tuple[Expr, ...]:
        return ()

    def visit_special(self, node: Special) -> tuple[Expr, ...]:
        return ()

    def visit_context(self, node: Context) -> tuple[Expr, ...]:
        return ()

    def visit_neg(self, node: Neg) -> tuple[Expr, ...]:
        return (node.operand,)

    def visit_not(self, node: Not) -> tuple[Expr, ...]:
        return (node.operand,)

    def visit_sum(self, node: Sum) -> tuple[Expr, ...]:
        return tuple(term for _, term in node.terms)

    def visit_product(self, node: Product) -> tuple[Expr, ...]:
        return tuple(factor for _, factor in node.factors)

    def visit_compare(self, node: Compare) -> tuple[Expr, ...]:
        return node.operands

    def visit_logic(self, node: Logic) -> tuple[Expr, ...]:
        return node.operands

    def visit_implies(self, node: Implies) -> tuple[Expr, ...]:
        return node.operands


_CHILDREN = _Children()


def children(node: Expr) -> tuple[Expr, ...]:
    """The node's direct subexpressions, left to right."""
    return _CHILDREN.visit(node)
