"""AVCL XML input: NPS conventions, SINK warnings for defaulted handlers, safe parsing."""

from __future__ import annotations

from typing import Any

import pytest

from countersign.orders.avcl import read_avcl
from countersign.orders.defaults import defaulted_findings
from countersign.orders.model import Orders
from countersign.orders.reader import OrdersReadError, ReadResult, read_bytes
from countersign.verify.structure import check_structure


def avcl(goals: str, *, root: str = "<AVCL>", head: str = "") -> bytes:
    closing = "</" + root[1:].split()[0].rstrip(">") + ">"
    return (
        f'<?xml version="1.0" encoding="UTF-8"?>\n{root}<head>{head}</head><body>'
        f"<MissionDefinition><AgendaMission><GoalList>{goals}</GoalList></AgendaMission>"
        f"</MissionDefinition></body>{closing}"
    ).encode()


def read(goals: str, **kwargs: str) -> ReadResult:
    return read_avcl(avcl(goals, **kwargs), "test.xml")


def sink_warnings(result: ReadResult) -> set[tuple[str, str, str]]:
    return {
        (f.subjects[0], f.details["outcome"], f.details["defaulted_to"])
        for f in result.findings
        if f.code == "SINK" and f.severity == "warning"
    }


def rejected(data: bytes) -> OrdersReadError:
    # How fast: tests/bench/bench_fail_fast.py (a wall-clock bound here flakes on a busy host).
    with pytest.raises(OrdersReadError) as caught:
        read_bytes(data, "hostile.xml")
    return caught.value


THREE = (
    '<Goal id="A" title="Search" nextOnSuccess="B" nextOnFailure="DONE" nextOnException="DONE">'
    '<Search requiredPD="0.8"/></Goal>'
    '<Goal id="B" title="Sample" nextOnSuccess="DONE" nextOnFailure="DONE" '
    'nextOnException="DONE"><SampleEnvironment/></Goal>'
    '<Goal id="DONE" title="Halt" description="Operations complete, final success state"/>'
)


def test_goals_start_and_terminal_in_document_order() -> None:
    result = read(THREE)
    orders = result.orders
    assert result.findings == []
    assert orders.start == "A"
    assert [g.id for g in orders.goals] == ["A", "B"]
    assert orders.terminals is not None
    assert [(t.id, t.kind, t.title) for t in orders.terminals] == [("DONE", "complete", "Halt")]
    assert orders.goals[0].next == {"succeed": "B", "fail": "DONE", "violate": "DONE"}
    assert check_structure(orders) == []


def test_missing_failure_defaults_to_success_with_warnings() -> None:
    result = read(
        '<Goal id="A" title="Transit" nextOnSuccess="B"/>'
        '<Goal id="B" nextOnSuccess="END" nextOnFailure="A2"/>'
        '<Goal id="A2" nextOnSuccess="END" nextOnFailure="END" nextOnException="END"/>'
        '<Goal id="END"/>'
    )
    goals = result.orders.goal_index()
    assert goals["A"].next == {"succeed": "B", "fail": "B", "violate": "B"}
    assert goals["B"].next == {"succeed": "END", "fail": "A2", "violate": "A2"}
    assert sink_warnings(result) == {
        ("A", "fail", "B"),
        ("A", "violate", "B"),
        ("B", "violate", "A2"),
    }
    messages = {(f.subjects[0], f.details["outcome"]): f.message for f in result.findings}
    assert "nextOnFailure" in messages[("A", "fail")]
    assert "NPS convention" in messages[("A", "fail")]
    assert "like a success" in messages[("A", "fail")]
    assert "nextOnException" in messages[("B", "violate")]
    assert "like a failure" in messages[("B", "violate")]
    assert "A2" in messages[("B", "violate")]
    # The defaults leave nothing missing, so the structure check has no SINK error.
    assert not [f for f in check_structure(result.orders) if f.code == "SINK"]


