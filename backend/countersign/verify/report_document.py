"""The validation report as a document: what the CLI prints, the API serves, the store keeps
and an approval signs the digest of (`report_digest`, RFC 8785 of exactly this JSON).

`Report` (verify/report.py) is the result of the checks, with the objects behind it; this is
its JSON shape, typed, so the readers of a stored report name fields mypy can check, and
`to_json` writes exactly what was written before: the same keys in the same order, the keys
that come later (probabilities, team, explanation) only when set."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

from ..orders.findings import Finding
from ..orders.json_fields import Malformed, an_object, nullable, optional, required

SEVERITIES = ("error", "warning")
_KEYS = ("mission", "digest", "ok", "findings", "paths", "costs", "checker", "probabilities",
         "team", "explanation")


def finding_from_json(data: Any, where: str) -> Finding:
    data = an_object(data, where)
    severity = required(data, "severity", str, where)
    if severity not in SEVERITIES:
        raise Malformed(f"{where}.severity must be error or warning")
    subjects = required(data, "subjects", list, where)
    if not all(isinstance(s, str) for s in subjects):
        raise Malformed(f"{where}.subjects must be a list of strings")
    details = optional(data, "details", dict, where)
    return Finding(required(data, "code", str, where), "error" if severity == "error"
                   else "warning", tuple(subjects), required(data, "message", str, where),
                   details or {})


@dataclass(frozen=True)
class PathSummary:
    """How many paths there are, in all and by terminal."""

    count: int
    by_terminal: dict[str, int]

    def to_json(self) -> dict[str, Any]:
        return {"count": self.count, "by_terminal": dict(self.by_terminal)}

    @classmethod
    def from_json(cls, data: Any, where: str = "report.paths") -> PathSummary:
        data = an_object(data, where)
        by_terminal = required(data, "by_terminal", dict, where)
        if not all(isinstance(n, int) and not isinstance(n, bool) for n in by_terminal.values()):
            raise Malformed(f"{where}.by_terminal must count paths in integers")
        return cls(required(data, "count", int, where), dict(by_terminal))


@dataclass(frozen=True)
class ReportDocument:
    mission: str
    digest: str
    ok: bool
    findings: tuple[Finding, ...]
    paths: PathSummary | None
    # Worst path per quantity (verify/budget.py WorstPath.to_json), as computed.
    costs: dict[str, Any] | None
    checker: str  # the fingerprint of the checks that made it (verify/fingerprint.py)
    # Only for orders that declare outcome probabilities (verify/probability.py).
    probabilities: dict[str, Any] | None = None
    # Only for a team's orders (verify/team_report.py).
    team: dict[str, Any] | None = None
    # Only when asked for; may itself be null (no orders to reason about).
    explanation: dict[str, Any] | None = None
    explained: bool = False

    def to_json(self) -> dict[str, Any]:
        data: dict[str, Any] = {
            "mission": self.mission, "digest": self.digest, "ok": self.ok,
            # Finding.details compares as equal whatever it holds, so it is written from the
            # finding itself, never from a copy.
            "findings": [f.to_json() for f in self.findings],
            "paths": self.paths.to_json() if self.paths is not None else None,
            "costs": self.costs, "checker": self.checker,
        }
        if self.probabilities is not None:
            data["probabilities"] = self.probabilities
        if self.team is not None:
            data["team"] = self.team
        if self.explained:
            data["explanation"] = self.explanation
        return data

    @classmethod
    def from_json(cls, data: Any) -> ReportDocument:
        """The report in this JSON; Malformed (a ValueError) names the field that is wrong."""
        data = an_object(data, "the report")
        unknown = sorted(set(data) - set(_KEYS))
        if unknown:
            raise Malformed(f"report.{unknown[0]} is not a field of a validation report")
        findings = required(data, "findings", list, "report")
        ok = required(data, "ok", bool, "report")
        typed = tuple(finding_from_json(f, f"report.findings[{i}]")
                      for i, f in enumerate(findings))
        if ok == any(f.severity == "error" for f in typed):
            raise Malformed("report.ok disagrees with its findings' severities")
        paths = nullable(data, "paths", dict, "report")
        return cls(
            mission=required(data, "mission", str, "report"),
            digest=required(data, "digest", str, "report"), ok=ok, findings=typed,
            paths=None if paths is None else PathSummary.from_json(paths),
            costs=nullable(data, "costs", dict, "report"),
            checker=required(data, "checker", str, "report"),
            probabilities=optional(data, "probabilities", dict, "report"),
            team=optional(data, "team", dict, "report"),
            explanation=data.get("explanation") if "explanation" in data else None,
            explained="explanation" in data)

    @property
    def errors(self) -> list[Finding]:
        return [f for f in self.findings if f.severity == "error"]
