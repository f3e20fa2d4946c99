"""Validation with contingency rules: the verify report plus the seed 004 design checks.

`verify` must not import `rehearse` (dependencies point inward), so the rule checks join the
report here; callers that want them (CLI `validate`, the store's cached reports) call this
instead of `verify.report.validate`. The findings land in the report, so the report digest a
supervisor signs covers them.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Sequence

from ..orders.findings import Finding, error
from ..orders.model import Orders
from ..verify.graph import MissionGraph
from ..verify.logic import LogicCache
from ..verify.report import SOLVER_BUDGET_S, Report, validate
from .rules import TheoryError, design_findings, theory_for
from .rules.design import CODE


def rules_findings(orders: Orders) -> list[Finding]:
    """RULES findings of the orders' (and target vehicle's) rules; none when there are none."""
    try:
        theory = theory_for(orders)
    except TheoryError as exc:
        return [error(CODE, [exc.path], f"The contingency rules cannot be read: {exc.reason}.")]
    if theory is None:
        return []
    return design_findings(theory, orders)


def validate_with_rules(
    orders: Orders,
    reader_findings: Sequence[Finding] = (),
    graph: MissionGraph | None = None,
    logic_cache: LogicCache | None = None,
    *,
    solver_budget_s: float = SOLVER_BUDGET_S,
) -> Report:
    report = validate(orders, reader_findings, graph, logic_cache,
                      solver_budget_s=solver_budget_s)
    extra = rules_findings(orders)
    if not extra:
        return report
    return dataclasses.replace(report, findings=[*report.findings, *extra])
