"""Every CLI output of every built-in example, as SHA-256 digests.

`refines` is optional: orders without it must print exactly what they printed before
refinement existed. `python -m tests.cli.cli_outputs --write` with PYTHONPATH pointing at a
pristine checkout writes the fixture that tests/cli/test_refine_unchanged.py compares with.
"""

from __future__ import annotations

import contextlib
import hashlib
import io
import json
import sys
from pathlib import Path

FIXTURE = Path(__file__).parent / "data" / "cli-outputs-before-refine.json"
# The examples that existed before refinement, and what is run on each.
EXAMPLES = ("harbor-approach-survey", "search-and-sample", "search-and-sample-rules",
            "transect-survey")
COMMANDS: dict[str, list[str]] = {
    "validate": ["validate"],
    "validate-json": ["validate", "--format", "json"],
    "paths": ["paths", "--limit", "300"],
    "paths-offset": ["paths", "--offset", "40", "--limit", "20"],
    "trace": ["paths", "--limit", "60", "--format", "trace"],
    **{f"export-{f}": ["export", "--format", f]
       for f in ("plain", "json", "dot", "turtle", "nps-turtle", "avcl", "imc", "moos")},
}


def _run(argv: list[str]) -> tuple[int, bytes, str]:
    from countersign.cli import main

    raw = io.BytesIO()
    out = io.TextIOWrapper(raw, encoding="utf-8", newline="")
    err = io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        code = main(argv)
        out.flush()
    return code, raw.getvalue(), err.getvalue()


def output_digest(command: str, example: str) -> str:
    argv = [*COMMANDS[command], f"example:{example}"]
    code, stdout, stderr = _run(argv)
    if command == "validate-json":
        # The checker's fingerprint names the code that checked, which changes by design.
        data = json.loads(stdout)
        data.pop("checker", None)
        stdout = json.dumps(data, sort_keys=True).encode()
    if command == "export-nps-turtle":
        stdout = _canonical_turtle(stdout)
    blob = json.dumps([code, stdout.decode("utf-8", "surrogateescape"), stderr])
    return hashlib.sha256(blob.encode("utf-8", "surrogateescape")).hexdigest()


def _canonical_turtle(text: bytes) -> bytes:
    # The NPS view names its blank nodes afresh on every run: compare the graphs instead.
    from rdflib import Graph
    from rdflib.compare import to_canonical_graph

    graph = to_canonical_graph(Graph().parse(data=text.decode("utf-8"), format="turtle"))
    return "\n".join(sorted(line for line in graph.serialize(format="nt").splitlines()
                            if line)).encode()


def all_digests() -> dict[str, str]:
    return {f"{example} {command}": output_digest(command, example)
            for example in EXAMPLES for command in COMMANDS}


if __name__ == "__main__":
    if sys.argv[1:] == ["--write"]:
        FIXTURE.write_text(json.dumps(all_digests(), indent=1, sort_keys=True) + "\n")
