"""z3's raw C API, in one place (z3-solver pinned <5.5 in pyproject).

The Python wrapper's `Solver.check(*assumptions)` re-checks the sort of every assumption,
which costs more than solving the small problems the logic check asks; the C call does not.
tests/codebase/test_private_apis.py fails first when z3 changes these names."""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any, Literal

Status = Literal["sat", "unsat", "unknown"]


def check_asts(z3: Any, ctx: Any, solver: Any, asts: Sequence[Any]) -> Status:
    """`solver.check(*literals)` given the literals' raw ASTs (`literal.as_ast()`), without
    the wrapper's per-assumption checks (z3.Z3Exception propagates); a caller that checks the
    same literals many times keeps their ASTs rather than asking each literal again."""
    assumptions = (z3.Ast * len(asts))(*asts)
    code = z3.Z3_solver_check_assumptions(ctx.ref(), solver.solver, len(asts), assumptions)
    if code == z3.Z3_L_TRUE:
        return "sat"
    if code == z3.Z3_L_FALSE:
        return "unsat"
    return "unknown"


def bool_constant(z3: Any, ctx: Any, name: str) -> tuple[Any, int]:
    """A Boolean constant's raw AST and its id. `z3.Bool` builds a sort, a symbol and a Python
    expression each time, which costs more than a check when every goal brings new
    indicators. The AST is held (one reference, never released) for the context's life, which
    frees it: a pushed assertion that named it may be popped while the session still uses it."""
    context = ctx.ref()
    ast = z3.Z3_mk_const(context, z3.Z3_mk_string_symbol(context, name),
                         z3.Z3_mk_bool_sort(context))
    z3.Z3_inc_ref(context, ast)
    return ast, z3.Z3_get_ast_id(context, ast)


def unsat_core_ids(z3: Any, ctx: Any, solver: Any) -> set[int]:
    """The AST ids of the last unsatisfiable check's core, without a Python expression per
    literal (`solver.unsat_core()` builds one each)."""
    context = ctx.ref()
    vector = z3.Z3_solver_get_unsat_core(context, solver.solver)
    z3.Z3_ast_vector_inc_ref(context, vector)
    try:
        return {z3.Z3_get_ast_id(context, z3.Z3_ast_vector_get(context, vector, i))
                for i in range(z3.Z3_ast_vector_size(context, vector))}
    finally:
        z3.Z3_ast_vector_dec_ref(context, vector)


def assert_any(z3: Any, ctx: Any, solver: Any, literals: Sequence[Any]) -> None:
    """`solver.add(z3.Or(literals))` without the wrapper's coercion of every argument (it cost
    more than the checks when a thousand constraints are asked about at once)."""
    disjuncts = (z3.Ast * len(literals))()
    for index, literal in enumerate(literals):
        disjuncts[index] = literal.as_ast()
    disjunction = z3.Z3_mk_or(ctx.ref(), len(literals), disjuncts)
    z3.Z3_solver_assert(ctx.ref(), solver.solver, disjunction)


def true_in_model(z3: Any, ctx: Any, model: Any, literals: Sequence[Any]) -> list[bool]:
    """For each Boolean literal, whether the model makes it true (model completion: an
    unconstrained literal is false), without building a Python expression per answer."""
    result: list[bool] = []
    out = (z3.Ast * 1)()
    context = ctx.ref()
    for literal in literals:
        if not z3.Z3_model_eval(context, model.model, literal.as_ast(), True, out):
            raise z3.Z3Exception("failed to evaluate a literal in the model")
        value = out[0]
        # Held while it is read: an answer z3 returns is not yet counted as referenced.
        z3.Z3_inc_ref(context, value)
        try:
            result.append(z3.Z3_get_bool_value(context, value) == z3.Z3_L_TRUE)
        finally:
            z3.Z3_dec_ref(context, value)
    return result


def check_asserting(z3: Any, ctx: Any, solver: Any, asts: Sequence[Any]) -> Status:
    """Push, assert the raw ASTs, check without assumptions, pop: a status-only check of terms
    parsed once (no SMT-LIB text per check, no indicator literals, no core to extract)."""
    context = ctx.ref()
    handle = solver.solver
    z3.Z3_solver_push(context, handle)
    try:
        for ast in asts:
            z3.Z3_solver_assert(context, handle, ast)
        code = z3.Z3_solver_check(context, handle)
    finally:
        z3.Z3_solver_pop(context, handle, 1)
    if code == z3.Z3_L_TRUE:
        return "sat"
    if code == z3.Z3_L_FALSE:
        return "unsat"
    return "unknown"
