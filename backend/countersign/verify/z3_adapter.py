"""z3's raw C API, in one place (z3-solver pinned <5.5 in pyproject).

The Python wrapper's `Solver.check(*assumptions)` re-checks the sort of every assumption,
which costs more than solving the small problems the logic check asks; the C call does not.
tests/unit/test_private_apis.py fails first when z3 changes these names."""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any, Literal

Status = Literal["sat", "unsat", "unknown"]


def check_assumptions(z3: Any, ctx: Any, solver: Any, literals: Sequence[Any]) -> Status:
    """`solver.check(*literals)` without the wrapper's per-assumption checks (z3.Z3Exception
    propagates)."""
    assumptions = (z3.Ast * len(literals))()
    for index, literal in enumerate(literals):
        assumptions[index] = literal.as_ast()
    code = z3.Z3_solver_check_assumptions(ctx.ref(), solver.solver, len(literals), assumptions)
    if code == z3.Z3_L_TRUE:
        return "sat"
    if code == z3.Z3_L_FALSE:
        return "unsat"
    return "unknown"
