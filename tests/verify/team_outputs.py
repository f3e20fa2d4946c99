"""What single-vehicle orders produce, hashed: teams must leave every byte of it alone.

`python -m tests.verify.team_outputs` with `PYTHONPATH` at the code of main before teams
wrote `data/team_baseline.json`; tests/verify/test_team.py compares today's code with it.
"""

from __future__ import annotations

import hashlib
import json
import sys

from countersign.approvals.statement import build_statement, statement_bytes
from countersign.orders.canonical import canonical_bytes, digest
from countersign.orders.examples import example_names, load_example
from countersign.rules.plain_orders import write_for_supervisor
from countersign.verify.graph import build_graph
from countersign.verify.paths import count_paths, iter_path_lines, iter_paths, trace_text
from countersign.verify.report import validate


def _sha(text: str | bytes) -> str:
    data = text.encode() if isinstance(text, str) else text
    return hashlib.sha256(data).hexdigest()


def outputs(name: str) -> dict[str, str]:
    """SHA-256 of each output of one built-in example."""
    orders = load_example(name)
    report = validate(orders).to_json()
    report.pop("checker")  # the fingerprint of the checking code changes with any code
    graph = build_graph(orders)
    counts = count_paths(graph)
    assert counts is not None
    paths = "\n".join(iter_path_lines(graph, counts, 0, 200, None))
    traces = "\n".join(trace_text(graph, p) for p in iter_paths(graph, counts, 0, 20))
    statement = build_statement(
        mission=orders.id, version=1, orders_digest=digest(orders), decision="approved",
        reason="ok", submission=1, report_digest="sha256:" + "0" * 64, paths=report["paths"],
        vehicle=orders.vehicle, author="op", supervisor="sup", key_id="k",
        time="2026-01-01T00:00:00Z", nonce="n")
    return {
        "canonical": _sha(canonical_bytes(orders)),
        "digest": digest(orders),
        "report": _sha(json.dumps(report, sort_keys=True)),
        **{f"export-{fmt}": _sha(write_for_supervisor(orders, fmt))
           for fmt in ("plain", "json", "dot", "turtle")},
        "paths": _sha(paths),
        "traces": _sha(traces),
        "statement": _sha(statement_bytes(statement)),
    }


if __name__ == "__main__":
    json.dump({name: outputs(name) for name in example_names()}, sys.stdout, indent=1,
              sort_keys=True)
    sys.stdout.write("\n")
