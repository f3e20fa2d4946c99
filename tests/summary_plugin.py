"""One line at the end of a test run: how many tests ran, and what was skipped and why.

./scripts/test prints it as its last line (skipped PostgreSQL tests went unnoticed).
Skip reasons are grouped so that 300 skipped PostgreSQL variants read as one reason."""

from __future__ import annotations

import os
from collections import Counter
from pathlib import Path

import pytest


def _reason(report: pytest.TestReport) -> str:
    longrepr = report.longrepr
    if isinstance(longrepr, tuple) and len(longrepr) == 3:
        return str(longrepr[2]).removeprefix("Skipped: ")
    return str(longrepr)


def summary_line(terminalreporter: pytest.TerminalReporter) -> str:
    stats = terminalreporter.stats
    counts = {key: len([r for r in stats.get(key, []) if getattr(r, "when", "call") != "teardown"
                        or key == "error"])
              for key in ("passed", "failed", "error", "skipped", "xfailed")}
    reasons: Counter[str] = Counter(_reason(r) for r in stats.get("skipped", []))
    ran = ", ".join(f"{n} {k}" for k, n in counts.items() if n and k != "skipped") or "nothing"
    if not reasons:
        return f"pytest: {ran}; nothing skipped"
    why = "; ".join(f"{n} because {reason}" for reason, n in reasons.most_common())
    return f"pytest: {ran}; {counts['skipped']} skipped: {why}"


def write_summary(terminalreporter: pytest.TerminalReporter) -> None:
    line = summary_line(terminalreporter)
    target = os.environ.get("COUNTERSIGN_TEST_SUMMARY")
    if target:
        Path(target).write_text(line + "\n", encoding="utf-8")
