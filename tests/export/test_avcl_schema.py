"""AVCL exports against the NPS AVCL 3.1 schema (../shared/reference/nps-ethical-control).

Every built-in example and every NPS mission, exported, must validate against AVCL.3.1.xsd with
lxml's XMLSchema and, where it is installed, with xmllint (libxml2-utils), and read back to the
same MEA: start, goals with their successors per outcome, terminals with their kinds, and the
same paths where they can be counted. Orders at the edges of what AVCL can say (ids that are not
XML names, dangling successors, duplicate ids, behaviours without a goal action) must still give
valid documents.
"""

from __future__ import annotations

import shutil
import subprocess
from pathlib import Path
from typing import Any

import pytest

from countersign.export.avcl import export_avcl
from countersign.orders.avcl import read_avcl
from countersign.orders.avcl_writer import write_avcl
from countersign.orders.examples import example_names, load_example
from countersign.orders.model import Orders
from countersign.orders.reader import read_file
from countersign.verify.paths import iter_paths, paths_of
from countersign.verify.structure import check_structure

NPS = Path(__file__).resolve().parents[2].parent / "shared" / "reference" / "nps-ethical-control"
SCHEMA = NPS / "schemas" / "AVCL.3.1.xsd"
AVCL_DIR = NPS / "missions" / "avcl"
MISSIONS = sorted(AVCL_DIR.glob("*.xml")) if AVCL_DIR.is_dir() else []
XMLLINT = shutil.which("xmllint")

pytestmark = pytest.mark.skipif(
    not SCHEMA.is_file(),
    reason=f"NPS AVCL schema not found at {SCHEMA}; conformance tests need ../shared",
)


@pytest.fixture(scope="module")
def schema() -> Any:
    etree = pytest.importorskip("lxml.etree")
    return etree.XMLSchema(etree.parse(str(SCHEMA)))


def assert_valid(text: str, schema: Any, tmp_path: Path) -> None:
    from lxml import etree

    document = etree.fromstring(text.encode("utf-8"))
    assert schema.validate(document), [str(e) for e in schema.error_log][:5]
    # XML Schema's IDREF rule (every reference names an id of the document), which libxml2
    # does not enforce and Xerces-based tools such as the NPS AUV Workbench do.
    ids = set(document.xpath("//@id"))
    references = document.xpath("//@nextOnSuccess | //@nextOnFailure | //@nextOnException"
                                " | //@refid")
    assert set(references) <= ids, set(references) - ids
    if XMLLINT is not None:  # the NPS tools' own kind of check, on the bytes written
        path = tmp_path / "export.xml"
        path.write_text(text, encoding="utf-8")
        run = subprocess.run([XMLLINT, "--noout", "--schema", str(SCHEMA), str(path)],
                             capture_output=True, text=True, check=False)
        assert run.returncode == 0, run.stderr[-2000:]


def mea(orders: Orders) -> dict[str, Any]:
    graph, counts = paths_of(orders)
    paths = ([(p.goals, p.outcomes, p.terminal) for p in iter_paths(graph, counts)]
             if counts is not None else None)
    return {
        "start": orders.start,
        "goals": {g.id: {o: g.successors(o) for o in ("succeed", "fail", "violate")}
                  for g in orders.goals},
        "terminals": {t.id: t.kind for t in orders.effective_terminals},
        "paths": paths,
    }


def every_mission() -> list[tuple[str, Orders]]:
    missions = [(f"example:{name}", load_example(name)) for name in example_names()]
    return missions + [(path.name, read_file(path).orders) for path in MISSIONS]


def test_the_nps_folder_holds_the_ten_missions() -> None:
    assert len(MISSIONS) == 10


@pytest.mark.parametrize(("name", "orders"), every_mission(), ids=lambda v: v
                         if isinstance(v, str) else "")
def test_export_validates_and_reads_back_to_the_same_mea(
        name: str, orders: Orders, schema: Any, tmp_path: Path) -> None:
    text = write_avcl(orders)
    assert_valid(text, schema, tmp_path)
    back = read_avcl(text.encode("utf-8"), f"{name}.xml").orders
    assert mea(back) == mea(orders)
    assert [g.behavior for g in back.goals] == [g.behavior for g in orders.goals]
    assert {f.code for f in check_structure(back)} == {f.code for f in check_structure(orders)}


