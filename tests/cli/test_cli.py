from __future__ import annotations

import json
import subprocess
import sys
import time
import urllib.request
from pathlib import Path

from ..ports import free_port
from ..verify.test_paths import FIGURE_6_TRACE_1
from .test_bad_input import run_cli


def test_validate_exemplar_json_report() -> None:
    result = run_cli("validate", "example:search-and-sample", "--format", "json")
    assert result.returncode == 0, result.stderr
    report = json.loads(result.stdout)
    assert report["mission"] == "search-and-sample"
    assert report["ok"] is True and report["findings"] == []
    assert report["digest"].startswith("sha256:") and len(report["digest"]) == 71
    assert report["paths"] == {"count": 75, "by_terminal": {"COMPLETE": 25, "ABORT": 50}}


def test_validate_text_names_findings(tmp_path: Path) -> None:
    orders = {"id": "x", "start": "G1", "goals": [
        {"id": "G1", "title": "Search", "next": {"succeed": "G2", "fail": "ABORT",
                                                 "violate": "ABORT"}},
        {"id": "G2", "title": "Sample", "next": {"succeed": "G1", "fail": "ABORT",
                                                 "violate": "ABORT"}}]}
    path = tmp_path / "loop.json"
    path.write_text(json.dumps(orders))
    result = run_cli("validate", str(path))
    assert result.returncode == 1
    assert "G7" in result.stdout and "[G1, G2]" in result.stdout
    assert "not countable" in result.stdout


def test_paths_ndjson_limit_and_offset() -> None:
    result = run_cli("paths", "example:search-and-sample", "--offset", "73", "--limit", "5")
    assert result.returncode == 0
    lines = [json.loads(line) for line in result.stdout.splitlines()]
    assert [p["index"] for p in lines] == [74, 75]
    assert lines[-1] == {"index": 75, "goals": ["G1", "G4", "G5"],
                         "outcomes": ["violate", "violate", "violate"], "terminal": "ABORT"}


def test_paths_trace_format() -> None:
    result = run_cli("paths", "example:search-and-sample", "--offset", "74", "--format", "trace")
    assert result.returncode == 0
    assert result.stdout.strip().split("\n", 1)[1] == FIGURE_6_TRACE_1.split("\n", 1)[1]


def test_paths_refuses_uncountable_orders(tmp_path: Path) -> None:
    path = tmp_path / "sink.json"
    path.write_text(json.dumps({"id": "x", "start": "G1", "goals": [{"id": "G1"}]}))
    result = run_cli("paths", str(path))
    assert result.returncode == 1 and "SINK" in result.stderr


def test_run_reads_answers_and_rejects_others_politely() -> None:
    result = run_cli("run", "example:search-and-sample", stdin=b"c\nmaybe\nc\nc\n")
    assert result.returncode == 0
    assert "Please answer s (the goal succeeded)" in result.stdout
    transcript = [ln for ln in result.stdout.splitlines()
                  if not ln.startswith("Please answer") and not ln.endswith("maybe")]
    assert "\n".join(transcript) == FIGURE_6_TRACE_1.split("\n", 1)[1]


def test_run_stops_cleanly_at_end_of_input() -> None:
    result = run_cli("run", "example:search-and-sample", stdin=b"s\n")
    assert result.returncode == 1
    assert "no outcome given for G2" in result.stdout
    assert "Traceback" not in result.stderr


def test_run_refuses_orders_with_errors(tmp_path: Path) -> None:
    path = tmp_path / "bad.json"
    path.write_text(json.dumps({"id": "x", "goals": []}))
    result = run_cli("run", str(path))
    assert result.returncode == 1 and "M2" in result.stderr


def test_examples_and_export() -> None:
    names = run_cli("examples").stdout.split()
    assert "search-and-sample" in names and len(names) >= 2
    exported = run_cli("export", "example:search-and-sample", "--format", "json")
    assert json.loads(exported.stdout)["id"] == "search-and-sample"
    assert run_cli("examples", "nope").returncode == 2


def test_export_plain_appends_the_contingency_rules() -> None:
    from countersign.orders.examples import load_example
    from countersign.rules.plain_orders import rules_sentences

    exported = run_cli("export", "example:search-and-sample-rules", "--format", "plain")
    assert exported.returncode == 0, exported.stderr
    orders, rules = exported.stdout.split("\n\nContingency rules\n\n")
    assert "Goal 1: Search Area A" in orders and "Norm 1:" in orders
    sentences = rules_sentences(load_example("search-and-sample-rules"))
    assert rules.splitlines() == sentences and len(sentences) == 12
    assert sentences[0].startswith("E_no_fix (estimation rule): If 'gps was captured' is false")
    plain = run_cli("export", "example:search-and-sample", "--format", "plain").stdout
    # the plain orders end with the vehicle profile that was checked
    assert "Contingency rules" not in plain
    assert plain.endswith("Budget: energy 1,500 Wh, duration 43,200 s.\n")
    # other formats are the orders writers' own
    exported = run_cli("export", "example:search-and-sample-rules", "--format", "json")
    assert "Contingency rules" not in exported.stdout


