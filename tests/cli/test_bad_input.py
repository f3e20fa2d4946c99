"""Bad input gets a clear error and exit code 2 (or a finding), never a traceback or a hang."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import pytest

from countersign.orders.reader import OrdersReadError, read_bytes

BOMB = b"""<?xml version="1.0"?>
<!DOCTYPE lolz [<!ENTITY lol "lol"><!ENTITY lol2 "&lol;&lol;&lol;&lol;&lol;&lol;&lol;&lol;">
<!ENTITY lol3 "&lol2;&lol2;&lol2;&lol2;&lol2;&lol2;&lol2;&lol2;&lol2;">
<!ENTITY lol4 "&lol3;&lol3;&lol3;&lol3;&lol3;&lol3;&lol3;&lol3;&lol3;">
<!ENTITY lol9 "&lol4;&lol4;&lol4;&lol4;&lol4;&lol4;&lol4;&lol4;&lol4;">]>
<AVCL><body><GoalList><Goal id="G1" title="&lol9;"/></GoalList></body></AVCL>"""


def run_cli(*args: str, stdin: bytes | None = None) -> subprocess.CompletedProcess[str]:
    return subprocess.run(
        [sys.executable, "-m", "countersign.cli", *args],
        input=stdin.decode() if stdin is not None else None,
        capture_output=True, text=True, timeout=20, check=False,
    )


def write(tmp_path: Path, name: str, data: bytes) -> str:
    target = tmp_path / name
    target.write_bytes(data)
    return str(target)


@pytest.mark.parametrize(
    ("name", "data", "expected"),
    [
        ("empty.json", b"", "is empty"),
        ("blank.json", b"  \n\t", "is empty"),
        ("invalid.json", b'{"id": "x", "goals": [', "invalid JSON at line 1"),
        ("array.json", b"[1, 2, 3]", "must be a JSON object, not an array"),
        ("number.json", b"42", "must be a JSON object"),
        ("bomb.xml", BOMB, "DTD"),
        ("latin1.json", b'{"id": "caf\xe9"}', "not UTF-8"),
        ("deep.json", b"[" * 100_000 + b"]" * 100_000, "nested too deeply"),
        ("dupkey.json", b'{"id": "a", "id": "b"}', "appears twice"),
        ("format.json", b'{"format": "other/2", "id": "x"}', "countersign.orders/1"),
        ("badid.json", b'{"id": "x", "goals": [{"id": "G 1"}]}', "$.goals[0].id"),
        ("newline.json", b'{"id": "x", "goals": [{"id": "G1\\nG2"}]}', "not a valid id"),
        ("noid.json", b'{"goals": []}', "$.id"),
    ],
)
def test_unreadable_input_exits_2_with_a_clear_message(
    tmp_path: Path, name: str, data: bytes, expected: str
) -> None:
    result = run_cli("validate", write(tmp_path, name, data))
    assert result.returncode == 2, result.stderr
    assert expected in result.stderr
    assert "Traceback" not in result.stderr + result.stdout


def test_fifty_megabyte_file_is_refused_without_reading_it(tmp_path: Path) -> None:
    big = tmp_path / "big.json"
    with big.open("wb") as handle:
        handle.write(b'{"id": "big", "description": "')
        handle.write(b"x" * (50 * 1024 * 1024))
        handle.write(b'"}')
    result = run_cli("validate", str(big))
    assert result.returncode == 2
    assert "larger than the 8 MiB limit" in result.stderr


def test_goal_with_ten_thousand_outcomes_is_a_clear_error(tmp_path: Path) -> None:
    nxt = {f"o{i}": "COMPLETE" for i in range(10_000)}
    data = json.dumps({"id": "x", "start": "G1", "goals": [{"id": "G1", "next": nxt}]})
    result = run_cli("validate", write(tmp_path, "wide.json", data.encode()))
    assert result.returncode == 2
    assert "$.goals[0].next.o0" in result.stderr
    assert "more problems" in result.stderr  # bounded: not ten thousand lines
    assert len(result.stderr.splitlines()) < 30


def test_missing_file_and_directory(tmp_path: Path) -> None:
    assert "does not exist" in run_cli("validate", str(tmp_path / "nope.json")).stderr
    result = run_cli("validate", str(tmp_path))
    assert result.returncode == 2 and "is a directory" in result.stderr


def test_structural_defects_are_findings_not_read_errors(tmp_path: Path) -> None:
    data = {"id": "x", "goals": [{"id": "G1", "next": {"succeed": "G1", "fail": "ZZ"}}]}
    result = run_cli("validate", write(tmp_path, "d.json", json.dumps(data).encode()),
                     "--format", "json")
    assert result.returncode == 1
    report = json.loads(result.stdout)
    # No vehicle profile either: VEHICLE (M6 and M7 cannot be decided).
    assert {f["code"] for f in report["findings"]} == {"M1", "VEHICLE"} | {"SINK", "G3", "G7"}
    assert report["paths"] is None


def test_read_errors_carry_json_paths() -> None:
    with pytest.raises(OrdersReadError) as caught:
        read_bytes(b'{"id": "x", "goals": [{"id": "G1", "next": {"succeed": 5}}],'
                   b' "terminals": [{"id": "T", "kind": "maybe"}]}')
    paths = [p.path for p in caught.value.problems]
    assert "$.goals[0].next.succeed" in paths
    assert "$.terminals[0].kind" in paths


def test_odd_but_valid_ids_round_trip() -> None:
    data = b'{"id": "m-1.x:y", "start": "a_b.c:d-e", "goals": [{"id": "a_b.c:d-e", "title": ' \
           b'"He said \\"go\\" \\\\ now", "next": {"succeed": "COMPLETE", "fail": "ABORT", ' \
           b'"violate": "ABORT"}}]}'
    assert read_bytes(data).orders.goals[0].id == "a_b.c:d-e"