def test_the_nps_dialect_is_read_but_never_written(schema: Any, tmp_path: Path) -> None:
    # SailorOverboard.xml fails its own schema (vehicleName on the root, MissionDefinition);
    # its export validates and carries the vehicle in the head instead.
    original = read_file(AVCL_DIR / "SailorOverboard.xml").orders
    text = write_avcl(original)
    assert_valid(text, schema, tmp_path)
    assert "MissionDefinition" not in text and "<AVCL version=\"3.1\">" in text
    back = read_avcl(text.encode("utf-8")).orders
    assert back.vehicles[0].title == original.vehicles[0].title
    assert back.target_vehicle() is not None


def edge_orders() -> Orders:
    goals = [
        {"id": "1st", "title": "Leave the dock", "behavior": "transit",
         "next": {"succeed": "a:b", "fail": "ABORT", "violate": "ABORT"}},
        {"id": "a:b", "title": "Mark the wreck", "behavior": "mark_target",
         "params": {"phase": "Survey", "pd": 0.9, "lane": 3},
         "next": {"succeed": ["COMPLETE", "a:b"], "fail": "NOWHERE", "violate": "ABORT"}},
        {"id": "1st", "title": "A second goal with a used id",
         "next": {"succeed": "COMPLETE", "fail": "ABORT", "violate": "ABORT"}},
    ]
    # A complete terminal whose words would say abort, and an abort one that says complete.
    terminals = [{"id": "FAILSAFE_DONE", "kind": "complete", "title": "Abort drill finished"},
                 {"id": "SUCCESS_HALT", "kind": "abort", "title": "Mission complete? No"}]
    return Orders.model_validate({"id": "edges", "start": "1st", "goals": goals,
                                  "terminals": terminals,
                                  "vehicle": "v", "vehicles": [{"id": "v", "title": "Iver",
                                                                "vehicle_type": "uuv"}]})


def test_orders_at_the_edges_of_avcl_still_validate(schema: Any, tmp_path: Path) -> None:
    orders = Orders.model_validate({
        **edge_orders().model_dump(mode="json", exclude_unset=True),
        "terminals": [*edge_orders().model_dump(mode="json")["terminals"],
                      {"id": "ABORT", "kind": "abort"}, {"id": "COMPLETE", "kind": "complete"}],
    })
    text = write_avcl(orders)
    assert_valid(text, schema, tmp_path)
    back = read_avcl(text.encode("utf-8")).orders
    # Ids that are not XML names come back; the dangling successor stays dangling (G3).
    assert [g.id for g in back.goals] == ["1st", "a:b"]
    assert back.start == "1st"
    assert {g.id: g.next for g in back.goals} == {
        "1st": {"succeed": "a:b", "fail": "ABORT", "violate": "ABORT"},
        "a:b": {"succeed": "COMPLETE", "fail": "NOWHERE", "violate": "ABORT"}}
    assert "G3" in {f.code for f in check_structure(back)}
    assert {t.id: t.kind for t in back.effective_terminals} == {
        "FAILSAFE_DONE": "complete", "SUCCESS_HALT": "abort", "ABORT": "abort",
        "COMPLETE": "complete"}
    assert [g.behavior for g in back.goals] == ["transit", "mark_target"]
    assert back.goal_index()["a:b"].params == {"phase": "Survey"}
    assert back.vehicles[0].model_extra == {"vehicle_type": "uuv"}
    assert '<Vehicle vehicleType="UUV" />' in text


def test_what_avcl_cannot_carry_is_named_in_notes() -> None:
    export = export_avcl(edge_orders())
    found = {(n.code, n.path) for n in export.notes}
    assert {("ID", "/goals"), ("DUP", "/goals/2"), ("DANGLING", "/goals"),
            ("CHOICE", "/goals/1/next/succeed"), ("BEHAVIOR", "/goals/1/behavior"),
            ("PARAMS", "/goals/1/params/lane"), ("VEHICLE", "/vehicles/0")} <= found
    assert ("PARAMS", "/goals/1/params/pd") in found  # pd is a Search's, not a MarkTarget's
    rules = export_avcl(load_example("search-and-sample-rules"))
    codes = {(n.code, n.path) for n in rules.notes}
    assert {("NORM", "/norms/0"), ("RULES", "/rules"), ("CONSTRAINT", "/constraints/0"),
            ("ENVELOPE", "/goals/0/envelope/depth_m"), ("REQUIRES", "/goals/0/requires")} <= codes
    assert all(n.message for n in rules.notes)
    assert rules.primary.name == "search-and-sample-rules.xml"
