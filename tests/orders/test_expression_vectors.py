"""The expression language against the vectors it shares with the editor
(frontend/src/editor/__fixtures__/expressions.json; frontend/src/editor/expr.test.ts reads the
same file): the parse tree or the error's column and message, the quantities read, the words a
supervisor signs, the type checker, the rehearsal monitor's verdict and what a goal's facts alone
decide. The file's "about" says what each field means; it is written by hand, so a change of
behaviour on either side shows as a failing vector."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

import pytest

from countersign.orders.conditions import condition_words
from countersign.orders.expressions import (
    MARITIME_QUANTITIES,
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
    describe,
    expression_quantities,
    parse,
    reads,
)
from countersign.rehearse.monitor import GoalFacts, compile_expr
from countersign.verify.expressions import Facts, check_condition, fold

VECTORS = (Path(__file__).resolve().parents[2] / "frontend" / "src" / "editor" / "__fixtures__"
           / "expressions.json")
DOCUMENT: dict[str, Any] = json.loads(VECTORS.read_text(encoding="utf-8"))
ENTRIES: list[dict[str, Any]] = DOCUMENT["expressions"]
FIELDS = {"text", "tree", "error", "reads", "words", "checked", "type_error", "evaluate",
          "browser"}
CASE_FIELDS = {"values", "behavior", "area", "tags", "holds", "decided"}


class Shape(ExprVisitor[str]):
    """The tree as the vectors write it: every composite node in parentheses, chains flat."""

    def visit_num(self, node: Num) -> str:
        return str(int(node.value)) if node.integral else repr(float(node.value))

    def visit_text(self, node: Text) -> str:
        return f"'{node.value}'"

    def visit_truth(self, node: Truth) -> str:
        return "true" if node.value else "false"

    def visit_name(self, node: Name) -> str:
        return node.name

    def visit_special(self, node: Special) -> str:
        return node.name

    def visit_context(self, node: Context) -> str:
        return f"context('{node.tag}')"

    def visit_neg(self, node: Neg) -> str:
        return f"(-{self.visit(node.operand)})"

    def visit_not(self, node: Not) -> str:
        return f"(not {self.visit(node.operand)})"

    def visit_sum(self, node: Sum) -> str:
        return self._chain(node.terms)

    def visit_product(self, node: Product) -> str:
        return self._chain(node.factors)

    def visit_compare(self, node: Compare) -> str:
        return self._chain(tuple(zip(("", *node.ops), node.operands, strict=True)))

    def visit_logic(self, node: Logic) -> str:
        return "(" + f" {node.op} ".join(self.visit(o) for o in node.operands) + ")"

    def visit_implies(self, node: Implies) -> str:
        return "(" + " implies ".join(self.visit(o) for o in node.operands) + ")"

    def _chain(self, items: tuple[tuple[str, Expr], ...]) -> str:
        (_, first), *rest = items
        return "(" + self.visit(first) + "".join(f" {op} {self.visit(x)}" for op, x in rest) + ")"


def _id(entry: dict[str, Any]) -> str:
    return repr(entry["text"])


def test_the_vectors_are_well_formed() -> None:
    texts = [entry["text"] for entry in ENTRIES]
    assert len(texts) == len(set(texts)), "a text appears twice"
    for entry in ENTRIES:
        assert set(entry) <= FIELDS, entry["text"]
        assert ("error" in entry) != ("tree" in entry), entry["text"]
        for case in entry.get("evaluate", []):
            assert set(case) <= CASE_FIELDS and {"holds", "decided"} <= set(case), entry["text"]
    assert sum("error" in entry for entry in ENTRIES) >= 15
    assert sum("evaluate" in entry for entry in ENTRIES) >= 10


def test_the_built_in_vocabulary_is_the_one_the_editor_knows() -> None:
    assert DOCUMENT["vocabulary"] == sorted(MARITIME_QUANTITIES)


@pytest.mark.parametrize("entry", [e for e in ENTRIES if "error" in e], ids=_id)
def test_syntax_errors_are_reported_at_their_column(entry: dict[str, Any]) -> None:
    with pytest.raises(ExprError) as caught:
        parse(entry["text"])
    assert {"col": caught.value.column, "message": caught.value.message} == entry["error"]


@pytest.mark.parametrize("entry", [e for e in ENTRIES if "tree" in e], ids=_id)
def test_parse_tree_reads_and_words(entry: dict[str, Any]) -> None:
    expr = parse(entry["text"])
    assert Shape().visit(expr) == entry["tree"]
    assert expression_quantities(entry["text"]) == entry["reads"]
    assert reads(expr).quantities == frozenset(entry["reads"])
    assert describe(expr, MARITIME_QUANTITIES) == entry["words"]
    assert condition_words(entry["text"], MARITIME_QUANTITIES) == entry["checked"]


@pytest.mark.parametrize("entry", [e for e in ENTRIES if "tree" in e], ids=_id)
def test_type_errors_are_reported_at_their_column(entry: dict[str, Any]) -> None:
    try:
        check_condition(parse(entry["text"]), MARITIME_QUANTITIES)
    except ExprError as error:
        assert {"col": error.column, "message": error.message} == entry.get("type_error")
    else:
        assert "type_error" not in entry


def _value(value: object) -> float | bool | str:
    # JSON has one number type; the monitor receives the simulation's floats.
    if isinstance(value, bool | str):
        return value
    assert isinstance(value, int | float)
    return float(value)


@pytest.mark.parametrize("entry", [e for e in ENTRIES if "evaluate" in e], ids=_id)
def test_evaluation_under_bindings(entry: dict[str, Any]) -> None:
    expr = parse(entry["text"])
    monitor = compile_expr(expr)
    for case in entry["evaluate"]:
        values = {name: _value(v) for name, v in case.get("values", {}).items()}
        behavior, area = case.get("behavior"), case.get("area")
        tags = frozenset(case.get("tags", []))
        verdict = monitor(values, GoalFacts(behavior, area, tags))
        assert (None if verdict is None else bool(verdict)) == case["holds"], case
        assert fold(expr, Facts(behavior, area, tags)) == case["decided"], case
