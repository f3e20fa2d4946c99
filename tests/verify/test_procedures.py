"""Procedures: a refinement saved by name and version and used by reference.

The orders' digest covers the procedure's digest; an unknown reference or a body that is not
the pinned one is PROCEDURE; a referenced procedure counts exactly like the same refinement
written inline (paths, traces, worst costs)."""

from __future__ import annotations

import copy
import json
from importlib import resources
from pathlib import Path
from typing import Any

import pytest

from countersign.cli import main
from countersign.orders.canonical import digest
from countersign.orders.examples import load_example
from countersign.orders.model import Orders
from countersign.orders.procedure import Procedure, procedure_from_data, read_procedure
from countersign.orders.reader import OrdersReadError, orders_from_data
from countersign.verify.paths import count_paths, iter_paths, trace_text
from countersign.verify.procedures import expand, procedure_findings, uses
from countersign.verify.refine import checked_form
from countersign.verify.report import validate

EXAMPLES = resources.files("countersign.orders.examples") / "procedures"
LIBRARY = EXAMPLES / "library"


def _procedure_data() -> dict[str, Any]:
    data: dict[str, Any] = json.loads((LIBRARY / "cell-search-1.json").read_text())
    return data


def _procedure() -> Procedure:
    return procedure_from_data(_procedure_data())


def _referring_data() -> dict[str, Any]:
    data: dict[str, Any] = json.loads(
        (EXAMPLES / "search-and-sample-procedure.json").read_text())
    return data


def _lookup(*procedures: Procedure) -> Any:
    library = {(p.name, p.version): p for p in procedures}
    return lambda name, version: library.get((name, version))


def _g1(data: dict[str, Any]) -> dict[str, Any]:
    goal: dict[str, Any] = next(g for g in data["goals"] if g["id"] == "G1")
    return goal


def test_the_example_refers_to_the_library_procedure_by_its_digest() -> None:
    procedure = _procedure()
    assert _g1(_referring_data())["refines"] == procedure.reference()
    assert uses(orders_from_data(_referring_data())) == [
        ("cell-search", 1, procedure.digest)]


def test_procedure_digest_covers_name_version_and_every_goal() -> None:
    base = _procedure()
    renamed = _procedure_data() | {"name": "other-search"}
    bumped = _procedure_data() | {"version": 2}
    edited = _procedure_data()
    edited["refines"]["goals"][0]["envelope"]["depth_m"] = [25, 51]
    digests = {base.digest, *(procedure_from_data(d).digest for d in (renamed, bumped, edited))}
    assert len(digests) == 4
    # Key order and whitespace are not content.
    shuffled = json.dumps(dict(reversed(list(_procedure_data().items()))), indent=7)
    assert read_procedure(shuffled.encode()).digest == base.digest


def test_the_orders_digest_covers_the_pinned_procedure_digest() -> None:
    data = _referring_data()
    other = copy.deepcopy(data)
    _g1(other)["refines"]["digest"] = "sha256:" + "0" * 64
    assert digest(orders_from_data(data)) != digest(orders_from_data(other))
    # And the orders as checked and stored (body copied in) cover the body itself.
    procedure = _procedure()
    expanded = expand(orders_from_data(data), _lookup(procedure))
    edited = _procedure_data()
    edited["refines"]["goals"][1]["title"] = "Scan only half the cell"
    changed = procedure_from_data(edited)
    expanded_changed = expand(orders_from_data(data), _lookup(changed))
    assert digest(expanded) != digest(expanded_changed)


def test_unknown_reference_is_a_procedure_error() -> None:
    orders = orders_from_data(_referring_data())
    report = validate(expand(orders, _lookup()))
    procedure = [f for f in report.findings if f.code == "PROCEDURE"]
    assert [(f.severity, f.subjects) for f in procedure] == [("error", ("G1",))]
    assert "does not hold" in procedure[0].message
    assert not report.ok


def test_a_changed_procedure_does_not_pass_as_the_pinned_one() -> None:
    edited = _procedure_data()
    edited["refines"]["goals"][0]["title"] = "Move to any cell"
    changed = procedure_from_data(edited)
    report = validate(expand(orders_from_data(_referring_data()), _lookup(changed)))
    procedure = [f for f in report.findings if f.code == "PROCEDURE"]
    assert len(procedure) == 1 and procedure[0].severity == "error"
    assert procedure[0].details["pinned"] == _procedure().digest
    assert procedure[0].details["actual"] == changed.digest
    assert not report.ok


