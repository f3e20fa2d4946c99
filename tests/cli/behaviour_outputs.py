"""What Countersign does, hashed: the guard every refactor is measured against.

"No behaviour change" means the OpenAPI document, the CLI's outputs on the built-in examples
and on the NPS missions, and the signed bytes of the approval fixtures stay byte for byte as
they were. This module computes a SHA-256 digest of each of them; tests/cli/
test_no_behaviour_change.py compares today's code with data/no-behaviour-change.json, written
from main at aea7afb (before the one-shape refactors).

Only what changes by design or is a measurement is normalised: the planner's time taken, the
checker fingerprint (`checker`, a digest of the checking code itself) in validation reports
and statements, and the blank-node names of the NPS Turtle view (compared as canonical graphs,
as tests/cli/cli_outputs.py does).

To regenerate the fixture deliberately (a change of behaviour that was meant), run from the
repository root, with the NPS reference material in ../shared so that its entries are written:

    PYTHONPATH=$PWD/backend .venv/bin/python -m tests.cli.behaviour_outputs --write

and say in the commit which entries changed and why (`--diff` prints the entries that differ
from the fixture without writing it). To write it from another commit's code (as it was written
from aea7afb), extract that commit's code and ontology and point PYTHONPATH there; the committed
documents (`file ...` entries) are read from this checkout:

    git archive COMMIT backend ontology | tar -x -C /tmp/base
    PYTHONPATH=/tmp/base/backend .venv/bin/python -m tests.cli.behaviour_outputs --write
"""

from __future__ import annotations

import contextlib
import hashlib
import json
import re
import sys
from collections.abc import Iterator
from datetime import UTC, datetime
from pathlib import Path
from typing import Any

from cryptography.hazmat.primitives.asymmetric.ed25519 import Ed25519PrivateKey

from .cli_outputs import _canonical_turtle, _run

REPO = Path(__file__).resolve().parents[2]
FIXTURE = Path(__file__).parent / "data" / "no-behaviour-change.json"
# The NPS reference material sits in ../shared next to the clone (as for the NPS conformance tests).
NPS_MISSIONS = REPO.parent / "shared" / "reference" / "nps-ethical-control" / "missions"
NPS_PREFIX = "nps:"
# A fixed stand-in for the checker fingerprint, which names the checking code by design.
CHECKER = "checker"

# What is run on every orders file: the commands of tests/cli/cli_outputs.py, plus explain.
ORDERS_COMMANDS: dict[str, list[str]] = {
    "validate": ["validate"],
    "validate-json": ["validate", "--format", "json"],
    "paths": ["paths", "--limit", "300"],
    "paths-offset": ["paths", "--offset", "40", "--limit", "20"],
    "trace": ["paths", "--limit", "60", "--format", "trace"],
    **{f"export-{f}": ["export", "--format", f]
       for f in ("plain", "json", "dot", "turtle", "nps-turtle", "avcl", "imc", "moos")},
    "explain": ["explain"],
    "explain-json": ["explain", "--format", "json"],
}
# What is run on the built-in examples only (they carry contingency rules or are printed).
EXAMPLE_COMMANDS: dict[str, list[str]] = {
    "examples": ["examples"],
    "rules": ["rules"],
    "rules-json": ["rules", "--format", "json"],
}
# Commands that read no orders file: the planner's examples and the built-in rule theories.
OTHER_RUNS: dict[str, list[str]] = {
    "examples-list": ["examples"],
    **{f"plan {name}": ["plan", f"example:{name}"]
       for name in ("gravitas", "gravitas-replan", "gravitas-currency")},
    **{f"plan-json {name}": ["plan", "--format", "json", f"example:{name}"]
       for name in ("gravitas", "gravitas-replan", "gravitas-currency")},
    "rules theory:transect": [
        "rules", "theory:transect", "--observe", "localisation_precision_low,transect_done(t1)",
        "--action", "transect_t2"],
    "rules-json theory:search-and-sample": [
        "rules", "theory:search-and-sample", "--format", "json", "--observe",
        "safety_sensor_failure(leak)", "--action", "area_search"],
}


def _sha(data: str | bytes) -> str:
    return hashlib.sha256(data.encode("utf-8") if isinstance(data, str) else data).hexdigest()


