"""Findings: what a check reports about a set of orders.

Defined beside the orders model because readers report findings too (an AVCL mission with a
missing handler loads with the NPS default and a SINK warning).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any, Literal

Severity = Literal["error", "warning"]


@dataclass(frozen=True)
class Finding:
    code: str
    severity: Severity
    subjects: tuple[str, ...]
    message: str
    # Extra machine-readable detail, e.g. the counterexample path of a BUDGET finding.
    details: dict[str, Any] = field(default_factory=dict, compare=False)

    def to_json(self) -> dict[str, Any]:
        data: dict[str, Any] = {
            "code": self.code,
            "severity": self.severity,
            "subjects": list(self.subjects),
            "message": self.message,
        }
        if self.details:
            data["details"] = self.details
        return data


def error(
    code: str, subjects: list[str] | tuple[str, ...], message: str, **details: Any
) -> Finding:
    return Finding(code, "error", tuple(subjects), message, details)


def warning(
    code: str, subjects: list[str] | tuple[str, ...], message: str, **details: Any
) -> Finding:
    return Finding(code, "warning", tuple(subjects), message, details)