def test_a_defaulted_record_warns_only_while_the_outcome_still_follows_its_model() -> None:
    """The record travels in JSON orders too, so it is judged against the successors as they
    are now: an outcome the author re-routed, a record naming no NPS default, or outcomes
    with no successor give no warning (and no crash); the others keep theirs."""
    def goal(goal_id: str, next_: dict[str, str], defaulted: dict[str, str]) -> dict[str, Any]:
        return {"id": goal_id, "title": f"Goal {goal_id}", "next": next_, "defaulted": defaulted}

    both = {"fail": "succeed", "violate": "fail"}
    orders = Orders.model_validate({"id": "m", "vehicle": "v", "start": "A", "goals": [
        goal("A", {"succeed": "B", "fail": "B", "violate": "B"}, both),
        goal("B", {"succeed": "COMPLETE", "fail": "ABORT", "violate": "ABORT"}, both),
        goal("C", {"succeed": "COMPLETE", "fail": "COMPLETE", "violate": "COMPLETE"},
             {"fail": "violate", "violate": "abort"}),
        goal("D", {"violate": "ABORT"}, {"fail": "succeed"}),
        goal("E", {"succeed": "NOWHERE", "fail": "NOWHERE", "violate": "ABORT"},
             {"fail": "succeed"}),
    ]})
    found = {(f.subjects[0], f.details["outcome"]): f for f in defaulted_findings(orders)}
    assert sorted(found) == [("A", "fail"), ("A", "violate"), ("B", "violate"), ("E", "fail")]
    assert found[("A", "fail")].message == (
        "Goal Goal A does not say what comes next when it fails: the AVCL orders give no "
        "nextOnFailure. Following the NPS convention, a failure is handled like a success, so "
        "the mission continues with Goal B. Confirm that this is intended, or add the handler "
        "explicitly."
    )
    assert found[("B", "violate")].details["defaulted_to"] == "ABORT"
    assert "continues with Mission abort." in found[("B", "violate")].message
    # A target that is neither a goal nor a terminal (G3) is named by its id.
    assert "continues with NOWHERE." in found[("E", "fail")].message


def test_goal_with_only_failure_handler_stays_a_goal_with_a_sink() -> None:
    result = read(
        '<Goal id="A" nextOnSuccess="B" nextOnFailure="B" nextOnException="B"/>'
        '<Goal id="B" nextOnFailure="END"/>'
        '<Goal id="END" description="final failure state"/>'
    )
    goal = result.orders.goal_index()["B"]
    assert goal.next == {"fail": "END", "violate": "END"}
    assert sink_warnings(result) == {("B", "violate", "END")}
    errors = [
        (f.subjects, f.details["outcome"])
        for f in check_structure(result.orders)
        if f.code == "SINK"
    ]
    assert errors == [(("B",), "succeed")]


@pytest.mark.parametrize(
    ("terminal", "kind"),
    [
        ('title="Halt" description="Unable to continue, final failure state"', "abort"),
        ('title="Halt and activate recovery beacon"', "abort"),
        ('title="Halt and await further orders"', "abort"),
        ('title="Stop" description="Unexpected problem, final exception state"', "abort"),
        ('title="Halt" description="Operations complete"', "complete"),
        ('title="Halt" description="final success state"', "complete"),
        ('title="Evade, Escape"', "complete"),  # neutral words, reached on success
    ],
)
def test_terminal_kind_from_words_or_success_edge(terminal: str, kind: str) -> None:
    result = read(
        '<Goal id="A" nextOnSuccess="T" nextOnFailure="T" nextOnException="T"/>'
        f'<Goal id="T" {terminal}/>'
    )
    assert result.orders.terminals is not None
    assert [t.kind for t in result.orders.terminals] == [kind]


def test_neutral_terminal_reached_only_on_failure_is_abort() -> None:
    result = read(
        '<Goal id="A" nextOnSuccess="OK" nextOnFailure="STOP" nextOnException="STOP"/>'
        '<Goal id="OK" title="Go home"/><Goal id="STOP" title="Stop here"/>'
    )
    assert result.orders.terminals is not None
    assert {t.id: t.kind for t in result.orders.terminals} == {"OK": "complete", "STOP": "abort"}


def test_no_terminal_goals_keeps_default_terminals() -> None:
    result = read('<Goal id="A" nextOnSuccess="COMPLETE" nextOnFailure="ABORT"/>')
    assert result.orders.terminals is None
    assert {t.id for t in result.orders.effective_terminals} == {"COMPLETE", "ABORT"}
    assert check_structure(result.orders) == []


def test_unknown_target_is_kept_and_reported_as_g3() -> None:
    result = read(
        '<Goal id="A" nextOnSuccess="NOWHERE" nextOnFailure="END" nextOnException="END"/>'
        '<Goal id="END" title="Done"/>'
    )
    assert result.orders.goals[0].next["succeed"] == "NOWHERE"
    g3 = [f for f in check_structure(result.orders) if f.code == "G3"]
    assert [(f.subjects, f.details["outcome"]) for f in g3] == [(("A", "NOWHERE"), "succeed")]