def test_standard_input() -> None:
    data = run_cli("examples", "search-and-sample").stdout.encode()
    result = run_cli("validate", "-", stdin=data)
    assert result.returncode == 0 and "Paths: 75" in result.stdout


def test_help_lists_every_command() -> None:
    result = run_cli("--help")
    for command in ("validate", "paths", "run", "export", "examples", "serve"):
        assert command in result.stdout


def test_serve_answers_health(tmp_path: Path) -> None:
    port = free_port()
    server = subprocess.Popen(
        [sys.executable, "-m", "countersign.cli", "serve", "--port", str(port),
         "--data-dir", str(tmp_path / "data")],
        stdout=subprocess.PIPE, stderr=subprocess.PIPE,
    )
    try:
        deadline = time.monotonic() + 120
        while True:
            try:
                with urllib.request.urlopen(f"http://127.0.0.1:{port}/api/health") as response:
                    body = json.loads(response.read())
                break
            except OSError:
                if time.monotonic() > deadline or server.poll() is not None:
                    raise
                time.sleep(0.2)
        assert body["status"] == "ok"
        assert (tmp_path / "data").is_dir()
    finally:
        server.terminate()
        server.wait(timeout=10)


def test_explain_reports_a_minimal_incompatible_subset(tmp_path: Path) -> None:
    orders = json.loads(run_cli("examples", "search-and-sample").stdout)
    orders["goals"][4]["envelope"] = {"depth_m": [0, 5]}  # G5 at 0-5 m, but C7 needs >= 20 m
    path = tmp_path / "shallow.json"
    path.write_text(json.dumps(orders))
    result = run_cli("explain", str(path), "--goals", "G5", "--format", "json")
    assert result.returncode == 1
    answer = json.loads(result.stdout)
    assert answer["consistent"] is False
    assert answer["core"]["goals"] == ["G5"] and answer["core"]["constraints"] == ["C7"]
    assert "C7 requires depth >= 20 m" in answer["explanation"]
    assert run_cli("explain", str(path), "--goals", "G9").returncode == 2
    assert run_cli("explain", "example:search-and-sample").returncode == 0


def test_validate_explain_shows_inferred_facts_and_meo_findings(tmp_path: Path) -> None:
    result = run_cli("validate", "example:search-and-sample", "--format", "json", "--explain")
    explanation = json.loads(result.stdout)["explanation"]
    assert explanation["constraint_scope"]["C1"] == ["G1", "G2", "G3", "G4", "G5"]
    assert explanation["constraint_scope"]["C7"] == ["G5"]
    text = run_cli("validate", "example:search-and-sample", "--explain").stdout
    assert "C1 appliesTo G5 [C3]" in text
    orders = json.loads(run_cli("examples", "search-and-sample").stdout)
    sampler = next(f for f in orders["vehicles"][0]["features"] if f["id"] == "sampler")
    sampler["fulfills"] = []  # the vehicle can no longer sample: G2 lacks capability (M7)
    path = tmp_path / "nosampler.json"
    path.write_text(json.dumps(orders))
    report = json.loads(run_cli("validate", str(path), "--format", "json").stdout)
    assert [(f["code"], f["subjects"][0]) for f in report["findings"]] == [("M7", "G2")]


def test_export_formats_read_back(tmp_path: Path) -> None:
    for fmt, suffix in (("turtle", "ttl"), ("avcl", "xml"), ("json", "json")):
        exported = run_cli("export", "example:search-and-sample", "--format", fmt)
        assert exported.returncode == 0, exported.stderr
        path = tmp_path / f"again.{suffix}"
        path.write_text(exported.stdout)
        report = json.loads(run_cli("validate", str(path), "--format", "json").stdout)
        assert report["paths"] == {"count": 75, "by_terminal": {"COMPLETE": 25, "ABORT": 50}}
        if fmt != "avcl":  # Turtle and JSON are lossless: same digest
            original = json.loads(run_cli("validate", "example:search-and-sample",
                                          "--format", "json").stdout)
            assert report["digest"] == original["digest"]
    nps = run_cli("export", "example:search-and-sample", "--format", "nps-turtle").stdout
    assert "hasNextGoalOnSuccess" in nps or "hasNextOnSuccess" in nps