def test_a_body_edited_inside_the_orders_is_a_procedure_error() -> None:
    expanded = expand(orders_from_data(_referring_data()), _lookup(_procedure()))
    data = expanded.model_dump(mode="json", exclude_unset=True)
    _g1(data)["refines"]["goals"][0]["envelope"]["depth_m"] = [0, 50]
    assert [f.code for f in procedure_findings(orders_from_data(data))] == ["PROCEDURE"]


def test_a_reference_without_digest_is_filled_in_from_the_library() -> None:
    data = _referring_data()
    del _g1(data)["refines"]["digest"]
    bare = orders_from_data(data)
    assert "pins no digest" not in " ".join(f.message for f in procedure_findings(bare))
    expanded = expand(bare, _lookup(_procedure()))
    assert expanded.goal_index()["G1"].refines.digest == _procedure().digest  # type: ignore[union-attr]
    assert procedure_findings(expanded) == []
    # Written with a body but no digest: an error that says which digest to pin.
    with_body = expanded.model_dump(mode="json", exclude_unset=True)
    del _g1(with_body)["refines"]["digest"]
    findings = procedure_findings(orders_from_data(with_body))
    assert len(findings) == 1 and _procedure().digest in findings[0].message


def test_a_referenced_procedure_counts_exactly_like_the_refinement_inlined() -> None:
    inline = load_example("search-and-sample-refined")
    referred = expand(orders_from_data(_referring_data()), _lookup(_procedure()))
    referred = referred.model_copy(update={"id": inline.id, "title": inline.title})
    a, b = validate(inline), validate(referred)
    assert b.ok and [f.to_json() for f in a.findings] == [f.to_json() for f in b.findings]
    assert a.paths is not None and b.paths is not None
    assert a.paths.to_json() == b.paths.to_json()
    assert {q: w.to_json() for q, w in (a.costs or {}).items()} == {
        q: w.to_json() for q, w in (b.costs or {}).items()}
    (_, graph_a), (_, graph_b) = checked_form(inline), checked_form(referred)
    counts_a, counts_b = count_paths(graph_a), count_paths(graph_b)
    assert counts_a is not None and counts_b is not None
    for offset in (0, counts_a.total // 2, counts_a.total - 5):
        traces_a = [trace_text(graph_a, p) for p in iter_paths(graph_a, counts_a, offset, 5)]
        traces_b = [trace_text(graph_b, p) for p in iter_paths(graph_b, counts_b, offset, 5)]
        assert traces_a == traces_b and len(traces_a) == 5


def test_orders_without_references_are_untouched() -> None:
    orders = load_example("search-and-sample-refined")
    assert expand(orders, _lookup(_procedure())) is orders
    assert procedure_findings(orders) == []


@pytest.mark.parametrize(("refines", "says"), [
    ({"version": 1}, "name the procedure too"),
    ({"procedure": "cell-search"}, "names no version"),
    ({"procedure": "cell-search", "version": 0}, "greater than or equal to 1"),
    ({"procedure": "cell-search", "version": 1, "digest": "md5:abc"}, "should match pattern"),
    ({"procedure": "<b>x</b>", "version": 1}, "is not a valid id"),
])
def test_malformed_references_are_read_errors(refines: dict[str, Any], says: str) -> None:
    data = _referring_data()
    _g1(data)["refines"] = refines
    with pytest.raises(OrdersReadError) as caught:
        orders_from_data(data)
    assert says in caught.value.summary()
    assert "$.goals[0].refines" in caught.value.summary()


@pytest.mark.parametrize(("change", "says"), [
    ({"format": "countersign.orders/1"}, "format must be 'countersign.procedure/1'"),
    ({"version": "2"}, "valid integer"),
    ({"version": True}, "valid integer"),
    ({"refines": {"procedure": "x", "version": 1}}, "not a reference to another procedure"),
    ({"refines": {"start": "A"}}, "has no goals"),
    ({"extra": 1}, "Extra inputs"),
])
def test_malformed_procedures_are_read_errors(change: dict[str, Any], says: str) -> None:
    with pytest.raises(OrdersReadError) as caught:
        procedure_from_data(_procedure_data() | change)
    assert says in caught.value.summary()


def test_oversized_or_non_json_procedure_files_are_refused() -> None:
    with pytest.raises(OrdersReadError, match="at most"):
        read_procedure(b" " * (3 * 1024 * 1024))
    with pytest.raises(OrdersReadError, match="invalid JSON"):
        read_procedure(b"{")


# --- the command line ----------------------------------------------------------------------

def _run(capsys: pytest.CaptureFixture[str], *argv: str) -> tuple[int, str, str]:
    code = main(list(argv))
    out, err = capsys.readouterr()
    return code, out, err


def test_cli_validate_fills_references_from_the_library(
        capsys: pytest.CaptureFixture[str]) -> None:
    orders = str(EXAMPLES / "search-and-sample-procedure.json")
    code, out, _ = _run(capsys, "validate", orders, "--format", "json")
    assert code == 1 and "PROCEDURE" in out
    code, out, _ = _run(capsys, "validate", orders, "--procedures", str(LIBRARY),
                        "--format", "json")
    report = json.loads(out)
    assert code == 0 and report["ok"] and report["paths"]["count"] == 867


def test_cli_library_problems_exit_2_and_say_where(
        tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    orders = str(EXAMPLES / "search-and-sample-procedure.json")
    (tmp_path / "broken.json").write_text('{"format": "countersign.procedure/1"}')
    code, _, err = _run(capsys, "validate", orders, "--procedures", str(tmp_path))
    assert code == 2 and "broken.json is not a procedure" in err and "$.name" in err
    twin = tmp_path / "twin"
    twin.mkdir()
    (twin / "a.json").write_text(json.dumps(_procedure_data()))
    edited = _procedure_data()
    edited["refines"]["goals"][0]["title"] = "changed"
    (twin / "b.json").write_text(json.dumps(edited))
    code, _, err = _run(capsys, "validate", orders, "--procedures", str(twin))
    assert code == 2 and "both hold procedure cell-search version 1" in err
    code, _, err = _run(capsys, "paths", orders, "--procedures", str(tmp_path / "none"))
    assert code == 2 and "cannot read procedure file" in err


def test_cli_procedures_check_and_reference(
        tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    file = str(LIBRARY / "cell-search-1.json")
    code, out, _ = _run(capsys, "procedures", "check", file, "--format", "json")
    checked = json.loads(out)
    assert code == 0 and checked["ok"] and checked["digest"] == _procedure().digest
    assert checked["paths"]["count"] > 0
    code, out, _ = _run(capsys, "procedures", "reference", file)
    assert code == 0 and json.loads(out) == _procedure().reference()
    looping = _procedure_data()
    del looping["refines"]["within"], looping["refines"]["on_timeout"]
    (tmp_path / "loop.json").write_text(json.dumps(looping))
    code, out, _ = _run(capsys, "procedures", "check", str(tmp_path / "loop.json"))
    assert code == 1 and "REFINE" in out


def test_team_members_references_are_expanded_and_checked() -> None:
    data = _referring_data()
    members = []
    for name in ("auv-1", "auv-2"):
        member = copy.deepcopy(data)
        member["vehicle"] = name
        member["vehicles"][0]["id"] = name
        members.append({"vehicle": name, "orders": member})
    team = {"format": "countersign.orders/1", "id": "pair", "team": members}
    orders = Orders.model_validate(team)
    assert len(uses(orders)) == 1
    expanded = expand(orders, _lookup(_procedure()))
    assert expanded.team is not None
    assert all(procedure_findings(m.orders) == [] for m in expanded.team)
    assert all(procedure_findings(m.orders) for m in orders.team or [])


def test_plain_orders_name_the_procedure_and_its_goals(
        capsys: pytest.CaptureFixture[str]) -> None:
    orders = str(EXAMPLES / "search-and-sample-procedure.json")
    code, out, _ = _run(capsys, "export", orders, "--format", "plain", "--procedures",
                        str(LIBRARY))
    assert code == 0
    assert (f"Goal 1 is carried out by procedure cell-search version 1 ({_procedure().digest}):"
            " 1.1 Move to the next unvisited cell of Area A") in out
    code, out, _ = _run(capsys, "export", orders, "--format", "plain")
    assert "no goal copied in from the library" in out


def test_a_procedure_naming_a_procedure_is_checked_with_its_goals_copied_in(
        tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    outer = {"format": "countersign.procedure/1", "name": "search-twice", "version": 1,
             "refines": {"start": "S1", "goals": [
                 {"id": "S1", "title": "Search", "refines": _procedure().reference(),
                  "next": {"succeed": "DONE", "fail": "GAVE_UP", "violate": "HALT"}}],
                 "terminals": [
                     {"id": "DONE", "kind": "complete", "returns": "succeed"},
                     {"id": "GAVE_UP", "kind": "abort", "returns": "fail"},
                     {"id": "HALT", "kind": "abort", "returns": "violate"}]}}
    file = tmp_path / "outer.json"
    file.write_text(json.dumps(outer))
    code, out, _ = _run(capsys, "procedures", "check", str(file), "--format", "json")
    assert code == 1 and "PROCEDURE" in out
    code, out, _ = _run(capsys, "procedures", "check", str(file), "--format", "json",
                        "--procedures", str(LIBRARY))
    checked = json.loads(out)
    assert code == 0 and checked["ok"], checked["findings"]
    assert checked["digest"] != procedure_from_data(outer).digest  # the goals are in it now
