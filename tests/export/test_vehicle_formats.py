"""IMC and MOOS-IvP exports, read back by independent readers (imcpy; a small .bhv reader)
and compared with the MEA path for path, for every built-in example and the NPS AVCL missions."""

from __future__ import annotations

import math
import re
from itertools import pairwise
from pathlib import Path
from urllib.parse import unquote

import pytest

from countersign.export.moos import helm_modes
from countersign.export.notes import ExportError
from countersign.export.vehicle import export_vehicle
from countersign.orders.examples import example_bytes, example_names
from countersign.orders.model import Orders
from countersign.orders.reader import read_bytes, read_file
from countersign.verify.paths import iter_paths, paths_of
from countersign.verify.refine import checked_form

from .readers import AVCL, NPS, Graph, description, graph_paths, mode_map, read_bhv, read_imc

EXAMPLES = example_names()


def _example(name: str) -> Orders:
    return read_bytes(example_bytes(name), name).orders


def _mea(orders: Orders) -> list[tuple[tuple[str, ...], tuple[str, ...], str]]:
    graph, counts = paths_of(orders)
    assert counts is not None
    return [(p.goals, p.outcomes, p.terminal) for p in iter_paths(graph, counts)]


def _edges(orders: Orders) -> dict[str, dict[str, str]]:
    return {g.id: {o: g.successors(o)[0] for o in ("succeed", "fail", "violate")}
            for g in orders.goals}


def _check_against_mea(orders: Orders, graph: Graph, rename: dict[str, str] | None = None) -> None:
    name = (lambda n: rename[n]) if rename else (lambda n: n)
    orders = checked_form(orders)[0]  # a refined mission is exported as its flat automaton
    edges = {name(s): {o: name(t) for o, t in out.items()} for s, out in graph.edges.items()}
    assert name(graph.start) == orders.start
    assert edges == _edges(orders)
    kinds = {t.id: t.kind for t in orders.effective_terminals}
    assert {name(t): k for t, k in graph.terminals.items()} == kinds
    _, counts = paths_of(orders)
    if counts is None:  # loops (NPS missions with G7): the edge sets above are the MEA
        return
    read = [(tuple(map(name, g)), o, name(t)) for g, o, t in graph_paths(graph)]
    assert read == _mea(orders)


@pytest.mark.parametrize("name", EXAMPLES)
def test_imc_export_parses_back_to_the_mea(name: str) -> None:
    orders = _example(name)
    export = export_vehicle(orders, "imc", version=4, approval={"decision": "approved"})
    plan, graph = read_imc(export.primary.content)
    assert plan.plan_id == f"{orders.id}@v4"
    meta = description(plan)
    assert meta["orders_digest"].startswith("sha256:") and meta["version"] == 4
    assert meta["approval"] == {"decision": "approved"}
    _check_against_mea(orders, graph)
    # Deterministic: the same orders give the same bytes.
    assert export_vehicle(orders, "imc", version=4,
                          approval={"decision": "approved"}).primary.content \
        == export.primary.content


def test_imc_maneuvers_follow_behaviour_and_area() -> None:
    orders = _example("search-and-sample")
    plan, _ = read_imc(export_vehicle(orders, "imc").primary.content)
    kinds = {m.maneuver_id: m.data.msg_name for m in plan.maneuvers}
    assert kinds == {"G1": "Rows", "G2": "StationKeeping", "G3": "Rows", "G4": "Loiter",
                     "G5": "Goto", "COMPLETE": "PopUp", "ABORT": "PopUp"}
    g5 = next(m.data for m in plan.maneuvers if m.maneuver_id == "G5")
    base = orders.area_index()["BASE"].polygon
    assert math.degrees(g5.lat) == pytest.approx(sum(p[0] for p in base) / 4, abs=1e-3)
    assert g5.z == pytest.approx(40) and g5.speed == pytest.approx(1.5)
    names = [v.name for v in plan.variables]
    assert names == [f"constraint.C{i}" for i in range(1, 8)]


@pytest.mark.parametrize("name", EXAMPLES)
def test_moos_mode_graph_equals_the_mea(name: str) -> None:
    orders = _example(name)
    export = export_vehicle(orders, "moos", version=1)
    text = export.primary.content.decode()
    _check_against_mea(orders, read_bhv(text), mode_map(text))
    moos = export.file(f"{orders.id}.moos")
    assert moos is not None and b"uSimMarine" in moos.content
    assert f"behaviors = {orders.id}.bhv".encode() in moos.content


def test_moos_constraints_become_conditions_or_named_comments() -> None:
    orders = _example("search-and-sample")
    text = export_vehicle(orders, "moos").primary.content.decode()
    assert "condition = ((LANE_DISTANCE_M < 1000) and (DEPTH_M < 20))" in text
    assert re.search(r"name = b\d+_G5_violate_C7\n", text)
    assert not re.search(r"name = b\d+_G5_violate_C4\n", text)
    data = orders.model_dump(mode="json", exclude_unset=True)
    data["constraints"][0]["expr"] = "nav_error_m + 1 <= 10"
    export = export_vehicle(Orders.model_validate(data), "moos")
    assert "// constraint C1 (nav_error_m + 1 <= 10): no helm condition" in \
        export.primary.content.decode()
    assert any(n.code == "MONITOR" and n.path == "/constraints/0" for n in export.notes)