def test_goal_details_behavior_duration_pd_phase() -> None:
    result = read(
        '<Goal id="G1" title="  Track  " description="Follow it" phase="Track" '
        'nextOnSuccess="G2" nextOnFailure="G2" nextOnException="G2">'
        '<Risk riskName="x"/><MonitorTransmissions/><OperatingArea refid="Op"/>'
        '<Duration value="600"/><ReportingCriteria value="periodic"/></Goal>'
        '<Goal id="G2" nextOnSuccess="G3" nextOnFailure="G3" nextOnException="G3">'
        '<Search datumType="point" requiredPD="0.5"/><Duration value="0"/></Goal>'
        '<Goal id="G3" nextOnSuccess="G4" nextOnFailure="G4" nextOnException="G4">'
        '<Risk riskName="only a risk"/></Goal>'
        '<Goal id="G4" nextOnSuccess="G5" nextOnFailure="G5" nextOnException="G5">'
        "<MarkTarget/></Goal>"
        '<Goal id="G5" title="End"/>'
    )
    goals = result.orders.goal_index()
    g1, g2, g3, g4 = goals["G1"], goals["G2"], goals["G3"], goals["G4"]
    assert (g1.title, g1.description, g1.behavior) == (
        "Track",
        "Follow it",
        "monitor_transmissions",
    )
    assert g1.requires == []
    assert g1.params == {"phase": "Track"}
    assert g1.cost is not None and g1.cost.duration_s == 600
    assert g1.area is None
    assert (g2.behavior, g2.params) == ("search", {"pd": 0.5})
    assert g2.cost is not None and g2.cost.duration_s == 0
    assert (g3.behavior, g3.requires, g3.cost) == (None, [], None)
    assert g4.behavior == "mark_target"


def test_operating_area_with_three_points_becomes_an_area() -> None:
    result = read(
        '<Goal id="G1" nextOnSuccess="END" nextOnFailure="END" nextOnException="END">'
        '<Patrol/><OperatingArea id="Box" description="Test box"><Polygon>'
        '<LatitudeLongitude latitude="36.70" longitude="-121.90"/>'
        '<LatitudeLongitude latitude="36.70" longitude="-121.87"/>'
        '<LatitudeLongitude latitude="N36°41.7\'" longitude="W121°52.2\'"/>'
        "</Polygon></OperatingArea></Goal>"
        '<Goal id="G2" nextOnSuccess="END" nextOnFailure="END" nextOnException="END">'
        '<Patrol/><OperatingArea><Point><LatitudeLongitude latitude="1" longitude="2"/>'
        "</Point></OperatingArea></Goal>"
        '<Goal id="END"/>'
    )
    orders = result.orders
    assert [a.id for a in orders.areas] == ["G1-area"]
    area = orders.areas[0]
    assert area.title == "Test box"
    assert area.polygon[:2] == [(36.70, -121.90), (36.70, -121.87)]
    assert area.polygon[2] == pytest.approx((36.695, -121.87))
    assert orders.goal_index()["G1"].area == "G1-area"
    assert orders.goal_index()["G2"].area is None


def test_mission_id_title_and_vehicle() -> None:
    result = read(
        THREE,
        root='<AVCL version="3.1" vehicleName="Rescue Drone #2" vehicleType="UAV">',
        head='<meta name="title" content="Lifeboat Tracking.xml"/>'
        '<meta name="description" content="Find the lifeboat."/>',
    )
    orders = result.orders
    assert orders.id == "lifeboat-tracking"
    assert orders.title == "Lifeboat Tracking"
    assert orders.description == "Find the lifeboat."
    assert orders.vehicle == "rescue-drone--2"
    assert len(orders.vehicles) == 1
    vehicle = orders.vehicles[0]
    assert (vehicle.id, vehicle.title) == ("rescue-drone--2", "Rescue Drone #2")
    assert vehicle.model_extra == {"vehicle_type": "UAV"}


def test_mission_id_from_file_name_without_meta_title() -> None:
    result = read_avcl(avcl(THREE), "/some/dir/My Mission.v2.xml")
    assert result.orders.id == "my-mission.v2"
    assert result.orders.vehicle is None
    assert result.orders.vehicles == []


