"""A team's orders exported a member at a time (`--member`): that vehicle's own orders, its
meeting goals holding at the meeting point and waiting for every partner; a team without a
member, or an unknown member, refused naming the option."""

from __future__ import annotations

import json
import re
from pathlib import Path
from typing import Any
from urllib.parse import unquote

import imcpy
import pytest

from countersign.cli import main
from countersign.export.avcl import export_avcl
from countersign.export.notes import VehicleExport
from countersign.export.team import MemberNeeded, UnknownMember, select_member
from countersign.export.vehicle import export_vehicle
from countersign.orders.examples import example_bytes
from countersign.orders.model import Orders
from countersign.orders.reader import read_bytes
from countersign.verify.paths import iter_paths, paths_of

from .readers import read_bhv, read_imc
from .strict_imc import StrictReader, imc_xml_or_skip

TEAM = "example:search-and-sample-team"
AVCL_SCHEMA = Path(__file__).resolve().parents[2].parent / "shared" / "reference" / \
    "nps-ethical-control" / "schemas" / "AVCL.3.1.xsd"


def _team() -> Orders:
    return read_bytes(example_bytes("search-and-sample-team"), "team").orders


def _blocks(bhv: str) -> dict[str, list[str]]:
    """Behaviour name -> its parameter lines."""
    out: dict[str, list[str]] = {}
    for match in re.finditer(r"^Behavior = \w+\n\{\n(.*?)^\}", bhv, re.M | re.S):
        lines = [line.strip() for line in match.group(1).splitlines()]
        name = next(line.split("=", 1)[1].strip() for line in lines if line.startswith("name"))
        out[name] = lines
    return out


def _text(export: VehicleExport, suffix: str) -> str:
    return next(f.content.decode() for f in export.files if f.name.endswith(suffix))


@pytest.mark.parametrize(("vehicle", "goal", "partner"), [("remus-100", "G4", "vehicle-2"),
                                                          ("vehicle-2", "G2", "remus-100")])
def test_a_meeting_goal_holds_posts_its_arrival_and_waits_for_all(
        vehicle: str, goal: str, partner: str) -> None:
    export = export_vehicle(_team(), "moos", member=vehicle)
    bhv = _text(export, ".bhv")
    own = next(m.orders for m in _team().team or () if m.vehicle == vehicle)
    # The member's own MEA, nothing of the partner's.
    assert read_bhv(bhv).edges[goal] == {o: own.goal_index()[goal].successors(o)[0]
                                         for o in ("succeed", "fail", "violate")}
    blocks = {name: lines for name, lines in _blocks(bhv).items() if f"_{goal}_" in name}
    hold = next(lines for name, lines in blocks.items() if name.endswith("_hold"))
    # Never ends by itself: no end flag, no duration (the partner may be hours late).
    assert not any(line.startswith(("endflag", "duration")) for line in hold)
    arrive = next(lines for name, lines in blocks.items() if name.endswith("_arrive"))
    assert f"runflag = MEET_R1_ARRIVED = {vehicle.replace('-', '_')}" in arrive
    assert any(line.startswith("condition = NAV_X >=") for line in arrive)
    for outcome in ("succeed", "fail", "violate"):
        relay = next(lines for name, lines in blocks.items() if name.endswith(f"_{outcome}"))
        assert "condition = MEET_R1_ALL = true" in relay, relay
    # A broken constraint at the meeting is its outcome, not a move of one member alone.
    for name, lines in blocks.items():
        if "_violate_" in name:
            assert "runflag = GOAL_OUTCOME = violate" in lines
            assert not any(line.startswith("runflag = MISSION_GOAL") for line in lines)
    assert "initialize MEET_R1_ALL = false" in bhv
    moos = _text(export, ".moos")
    assert "ProcessConfig = pShare" in moos and "output = src_name = MEET_R1_ARRIVED" in moos
    assert "Log = MEET_R1_ARRIVED @ 0" in moos and "Log = MEET_R1_ALL @ 0" in moos
    assert f"members {', '.join(sorted((vehicle, partner)))}" in moos
    assert any(n.code == "MEET" and partner in n.message for n in export.notes)


def test_one_vehicles_orders_export_as_before() -> None:
    """Outside a team a `meet` means nothing to a vehicle: the files carry no meeting."""
    orders = read_bytes(example_bytes("search-and-sample"), "x").orders
    data = orders.model_dump(mode="json", exclude_unset=True)
    data["goals"] = [{**g, "meet": "R1"} if g["id"] == "G4" else g for g in data["goals"]]
    with_meet = export_vehicle(Orders.model_validate(data), "moos")
    assert "MEET_" not in _text(with_meet, ".bhv") and "pShare" not in _text(with_meet, ".moos")