@pytest.mark.parametrize("fmt", ["imc", "moos"])
def test_every_export_names_what_it_cannot_carry(fmt: str) -> None:
    export = export_vehicle(_example("search-and-sample-rules"), fmt)
    found = {(n.code, n.path) for n in export.notes}
    assert ("NORM", "/norms/0") in found and ("RULES", "/rules") in found
    assert all(n.message for n in export.notes)


@pytest.mark.parametrize("fmt", ["imc", "moos"])
def test_orders_that_cannot_be_a_plan_are_refused(fmt: str) -> None:
    data = _example("search-and-sample").model_dump(mode="json", exclude_unset=True)
    data["goals"][0]["next"]["fail"] = "NOWHERE"
    with pytest.raises(ExportError, match="G3"):
        export_vehicle(Orders.model_validate(data), fmt)


def test_a_plan_too_large_for_one_imc_message_is_refused() -> None:
    goals = [{"id": f"G{i}", "title": "A goal with a long enough title " * 3,
              "next": {o: f"G{i + 1}" if i < 399 else "COMPLETE"
                       for o in ("succeed", "fail", "violate")}} for i in range(400)]
    orders = Orders.model_validate({"id": "big", "start": "G0", "goals": goals})
    with pytest.raises(ExportError, match="65,535 bytes"):
        export_vehicle(orders, "imc")
    assert export_vehicle(orders, "moos").primary.content  # MOOS has no such limit


@pytest.mark.skipif(not AVCL, reason=f"NPS reference missions not found under {NPS}")
@pytest.mark.parametrize("path", AVCL, ids=[p.name for p in AVCL])
def test_nps_avcl_missions_export_to_both_formats(path: object) -> None:
    assert len(AVCL) == 10  # the NPS folder's missions, loops and unreachable goals included
    orders = read_file(str(path)).orders
    _, graph = read_imc(export_vehicle(orders, "imc").primary.content)
    _check_against_mea(orders, graph)
    text = export_vehicle(orders, "moos").primary.content.decode()
    _check_against_mea(orders, read_bhv(text), mode_map(text))


def test_user_text_cannot_start_a_helm_declaration() -> None:
    # Titles and behaviours are the operator's text; in the .bhv they stand only inside
    # one-line comments, so a line break (any Unicode one) cannot start a mode or behaviour.
    injected = "x\nset MODE = EVIL {\n  MODE = ACTIVE\n}\u2028Behavior = BHV_Waypoint\x85{"
    data = _example("search-and-sample").model_dump(mode="json", exclude_unset=True)
    for goal in data["goals"]:
        goal["title"] = injected
        goal["behavior"] = injected
    orders = Orders.model_validate(data)
    text = export_vehicle(orders, "moos", version=1).primary.content.decode()
    assert "EVIL" not in mode_map(text).values()
    assert not any(line.startswith(("set MODE = EVIL", "Behavior = BHV_Waypoint{"))
                   for line in text.splitlines())
    _check_against_mea(orders, read_bhv(text), mode_map(text))


def _behaviour_names(text: str) -> list[str]:
    return re.findall(r"^Behavior = \w+\n\{\n  name = (\S+)$", text, re.M)


@pytest.mark.parametrize("orders", [
    *(_example(name) for name in EXAMPLES),
    *(read_file(str(path)).orders for path in AVCL),
    read_file(str(Path(__file__).with_name("refined_twice.json"))).orders,
    # ids chosen so that a mode name plus a role would begin another behaviour's name
    Orders.model_validate({"id": "tricky", "start": "G1", "constraints": [
        {"id": "C1", "applies_to": "mission", "expr": "x <= 1"}], "goals": [
        {"id": i, "next": {o: "COMPLETE" for o in ("succeed", "fail", "violate")}}
        for i in ("G1", "G1_violate", "G1_run", "G1_violate_C1")]}),
], ids=[*EXAMPLES, *(p.stem for p in AVCL), "refined-twice", "tricky-ids"])
def test_no_behaviour_name_begins_another(orders: Orders) -> None:
    # pHelmIvP refuses the whole behaviour set when one name begins another
    names = sorted(_behaviour_names(export_vehicle(orders, "moos").primary.content.decode()))
    assert names and len(names) == len(set(names))
    assert [(a, b) for a, b in pairwise(names) if b.startswith(a)] == []


def test_depth_is_held_for_as_long_as_the_mode_lasts() -> None:
    text = export_vehicle(_example("search-and-sample"), "moos").primary.content.decode()
    blocks = re.findall(r"^Behavior = BHV_ConstantDepth\n\{\n(.*?)^\}", text, re.M | re.S)
    assert len(blocks) == 5
    assert all("  duration = no-time-limit\n" in block for block in blocks)