def _without_checker(data: Any) -> Any:
    """`data` with every `checker` value replaced by CHECKER (the fingerprint is by design)."""
    if isinstance(data, dict):
        return {k: CHECKER if k == "checker" else _without_checker(v) for k, v in data.items()}
    if isinstance(data, list):
        return [_without_checker(v) for v in data]
    return data


def run_digest(argv: list[str]) -> str:
    """SHA-256 of a CLI run: exit code, standard output and standard error. NPS missions are
    named relative to NPS_MISSIONS, run from there, so that messages naming the file do not
    depend on where the clone is."""
    if argv[-1].startswith(NPS_PREFIX):
        with contextlib.chdir(NPS_MISSIONS):
            code, stdout, stderr = _run([*argv[:-1], argv[-1].removeprefix(NPS_PREFIX)])
    else:
        code, stdout, stderr = _run(argv)
    if "--format" in argv and argv[argv.index("--format") + 1] == "json" and stdout.strip():
        try:
            data = json.loads(stdout)
        except ValueError:
            pass
        else:
            stdout = json.dumps(_without_checker(data), sort_keys=True).encode()
    if argv[:3] == ["export", "--format", "nps-turtle"] and code == 0:
        stdout = _canonical_turtle(stdout)
    if argv[0] == "plan":
        # The planner's text says how long it took ("... 48 states in 0.000 s."): a measurement.
        stdout = re.sub(rb"(states in )[0-9.]+( s)", rb"\1T\2", stdout)
    blob = json.dumps([code, stdout.decode("utf-8", "surrogateescape"), stderr])
    return _sha(blob.encode("utf-8", "surrogateescape"))


def example_names() -> list[str]:
    from countersign.orders.examples import example_names as names
    from countersign.orders.examples import team_example_names

    return [*names(), *team_example_names()]


def nps_files() -> list[Path]:
    """The NPS missions (AVCL XML and Turtle), or none when ../shared is absent."""
    if not NPS_MISSIONS.is_dir():
        return []
    return sorted([*NPS_MISSIONS.glob("avcl/*.xml"), *NPS_MISSIONS.glob("turtle/*.ttl")])


def cli_runs(*, nps: bool = True) -> Iterator[tuple[str, list[str]]]:
    """(fixture key, argv) of every CLI run the guard compares."""
    for name in example_names():
        for command, argv in {**ORDERS_COMMANDS, **EXAMPLE_COMMANDS}.items():
            source = name if command == "examples" else f"example:{name}"
            yield f"example {name} {command}", [*argv, source]
    yield from ((f"run {key}", argv) for key, argv in OTHER_RUNS.items())
    for path in nps_files() if nps else []:
        relative = path.relative_to(NPS_MISSIONS).as_posix()
        for command, argv in ORDERS_COMMANDS.items():
            yield f"{NPS_PREFIX}{relative} {command}", [*argv, f"{NPS_PREFIX}{relative}"]


# --- the signed bytes of the approval fixtures ---------------------------------------------

TIME = "2026-12-04T12:00:00Z"


def _key(seed: int) -> Ed25519PrivateKey:
    # A fixed test key (never used outside these fixtures); Ed25519 signatures are
    # deterministic, so the same bytes are signed into the same signature.
    return Ed25519PrivateKey.from_private_bytes(bytes((seed * 3 + i) % 256 for i in range(32)))


def approval_statements(name: str) -> dict[str, dict[str, Any]]:
    """The statements a supervisor would sign for one example: a fixed approval record in
    every field the server fills (report, paths, probabilities, exports, team), a rejection
    and a revocation."""
    from countersign.approvals import dsse
    from countersign.approvals.statement import build_statement, json_digest
    from countersign.export.package import export_digests
    from countersign.orders.canonical import digest
    from countersign.orders.examples import load_example
    from countersign.orders.team import member_digests
    from countersign.verify.report import validate

    orders = load_example(name)
    report = _without_checker(validate(orders).to_json())
    common: dict[str, Any] = {
        "mission": orders.id, "version": 3, "orders_digest": digest(orders), "submission": 7,
        "report_digest": json_digest(report), "paths": report.get("paths"),
        "vehicle": orders.vehicle, "author": "operator", "supervisor": "supervisor",
        "key_id": dsse.key_id(_key(1).public_key()), "time": TIME, "nonce": "0f" * 16,
        "probabilities": report.get("probabilities"), "checker": CHECKER,
        "team": member_digests(orders) if orders.team is not None else None,
    }
    approved = build_statement(
        **common, decision="approved", reason="Every path checked.",
        rehearsal_digest="sha256:" + "ab" * 32, campaigns=["sha256:" + "cd" * 32],
        exports=export_digests(orders, version=3, submission=7))
    rejected = build_statement(**common, decision="rejected", reason="Area B is too shallow.")
    revoked = build_statement(**common, decision="revoked", reason="Superseded by version 4.",
                              revokes="sha256:" + "ef" * 32)
    return {"approved": approved, "rejected": rejected, "revoked": revoked}


