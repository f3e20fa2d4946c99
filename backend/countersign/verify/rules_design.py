"""The contingency rules' design checks (seed 004, section IV-B) as report findings.

The rules engine itself is pure and lives in `countersign.rules`; this module only turns its
verdicts into the RULES findings `report.validate` adds, so the report digest a supervisor signs
covers them.
"""

from __future__ import annotations

from ..orders.findings import Finding, error
from ..orders.model import Orders


def rules_findings(orders: Orders) -> list[Finding]:
    """RULES findings of the orders' (and target vehicle's) rules; none when there are none."""
    vehicle = orders.target_vehicle()
    if orders.rules is None and (vehicle is None or vehicle.rules is None):
        return []  # no theory to read: orders without rules do not import the rules engine
    from ..rules import TheoryError, design_findings, theory_for
    from ..rules.design import CODE

    try:
        theory = theory_for(orders)
    except TheoryError as exc:
        return [error(CODE, [exc.path], f"The contingency rules cannot be read: {exc.reason}.")]
    if theory is None:
        return []
    return design_findings(theory, orders)