# --- refined missions: nested helm modes, the hierarchy in IMC maneuver ids -------
TWICE = Path(__file__).with_name("refined_twice.json")
REFINED = ["search-and-sample-refined", "refined-twice"]
_DECLARED = re.compile(r"^set MODE = (\w+) \{\n  MODE = (\S+)\n  (.+)\n\}", re.M)


def _refined(name: str) -> Orders:
    return read_file(str(TWICE)).orders if name == "refined-twice" else _example(name)


@pytest.mark.parametrize("name", REFINED)
def test_a_refined_goal_is_a_helm_mode_holding_the_modes_of_its_goals(name: str) -> None:
    orders = _refined(name)
    flat, graph = checked_form(orders)
    assert graph.nesting is not None
    text = export_vehicle(orders, "moos").primary.content.decode()
    # Independently of the exporter: each declaration's parent, its condition, its place.
    declared = {m.group(1): (m.group(2), m.group(3), i)
                for i, m in enumerate(_DECLARED.finditer(text))}
    groups = {m.group(2): m.group(1) for m in re.finditer(
        r"^// mode (\w+) = refined goal (\S+): ", text, re.M)}
    goal_mode = {goal: mode for mode, goal in mode_map(text).items()}

    chains = graph.nesting.parents
    assert set(groups) == {p for chain in chains.values() for p, _ in chain}
    for goal in flat.goals:
        mode = goal_mode[goal.id]
        parent, condition, at = declared[mode]
        chain = [groups[p] for p, _ in chains.get(goal.id, ())]
        assert parent == ":".join(["ACTIVE", *chain]), goal.id
        assert condition == f"MISSION_GOAL = {mode}"
        for depth, group in enumerate(chain):
            above, selector, before = declared[group]
            assert above == ":".join(["ACTIVE", *chain[:depth]])
            assert before < at  # the helm builds the mode string parent first
            assert f"(MISSION_GOAL = {mode})" in selector
        # Its behaviours run in that mode and no other.
        runs = re.findall(rf"name = b\d+_{mode}_run\n  pwt = 100\n  condition = MODE == (\S+)",
                          text)
        assert runs == [mode if chain else f"ACTIVE:{mode}"]
    for flat_id, group in groups.items():
        inside = {goal_mode[g.id] for g in flat.goals if flat_id in dict(chains.get(g.id, ()))}
        named = set(re.findall(r"MISSION_GOAL = (\w+)", declared[group][1]))
        assert named == inside, flat_id
    # The transitions are still exactly the flat automaton's.
    _check_against_mea(orders, read_bhv(text), mode_map(text))


def test_refined_modes_are_named_by_their_own_ids_and_unrolled_copies_spelt_out() -> None:
    orders = _refined("refined-twice")
    flat, graph = checked_form(orders)
    helm = helm_modes(flat, graph.nesting)
    assert helm.path["G1/G1.1#1"] == "ACTIVE:G1:G1_1_k1"
    assert helm.path["G1/G1.2#2/G1.2.1"] == "ACTIVE:G1:G1_2_k2:G1_2_1"
    assert helm.path["G2"] == "ACTIVE:G2" and helm.path["COMPLETE"] == "ACTIVE:COMPLETE"
    names = list(helm.name.values()) + [g.name for g in helm.groups]
    assert len(names) == len(set(names))  # MISSION_GOAL and MODE == name one mode each
    assert helm.goal_of("ACTIVE:G1:G1_2_k2:G1_2_1") == "G1/G1.2#2/G1.2.1"


@pytest.mark.parametrize("name", REFINED)
def test_imc_maneuver_ids_carry_the_hierarchy(name: str) -> None:
    orders = _refined(name)
    graph = checked_form(orders)[1]
    plan, read = read_imc(export_vehicle(orders, "imc").primary.content)
    assert graph.nesting is not None
    for maneuver in plan.maneuvers:
        custom = dict(kv.split("=", 1) for kv in maneuver.data.custom.split(";") if kv)
        chain = graph.nesting.parents.get(maneuver.maneuver_id, ())
        # The id is the refined goals' ids, outermost first, and the goal's own, by '/'.
        assert maneuver.maneuver_id.split("/")[:-1] == \
            [p.rsplit("/", 1)[-1] for p, _ in chain]
        if chain:
            assert unquote(custom["inside"]) == "/".join(p for p, _ in chain)
            assert unquote(custom["inside.title"]) == " / ".join(t for _, t in chain)
        else:
            assert "inside" not in custom
    _check_against_mea(orders, read)


def test_nested_mode_conditions_are_bounded(monkeypatch: pytest.MonkeyPatch) -> None:
    # 12 goals inside G1, and 2 inside each of the 3 copies of G1.2: 18 names in all
    monkeypatch.setattr("countersign.export.moos.MAX_NESTED_SELECTORS", 17)
    with pytest.raises(ExportError, match=r"name 18 goals inside them .* over the 17"):
        export_vehicle(_refined("refined-twice"), "moos")
    monkeypatch.setattr("countersign.export.moos.MAX_NESTED_SELECTORS", 18)
    assert export_vehicle(_refined("refined-twice"), "moos").primary.content