def signed_bytes(name: str) -> dict[str, str]:
    """Digests of every byte string a signature covers for the approval fixtures of one
    example: the statement, its DSSE PAE and envelope, the log entry, its receipt and the
    checkpoint over the log."""
    from countersign.approvals import dsse
    from countersign.approvals.log import GENESIS, entry_bytes, event_data, sign_checkpoint
    from countersign.approvals.merkle import Tree, leaf_hash
    from countersign.approvals.receipt import make_receipt
    from countersign.approvals.statement import statement_bytes

    out: dict[str, str] = {}
    entries: list[bytes] = []
    prev = GENESIS
    for index, (decision, statement) in enumerate(approval_statements(name).items()):
        payload = statement_bytes(statement)
        envelope = json.dumps(dsse.sign_envelope(payload, _key(1)))
        event = event_data(
            id=index + 1, at=datetime(2026, 12, 4, 12, 0, index, tzinfo=UTC),
            actor="supervisor", kind=decision, mission=str(statement["predicate"]["mission"]),
            before="submitted", after=decision,
            detail={"envelope": dsse.envelope_digest(envelope), "submission": 7})
        entry = entry_bytes(index, prev, event)
        prev = leaf_hash(entry).hex()
        entries.append(entry)
        out |= {
            f"{decision} statement": _sha(payload),
            f"{decision} pae": _sha(dsse.pae(dsse.PAYLOAD_TYPE, payload)),
            f"{decision} envelope": _sha(envelope),
            f"{decision} log entry": _sha(entry),
            f"{decision} receipt": _sha(make_receipt(_key(2), "countersign.example/log", index,
                                                     prev, TIME)),
        }
    tree = Tree(leaf_hash(e) for e in entries)
    out["checkpoint"] = _sha(json.dumps(sign_checkpoint(_key(2), len(entries), tree.root()),
                                        sort_keys=True))
    return out


def file_digests() -> dict[str, str]:
    """Committed files that pin behaviour elsewhere: the OpenAPI document (which
    tests/e2e/test_client_schema.py ties to the live app) and the crypto vectors and rule
    fixtures the browser shares with the Python code (tests/approvals/test_browser_vectors.py)."""
    files = ("frontend/openapi.json", "frontend/src/crypto/__fixtures__/vectors.json",
             "frontend/src/crypto/__fixtures__/duties.json",
             "frontend/src/crypto/__fixtures__/roles.json")
    return {f"file {name}": _sha((REPO / name).read_bytes()) for name in files}


def all_digests(*, nps: bool = True) -> dict[str, str]:
    digests = {key: run_digest(argv) for key, argv in cli_runs(nps=nps)}
    for name in example_names():
        digests |= {f"approval {name} {k}": v for k, v in signed_bytes(name).items()}
    return digests | file_digests()


def main(argv: list[str]) -> int:
    if argv not in (["--write"], ["--diff"]):
        print(__doc__)
        return 2
    if not NPS_MISSIONS.is_dir():
        print(f"{NPS_MISSIONS} is absent: the NPS entries cannot be computed", file=sys.stderr)
        return 2
    current = all_digests()
    if argv == ["--diff"]:
        before = json.loads(FIXTURE.read_text(encoding="utf-8"))
        for key in sorted(set(before) | set(current)):
            if before.get(key) != current.get(key):
                print(key)
        return 0
    FIXTURE.write_text(json.dumps(current, indent=1, sort_keys=True) + "\n", encoding="utf-8")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