def test_namespaced_avcl_is_read_by_local_names() -> None:
    data = avcl(THREE.replace("<Goal", "<a:Goal").replace("</Goal", "</a:Goal"), root="<a:AVCL>")
    data = data.replace(b"<a:AVCL>", b'<a:AVCL xmlns:a="urn:avcl" xmlns="urn:avcl">')
    result = read_bytes(data, "ns.xml")
    assert [g.id for g in result.orders.goals] == ["A", "B"]


def test_billion_laughs_is_rejected() -> None:
    levels = ['<!ENTITY lol0 "lol">'] + [
        f'<!ENTITY lol{i} "{("&lol" + str(i - 1) + ";") * 10}">' for i in range(1, 10)
    ]
    bomb = (
        '<?xml version="1.0"?>\n<!DOCTYPE AVCL [' + "".join(levels) + "]>"
        '<AVCL><body><GoalList><Goal id="A" title="&lol9;"/></GoalList></body></AVCL>'
    ).encode()
    error = rejected(bomb)
    assert error.problems[0].path == "$"
    assert "DTD" in error.problems[0].message


def test_external_entity_is_rejected() -> None:
    data = (
        b'<?xml version="1.0"?><!DOCTYPE AVCL [<!ENTITY xxe SYSTEM "file:///etc/passwd">]>'
        b'<AVCL><body><GoalList><Goal id="A" title="&xxe;"/></GoalList></body></AVCL>'
    )
    error = rejected(data)
    assert "passwd" not in str(error)
    assert "refused" in str(error)


def test_external_dtd_is_rejected() -> None:
    data = b'<!DOCTYPE AVCL SYSTEM "http://example.invalid/avcl.dtd"><AVCL/>'
    assert "DTD" in str(rejected(data))


def test_undeclared_entity_is_a_parse_error() -> None:
    error = rejected(b"<AVCL><body><GoalList><Goal id='&x;'/></GoalList></body></AVCL>")
    assert "not well-formed XML" in str(error)


@pytest.mark.parametrize(
    ("data", "path", "words"),
    [
        (b"<Mission><GoalList/></Mission>", "/Mission", "not <AVCL>"),
        (b'<x:Orders xmlns:x="urn:x"/>', "/Orders", "not <AVCL>"),
        (b"<AVCL><body/></AVCL>", "/AVCL", "no GoalList"),
        (b"<AVCL><body><GoalList>", "$", "line 1"),
        (b"<AVCL>\xff</AVCL>", "$", "not well-formed"),
    ],
)
def test_unusable_documents_are_rejected(data: bytes, path: str, words: str) -> None:
    error = rejected(data)
    assert error.problems[0].path == path
    assert words in error.problems[0].message


def test_invalid_ids_are_named_with_their_xml_path() -> None:
    with pytest.raises(OrdersReadError) as caught:
        read(
            '<Goal id="bad id" nextOnSuccess="B"/><Goal title="no id"/><Goal id="C" '
            'nextOnSuccess="-x"/>'
        )
    problems = {(p.path, p.message.split(":")[0]) for p in caught.value.problems}
    base = "/AVCL/body/MissionDefinition/AgendaMission/GoalList"
    assert problems == {
        (f"{base}/Goal[1]/@id", "the AVCL id 'bad id' cannot be used"),
        (f"{base}/Goal[2]/@id", "the Goal has no id"),
        (f"{base}/Goal[3]/@nextOnSuccess", "the AVCL id '-x' cannot be used"),
    }


def test_bad_numbers_are_read_errors() -> None:
    with pytest.raises(OrdersReadError) as caught:
        read(
            '<Goal id="A" nextOnSuccess="B"><Search requiredPD="high"/>'
            '<Duration value="-5"/></Goal><Goal id="B"/>'
        )
    paths = [p.path for p in caught.value.problems]
    assert paths == [
        "/AVCL/body/MissionDefinition/AgendaMission/GoalList/Goal[1]/Search/@requiredPD",
        "/AVCL/body/MissionDefinition/AgendaMission/GoalList/Goal[1]/Duration/@value",
    ]


def test_empty_goal_list_reads_as_orders_without_goals() -> None:
    orders = read("").orders
    assert orders.goals == [] and orders.start is None
    assert {f.code for f in check_structure(orders)} == {"M1", "M2"}