def test_team_without_member_or_unknown_member_is_refused_by_name() -> None:
    with pytest.raises(MemberNeeded, match="remus-100, vehicle-2"):
        export_vehicle(_team(), "moos")
    with pytest.raises(UnknownMember, match=r"'auv-9'.*remus-100, vehicle-2"):
        export_vehicle(_team(), "imc", member="auv-9")
    single = read_bytes(example_bytes("search-and-sample"), "x").orders
    with pytest.raises(UnknownMember, match="one vehicle's, not a team's"):
        select_member(single, "remus-100")


def test_imc_meeting_maneuver_names_meet_and_partners_within_imc_xml(
        tmp_path_factory: pytest.TempPathFactory) -> None:
    strict = StrictReader(imc_xml_or_skip(), tmp_path_factory.mktemp("pyimclsts"))
    data = export_vehicle(_team(), "imc", member="vehicle-2").primary.content
    plan = strict.read(data)
    lenient, graph = read_imc(data)
    step = next(m["data"] for m in plan["maneuvers"] if m["maneuver_id"] == "G2")
    custom = {k: unquote(v) for k, v in (kv.split("=", 1) for kv in step["custom"].split(";"))}
    assert custom["meet"] == "R1" and custom["meet.partners"] == "remus-100"
    assert step["duration"] == 0  # no clock ends a meeting
    held = next(m.data for m in lenient.maneuvers if m.maneuver_id == "G2")
    assert isinstance(held, imcpy.Loiter) and "meet=R1" in held.custom
    assert graph.start == "G1" and set(graph.edges) == {"G1", "G2", "G3"}


def test_avcl_of_a_member_is_schema_valid_with_a_meeting_note(tmp_path: Path) -> None:
    member = select_member(_team(), "remus-100")
    assert member is not None
    export = export_avcl(member.orders, member)
    assert any(n.code == "MEET" and n.path == "/goals/3/meet" and "R1" in n.message
               and "vehicle-2" in n.message for n in export.notes)
    if not AVCL_SCHEMA.is_file():
        pytest.skip(f"NPS AVCL schema not found at {AVCL_SCHEMA}")
    from tests.export.test_avcl_schema import assert_valid

    etree = pytest.importorskip("lxml.etree")
    assert_valid(export.primary.content.decode(), etree.XMLSchema(etree.parse(str(AVCL_SCHEMA))),
                 tmp_path)


@pytest.mark.parametrize("args", [
    ["export", TEAM, "--format", "moos"], ["export", TEAM, "--format", "imc"],
    ["export", TEAM, "--format", "avcl"], ["export", TEAM, "--format", "moos", "--member", "x"],
    ["export", "example:search-and-sample", "--format", "moos", "--member", "remus-100"],
    ["execution", "check", TEAM, "log.ndjson"],
    ["execution", "check", TEAM, "log.ndjson", "--member", "x"],
], ids=["moos", "imc", "avcl", "unknown", "not-a-team", "check", "check-unknown"])
def test_cli_refuses_with_exit_2_naming_member(args: list[str],
                                               capsys: pytest.CaptureFixture[str]) -> None:
    assert main(args) == 2
    err = capsys.readouterr().err
    assert "--member" in err and "Traceback" not in err


def test_cli_writes_a_members_files(tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    assert main(["export", TEAM, "--format", "moos", "--member", "vehicle-2",
                 "--output", str(tmp_path)]) == 0
    assert sorted(p.name for p in tmp_path.iterdir()) == [
        "search-and-sample-v2.bhv", "search-and-sample-v2.moos"]
    assert "note MEET" in capsys.readouterr().err
    assert main(["export", TEAM, "--format", "json", "--member", "vehicle-2"]) == 0
    assert json.loads(capsys.readouterr().out)["vehicle"] == "vehicle-2"


def _log(goals: list[tuple[str, str]]) -> str:
    lines: list[dict[str, Any]] = []
    for step, (goal, outcome) in enumerate(goals):
        lines.append({"goal": goal, "outcome": outcome,
                      "start": f"2026-01-01T0{step}:00:00Z", "time": f"2026-01-01T0{step}:30:00Z"})
    return "".join(json.dumps(line) + "\n" for line in lines)


def test_execution_check_reads_a_members_log_against_its_own_orders(
        tmp_path: Path, capsys: pytest.CaptureFixture[str]) -> None:
    log = tmp_path / "v2.ndjson"
    log.write_text(_log([("G1", "succeed"), ("G2", "succeed"), ("G3", "succeed")]))
    own = next(m.orders for m in _team().team or () if m.vehicle == "vehicle-2")
    graph, counts = paths_of(own)
    assert counts is not None
    index = next(p.index for p in iter_paths(graph, counts)
                 if p.goals == ("G1", "G2", "G3") and p.outcomes == ("succeed",) * 3)
    code = main(["execution", "check", TEAM, str(log), "--member", "vehicle-2",
                 "--format", "json"])
    verdict = json.loads(capsys.readouterr().out)
    assert code in (0, 3) and verdict["path"] == index and verdict["terminal"] == "COMPLETE"
    # The same log is no path of the other member's orders (its G2 is a sample, then G3).
    assert main(["execution", "check", TEAM, str(log), "--member", "remus-100"]) == 1
