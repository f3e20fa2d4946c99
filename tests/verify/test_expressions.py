"""The expression language: parser, positions of errors, types and units, partial evaluation,
translation to z3, and pathological input."""

from __future__ import annotations

from fractions import Fraction

import pytest
import z3
from hypothesis import given, settings
from hypothesis import strategies as st

from countersign.orders.examples import load_example
from countersign.orders.model import Orders, Quantity
from countersign.verify.expressions import (
    MAX_DEPTH,
    MAX_TERMS,
    Compare,
    Context,
    ExprError,
    Facts,
    Implies,
    Logic,
    Name,
    Not,
    Special,
    Translator,
    check_condition,
    describe,
    fold,
    identifiers,
    parse,
    quantity_table,
    reads,
    to_smtlib,
    to_z3,
)

QUANTITIES = quantity_table(load_example("search-and-sample"))


def error_of(source: str, quantities: dict[str, Quantity] | None = None) -> str:
    with pytest.raises(ExprError) as caught:
        expr = parse(source)
        check_condition(expr, quantities if quantities is not None else QUANTITIES)
    return caught.value.located("C4")


# Parsing ---------------------------------------------------------------------------------------


def test_precedence_or_below_and_below_not_below_comparison() -> None:
    expr = parse("not a > 1 or b < 2 and c == 3")
    assert isinstance(expr, Logic) and expr.op == "or"
    left, right = expr.operands
    assert isinstance(left, Not) and isinstance(left.operand, Compare)
    assert isinstance(right, Logic) and right.op == "and"


def test_implies_is_weakest_and_right_associative() -> None:
    expr = parse("a > 1 implies b > 1 or c > 1 implies d > 1")
    assert isinstance(expr, Implies)
    assert len(expr.operands) == 3
    assert isinstance(expr.operands[1], Logic)


def test_keywords_are_case_insensitive_and_behaviour_is_accepted() -> None:
    expr = parse("behaviour == 'sample' AND context('shipping_lane')")
    assert isinstance(expr, Logic)
    assert isinstance(expr.operands[0], Compare)
    assert isinstance(expr.operands[0].operands[0], Special)
    assert isinstance(expr.operands[1], Context)


def test_long_chains_are_flat() -> None:
    expr = parse(" and ".join(f"depth_m > {i}" for i in range(300)))
    assert isinstance(expr, Logic) and len(expr.operands) == 300


def test_reads_and_identifiers() -> None:
    expr = parse("lane_distance_m >= 1000 or depth_m >= 20 and behavior == 'x' "
                 "and context('shipping_lane') and area != 'A'")
    found = reads(expr)
    assert found.quantities == {"lane_distance_m", "depth_m"}
    assert found.tags == {"shipping_lane"} and found.behavior and found.area
    assert identifiers("nav_error_m <= 10") == {"nav_error_m"}
    assert identifiers("nav_error_m <=") == frozenset()


# Errors with positions --------------------------------------------------------------------------


@pytest.mark.parametrize(
    ("source", "message"),
    [
        ("lane_distance_m >=", "C4, column 19: expected a value after '>='"),
        ("depth_m >= 20 or", "C4, column 17: expected a value after 'or'"),
        ("depth_m >= 20 20", "C4, column 15: expected an operator after '20', found '20'"),
        ("(depth_m > 1", "C4, column 13: the '(' at column 1 is never closed"),
        ("depth_m > 1)", "C4, column 12: this ')' closes nothing"),
        ("", "C4, column 1: the expression is empty"),
        ("depth_m = 5", "C4, column 9: '=' is not an operator here; use =="),
        ("a && b", "C4, column 3: '&&' is not an operator here; use and"),
        ("depth_m => 5", "C4, column 9: '=>' is not an operator here; use implies"),
        ("'open", "C4, column 1: the text starting with ' is never closed"),
        ("__import__('os')", "C4, column 1: unknown function '__import__'"),
        ("context(shipping_lane)", "C4, column 9: context() takes one quoted area tag"),
        ("depht_m > 3", "C4, column 1: unknown quantity 'depht_m' (did you mean 'depth_m'?)"),
        ("Behavior == 'x'", "C4, column 1: unknown quantity 'Behavior' (write 'behavior'"),
        ("depth_m", "C4, column 1: this is a number, not a condition"),
        ("behavior > 'a'", "C4, column 1: '>' needs numbers, but this is text"),
        ("depth_m == 'deep'", "C4, column 12: '==' compares a number with text"),
        ("not depth_m", "C4, column 5: 'not' needs a condition, but this is a number"),
        ("safety_equipment_ok + 1 > 0", "C4, column 1: '+' needs a number, but this is a"),
        ("depth_m / 0 > 1", "C4, column 11: division by zero"),
        ("depth_m + nav_error_m * contact_distance_m > 1", None),
        ("20m <= depth_m", "C4, column 1: a number cannot run into a name"),
    ],
)
def test_error_messages_name_the_column(source: str, message: str | None) -> None:
    if message is None:
        check_condition(parse(source), QUANTITIES)
        return
    assert error_of(source).startswith(message)


