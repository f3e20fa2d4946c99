"""Constraint monitors: the orders' constraint expressions, parsed by the safe parser of
`verify.expressions`, compiled once into closures and evaluated on the simulated state every
step.

Compiling matters because the monitors run every simulated second for every constraint in
scope; visiting the tree each time would dominate the simulation's cost.
A quantity the simulation does not produce is unknown: a comparison on it is unknown, and an
unknown verdict never ends a goal (the record lists the constraint as unmonitored instead).
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import dataclass

from ..orders.model import Goal, Orders
from ..verify.expressions import (
    Compare,
    Context,
    Expr,
    ExprError,
    ExprVisitor,
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
    parse,
)

Value = float | bool | str | None  # None: unknown
Values = Mapping[str, float | bool | str]


@dataclass(frozen=True)
class GoalFacts:
    behavior: str | None
    area: str | None
    tags: frozenset[str]


Compiled = Callable[[Values, GoalFacts], Value]


def _const(value: Value) -> Compiled:
    return lambda values, facts: value


def _compare(op: str, a: Value, b: Value) -> bool | None:
    if a is None or b is None:
        return None
    if op == "==":
        return a == b
    if op == "!=":
        return a != b
    if isinstance(a, str) or isinstance(b, str):
        return None  # ordering strings is a type error the static check reports
    x, y = float(a), float(b)
    if op == "<":
        return x < y
    if op == "<=":
        return x <= y
    if op == ">":
        return x > y
    return x >= y


def compile_expr(expr: Expr) -> Compiled:
    return _COMPILE.visit(expr)


class _Compile(ExprVisitor[Compiled]):
    __slots__ = ()

    def visit_num(self, node: Num) -> Compiled:
        return _const(float(node.value))

    def visit_text(self, node: Text) -> Compiled:
        return _const(node.value)

    def visit_truth(self, node: Truth) -> Compiled:
        return _const(node.value)

    def visit_name(self, node: Name) -> Compiled:
        name = node.name
        return lambda values, facts: values.get(name)

    def visit_special(self, node: Special) -> Compiled:
        if node.name == "behavior":
            return lambda values, facts: facts.behavior or ""
        return lambda values, facts: facts.area or ""

    def visit_context(self, node: Context) -> Compiled:
        tag = node.tag
        return lambda values, facts: tag in facts.tags

    def visit_not(self, node: Not) -> Compiled:
        inner = self.visit(node.operand)

        def negate(values: Values, facts: GoalFacts) -> Value:
            v = inner(values, facts)
            return None if v is None else not v

        return negate

    def visit_neg(self, node: Neg) -> Compiled:
        inner = self.visit(node.operand)

        def minus(values: Values, facts: GoalFacts) -> Value:
            v = inner(values, facts)
            return None if v is None or isinstance(v, str) else -float(v)

        return minus

    def visit_logic(self, node: Logic) -> Compiled:
        parts = [self.visit(o) for o in node.operands]
        decisive = node.op == "or"

        def logic(values: Values, facts: GoalFacts) -> Value:
            unknown = False
            for part in parts:
                v = part(values, facts)
                if v is None:
                    unknown = True
                elif bool(v) is decisive:
                    return decisive
            return None if unknown else not decisive

        return logic

    def visit_implies(self, node: Implies) -> Compiled:
        chain = [self.visit(o) for o in node.operands]

        def implies(values: Values, facts: GoalFacts) -> Value:
            result: Value = chain[-1](values, facts)
            for part in reversed(chain[:-1]):
                premise = part(values, facts)
                if premise is False or result is True:
                    result = True
                elif premise is None:
                    result = None
            return result

        return implies

    def visit_compare(self, node: Compare) -> Compiled:
        operands = [self.visit(o) for o in node.operands]
        ops = node.ops

        def compare(values: Values, facts: GoalFacts) -> Value:
            unknown = False
            left = operands[0](values, facts)
            for op, operand in zip(ops, operands[1:], strict=True):
                right = operand(values, facts)
                verdict = _compare(op, left, right)
                if verdict is None:
                    unknown = True
                elif not verdict:
                    return False
                left = right
            return None if unknown else True

        return compare

    def visit_sum(self, node: Sum) -> Compiled:
        terms = [(op, self.visit(t)) for op, t in node.terms]

        def total(values: Values, facts: GoalFacts) -> Value:
            acc = 0.0
            for op, term in terms:
                v = term(values, facts)
                if v is None or isinstance(v, str):
                    return None
                acc = acc + float(v) if op == "+" else acc - float(v)
            return acc

        return total

    def visit_product(self, node: Product) -> Compiled:
        factors = [(op, self.visit(f)) for op, f in node.factors]

        def multiply(values: Values, facts: GoalFacts) -> Value:
            acc = 1.0
            for op, factor in factors:
                v = factor(values, facts)
                if v is None or isinstance(v, str):
                    return None
                if op == "/":
                    if float(v) == 0:
                        return None
                    acc /= float(v)
                else:
                    acc *= float(v)
            return acc

        return multiply


_COMPILE = _Compile()


@dataclass(frozen=True)
class Monitor:
    constraint_id: str
    text: str
    expr: str
    scope: frozenset[str] | None  # None: the whole mission
    check: Compiled

    def applies(self, goal_id: str) -> bool:
        return self.scope is None or goal_id in self.scope

    def holds(self, values: Values, facts: GoalFacts) -> bool | None:
        verdict = self.check(values, facts)
        return None if verdict is None else bool(verdict)


def monitors_of(orders: Orders) -> tuple[list[Monitor], list[str]]:
    """Monitors for every constraint with a parsable expression, and the ids of the
    constraints that cannot be monitored (no expression, or one that does not parse)."""
    monitors: list[Monitor] = []
    skipped: list[str] = []
    for constraint in orders.constraints:
        if not constraint.expr:
            skipped.append(constraint.id)
            continue
        try:
            tree = parse(constraint.expr)
        except ExprError:
            skipped.append(constraint.id)
            continue
        scope = None if constraint.applies_to == "mission" else frozenset(constraint.applies_to)
        monitors.append(
            Monitor(constraint.id, constraint.text, constraint.expr, scope, compile_expr(tree))
        )
    return monitors, skipped


def facts_of(goal: Goal, orders: Orders) -> GoalFacts:
    area = orders.area_index().get(goal.area) if goal.area else None
    return GoalFacts(goal.behavior, goal.area, frozenset(area.contexts) if area else frozenset())
