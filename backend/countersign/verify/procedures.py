"""Procedure references: copying bodies in from a library, and PROCEDURE findings.

`expand(orders, lookup)` gives every reference without a body the library's body (and the
library's digest when the reference pins none); the result is checked like orders with the
same refinements written inline, so counts, traces and budgets are those of the inline form.
`procedure_findings(orders)` reports, as PROCEDURE errors, a reference the library could not
fill in, a reference that pins no digest, and a body whose digest is not the pinned one.
Pure: the library is a lookup function (a directory on the command line, the store's table on
the server).
"""

from __future__ import annotations

from collections.abc import Callable, Iterator
from typing import Any

from ..orders.findings import Finding, error
from ..orders.model import Goal, Orders, Refinement
from ..orders.procedure import Procedure, body_json, has_body, procedure_digest
from .paths import PathCounts
from .refine import MAX_DEPTH

Lookup = Callable[[str, int], Procedure | None]
SEP = "/"


def references(goals: list[Goal], prefix: str = "", depth: int = 1
               ) -> Iterator[tuple[str, Refinement]]:
    """(goal path, refinement) of every procedure reference, at every refinement level."""
    for goal in goals:
        refinement = goal.refines
        if refinement is None:
            continue
        path = prefix + goal.id
        if refinement.procedure is not None:
            yield path, refinement
        if depth <= MAX_DEPTH:
            yield from references(refinement.goals, path + SEP, depth + 1)


def uses(orders: Orders) -> list[tuple[str, int, str | None]]:
    """The distinct (name, version, pinned digest) the orders refer to, team members too."""
    found: dict[tuple[str, int, str | None], None] = {}
    for member in _members(orders):
        for _path, ref in references(member.goals):
            assert ref.procedure is not None and ref.version is not None
            found[(ref.procedure, ref.version, ref.digest)] = None
    return list(found)


def _members(orders: Orders) -> list[Orders]:
    return [orders] if orders.team is None else [m.orders for m in orders.team]


def expand(orders: Orders, lookup: Lookup) -> Orders:
    """The orders with each bare reference's body copied in from the library; the same object
    when there is nothing to copy (so the digest of orders without references never moves)."""
    if not uses(orders):
        return orders
    data: dict[str, Any] = orders.model_dump(mode="json", exclude_unset=True)
    changed = False
    if orders.team is None:
        changed = _expand_goals(data.get("goals", []), lookup, 1)
    else:
        for member in data["team"]:
            changed |= _expand_goals(member["orders"].get("goals", []), lookup, 1)
    return Orders.model_validate(data) if changed else orders


def _expand_goals(goals: list[dict[str, Any]], lookup: Lookup, depth: int) -> bool:
    changed = False
    for goal in goals:
        refines = goal.get("refines")
        if not isinstance(refines, dict) or depth > MAX_DEPTH:
            continue
        name, version = refines.get("procedure"), refines.get("version")
        bare = not any(key in refines for key in ("start", "goals", "terminals", "within",
                                                  "on_timeout"))
        if isinstance(name, str) and isinstance(version, int) and bare:
            found = lookup(name, version)
            if found is not None:
                refines.update(body_json(found.refines))
                refines.setdefault("digest", found.digest)
                changed = True
        changed |= _expand_goals(refines.get("goals", []), lookup, depth + 1)
    return changed


def expand_procedure(procedure: Procedure, lookup: Lookup) -> Procedure:
    """The procedure with the goals of the procedures it names itself copied in."""
    wrapper = Orders.model_validate({"id": "p", "goals": [
        {"id": "p", "refines": procedure.to_json()["refines"]}]})
    expanded = expand(wrapper, lookup)
    if expanded is wrapper:
        return procedure
    body = expanded.goals[0].refines
    assert body is not None
    return procedure.model_copy(update={"refines": body})


def procedure_findings(orders: Orders) -> list[Finding]:
    findings: list[Finding] = []
    for path, ref in references(orders.goals):
        assert ref.procedure is not None and ref.version is not None
        named = f"procedure {ref.procedure} version {ref.version}"
        if not has_body(ref):
            findings.append(error(
                "PROCEDURE", [path], f"{path} is carried out by {named}, which the procedure "
                "library does not hold (on the command line, give the library with "
                "--procedures DIR).", procedure=ref.procedure, version=ref.version))
            continue
        actual = procedure_digest(ref.procedure, ref.version, ref)
        if ref.digest is None:
            findings.append(error(
                "PROCEDURE", [path], f"{path} names {named} but pins no digest: write "
                f"\"digest\": \"{actual}\" so that a changed procedure cannot pass as this "
                "one.", procedure=ref.procedure, version=ref.version))
        elif actual != ref.digest:
            findings.append(error(
                "PROCEDURE", [path], f"{path} pins {named} at {ref.digest}, but the "
                f"procedure's goals have digest {actual}: the procedure is not the one these "
                "orders named.", procedure=ref.procedure, version=ref.version,
                pinned=ref.digest, actual=actual))
    return findings


# Findings about the vehicle are decided in the orders that use a procedure, for their vehicle.
VEHICLE_CODES = frozenset({"VEHICLE", "M6", "M7", "BUDGET"})
PROCEDURE_SOLVER_BUDGET_S = 2.0


def _wrapper(procedure: Procedure) -> Orders:
    """Orders with one goal carried out by the procedure, every outcome used, no vehicle."""
    return Orders.model_validate({
        "id": procedure.name, "start": procedure.name,
        "goals": [{"id": procedure.name, "title": procedure.name,
                   "refines": procedure.to_json()["refines"],
                   "next": {"succeed": "COMPLETE", "fail": "ABORT", "violate": "ABORT"}}]})


def check_procedure(procedure: Procedure) -> tuple[list[Finding], PathCounts | None]:
    """The procedure checked as the one refinement of a goal (structure, REFINE, expressions,
    nested references): its findings, and its path counts by terminal (COMPLETE: it returned
    succeed; ABORT: fail or violate). Vehicle checks belong to the orders that use it."""
    from .report import validate

    report = validate(_wrapper(procedure), solver_budget_s=PROCEDURE_SOLVER_BUDGET_S)
    return [f for f in report.findings if f.code not in VEHICLE_CODES], report.paths