def test_units_must_agree_in_sums_and_comparisons() -> None:
    quantities = {**QUANTITIES, "speed_mps": Quantity(unit="m/s")}
    assert "units differ" in error_of("depth_m + speed_mps > 1", quantities)
    assert "units differ" in error_of("depth_m >= speed_mps", quantities)
    # Scaling by a literal keeps the unit; products of quantities are not compared.
    check_condition(parse("2 * depth_m >= lane_distance_m / 2"), quantities)
    check_condition(parse("depth_m * speed_mps >= depth_m"), quantities)


@pytest.mark.parametrize(
    ("source", "fragment"),
    [
        ("depth_m ≥ 20", "'≥' (GREATER-THAN OR EQUAL TO) is not allowed; write '>='"),
        ("depth_m − 5 > 0", "write '-'"),
        ("dеpth_m > 1", "column 2: 'е' (CYRILLIC SMALL LETTER IE) looks like a letter"),
        ("depth_m > ５", "is not an ASCII digit"),
        ("behavior == ‘sample’", "write \"'\""),
        ("depth_m\u200b > 1", "invisible or control character U+200B"),
        ("depth_m > 1\x00", "invisible or control character U+0000"),
    ],
)
def test_unicode_look_alikes_are_named(source: str, fragment: str) -> None:
    assert fragment in error_of(source)


@pytest.mark.parametrize(
    ("source", "fragment"),
    [
        ("depth_m > 1e999", "out of range"),
        ("depth_m > 1e-99999999", "out of range"),
        ("depth_m > " + "9" * 5000, "has more than 30 digits"),
        ("(" * 1_000 + "depth_m > 1" + ")" * 1_000, f"nests more than {MAX_DEPTH} levels"),
        ("not " * 2_000 + "depth_m > 1", f"nests more than {MAX_DEPTH} levels"),
        ("-" * 1_000 + "depth_m > 1", f"nests more than {MAX_DEPTH} levels"),
        ("(" * 4_000 + "depth_m > 1" + ")" * 4_000, "too long: more than 4,000 symbols"),
        (" + ".join(["depth_m"] * 10_000) + " > 1", "longer than 10,000 characters"),
        (" + ".join(["1"] * 1_500) + " > 1", f"more than {MAX_TERMS:,} terms"),
        ("x" * 20_000, "longer than 10,000 characters"),
    ],
)
def test_pathological_expressions_are_refused(source: str, fragment: str) -> None:
    # How fast: tests/bench/bench_fail_fast.py (no wall-clock bound in a unit test).
    assert fragment in error_of(source)


def test_large_but_legal_numbers_are_exact() -> None:
    expr = parse("depth_m <= 123456789012345678901234567890")
    check_condition(expr, QUANTITIES)
    _, term = to_smtlib(expr, QUANTITIES)
    assert "123456789012345678901234567890" in term


# Partial evaluation --------------------------------------------------------------------------


def test_fold_decides_what_the_facts_decide() -> None:
    facts = Facts("sample", "A", frozenset({"marine_protected_area"}))
    assert fold(parse("behavior == 'sample' and context('marine_protected_area')"), facts) is True
    assert fold(parse("behavior == 'transit' and depth_m > 3"), facts) is False
    assert fold(parse("behavior == 'sample' and depth_m > 3"), facts) is None
    assert fold(parse("context('shipping_lane') implies depth_m > 3"), facts) is True
    assert fold(parse("area == 'A' or depth_m > 3"), facts) is True
    nothing = Facts(None, None, frozenset())
    assert fold(parse("behavior == 'sample'"), nothing) is False
    assert fold(parse("behavior != 'sample'"), nothing) is True


# z3 translation --------------------------------------------------------------------------------

_SMALL = st.integers(min_value=-20, max_value=20)


