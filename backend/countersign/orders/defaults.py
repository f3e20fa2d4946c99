"""SINK warnings for handlers an importer filled in by the NPS convention, kept in the orders.

The AVCL reader records on each goal which outcomes it defaulted and to which handler they are
handled alike (`"defaulted": {"violate": "fail"}`). The validation report derives the warnings
from that record, so they stay in the stored report of the draft, every version and every
approval (the record is inside the signed digest), and a warning disappears once the author
gives the outcome a successor of its own.
"""

from __future__ import annotations

from .findings import Finding, warning
from .model import Orders

_HANDLER = {"fail": "nextOnFailure", "violate": "nextOnException"}
_OUTCOME_WORDS = {"fail": "fails", "violate": "ends with an imminent constraint violation"}
_LIKE = {
    ("fail", "succeed"): "a failure is handled like a success",
    ("violate", "fail"): "a constraint violation is handled like a failure",
    ("violate", "succeed"): (
        "a constraint violation is handled like a success (the failure handler is missing too)"
    ),
}


def default_warning(goal_id: str, goal_label: str, outcome: str, like: str,
                    target: str, target_label: str) -> Finding:
    return warning(
        "SINK",
        [goal_id],
        f"Goal {goal_label} does not say what comes next when it "
        f"{_OUTCOME_WORDS[outcome]}: the AVCL orders give no {_HANDLER[outcome]}. "
        f"Following the NPS convention, {_LIKE[(outcome, like)]}, so the mission continues "
        f"with {target_label}. Confirm that this is intended, or add the handler explicitly.",
        outcome=outcome,
        defaulted_to=target,
    )


def defaulted_findings(orders: Orders) -> list[Finding]:
    labels = {t.id: t.label for t in orders.effective_terminals}
    labels.update({g.id: g.label for g in orders.goals})
    findings: list[Finding] = []
    for goal in orders.goals:
        record = getattr(goal, "defaulted", None)
        if not isinstance(record, dict):
            continue
        for outcome in ("fail", "violate"):
            like = record.get(outcome)
            if not isinstance(like, str) or (outcome, like) not in _LIKE:
                continue
            # Still the default: the outcome continues where its model outcome does.
            target = goal.successors(outcome)
            if len(target) != 1 or target != goal.successors(like):
                continue
            findings.append(default_warning(goal.id, goal.label, outcome, like, target[0],
                                            labels.get(target[0], target[0])))
    return findings