@st.composite
def arithmetic(draw: st.DrawFn, depth: int = 0) -> str:
    if depth > 2 or draw(st.booleans()):
        value = draw(_SMALL)
        return f"({value})" if value < 0 else str(value)
    op = draw(st.sampled_from(["+", "-", "*", "/"]))
    left = draw(arithmetic(depth + 1))
    right = draw(arithmetic(depth + 1))
    if op == "/":
        right = f"({right} + 100)"  # never zero: the operands stay within +-9,000
    return f"({left} {op} {right})"


@st.composite
def conditions(draw: st.DrawFn, depth: int = 0) -> str:
    if depth > 2 or draw(st.booleans()):
        op = draw(st.sampled_from(["==", "!=", "<", "<=", ">", ">="]))
        return f"{draw(arithmetic())} {op} {draw(arithmetic())}"
    op = draw(st.sampled_from(["and", "or", "implies", "not"]))
    if op == "not":
        return f"not ({draw(conditions(depth + 1))})"
    return f"({draw(conditions(depth + 1))}) {op} ({draw(conditions(depth + 1))})"


@settings(max_examples=150, deadline=None)
@given(conditions())
def test_z3_translation_agrees_with_exact_evaluation(source: str) -> None:
    expr = parse(source)
    check_condition(expr, QUANTITIES)
    expected = fold(expr, Facts(None, None, frozenset()))
    assert expected is not None
    translated = to_z3(expr, QUANTITIES)
    assert z3.is_true(z3.simplify(translated)) is expected


def test_z3_translation_of_quantities_and_facts() -> None:
    quantities = {**QUANTITIES, "contact_count": Quantity(type="integer", min=0)}
    expr = parse("contact_count < 2.5 and depth_m >= 20 and safety_equipment_ok "
                 "and behavior == 'sample' and context('shipping_lane')")
    check_condition(expr, quantities)
    formula = to_z3(expr, quantities)
    solver = z3.Solver()
    solver.add(formula)
    assert solver.check() == z3.sat
    model = solver.model()
    values = {d.name(): model[d] for d in model.decls()}
    assert values["q:contact_count"].as_long() <= 2
    assert z3.is_true(values["q:safety_equipment_ok"])
    # A string's code is its own bytes as a number, whatever was translated before.
    sample = int.from_bytes(b"\x01sample", "big")
    assert values["behavior"].as_long() == sample
    lane = "ctx:" + str(int.from_bytes(b"\x01shipping_lane", "big"))
    assert z3.is_true(values[lane])
    solver.add(z3.Not(z3.Bool(lane)))
    assert solver.check() == z3.unsat


def test_a_formula_reads_the_same_whatever_was_translated_before() -> None:
    # Its text is what z3 solves: a code that depended on the strings met earlier would let a
    # warm session and a cold one solve different formulas for the same orders.
    expr = parse("behavior == 'sample' and context('shipping_lane')")
    fresh = Translator(QUANTITIES)
    used = Translator(QUANTITIES)
    used.condition(parse("behavior == 'loiter' or context('coastal')"))
    assert used.condition(expr) == fresh.condition(expr)
    assert fresh.string_code("sample") != fresh.string_code("loiter")


def test_describe_reads_like_orders() -> None:
    assert describe(parse("lane_distance_m >= 1000 or depth_m >= 20"), QUANTITIES) == (
        "distance to nearest shipping lane >= 1,000 m or depth >= 20 m"
    )
    assert describe(parse("not (behavior == 'surface' and context('shipping_lane'))"),
                    QUANTITIES) == "not (behavior is 'surface' and in a shipping lane)"
    assert describe(parse("context('coastal')"), QUANTITIES) == "in a coastal area"


# Vocabulary ------------------------------------------------------------------------------------


def test_quantity_table_overrides_vocabulary_and_adds_envelope_names() -> None:
    orders = Orders.model_validate({
        "id": "q", "goals": [{"id": "G1", "envelope": {"turbidity_ntu": [0, 5]}}],
        "quantities": {"depth_m": {"unit": "ft", "min": 0, "max": 30}},
    })
    table = quantity_table(orders)
    assert table["depth_m"].unit == "ft" and table["depth_m"].max == 30
    assert table["altitude_m"].unit == "m"
    assert "turbidity_ntu" in table
    check_condition(parse("turbidity_ntu < 3"), table)
    assert isinstance(parse("turbidity_ntu < 3"), Compare)
    assert isinstance(parse("turbidity_ntu"), Name)
    assert Fraction(1, 2) == parse(".5 < 1").operands[0].value  # type: ignore[union-attr]
