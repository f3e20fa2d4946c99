from __future__ import annotations

from countersign.orders.examples import load_example
from countersign.orders.model import Orders
from countersign.verify.structure import MAX_LOOPS_REPORTED, check_structure

from .builders import codes, orders_from


def test_exemplar_has_no_structural_findings() -> None:
    assert check_structure(load_example("search-and-sample")) == []


def test_no_goals_is_m2_and_m1() -> None:
    orders = Orders.model_validate({"id": "empty", "goals": []})
    assert codes(check_structure(orders)) == ["M2", "M1"]


def test_unknown_start_and_terminal_start_are_m1() -> None:
    found = check_structure(orders_from({"G1": ("COMPLETE",) * 3}, start="G9"))
    assert codes(found) == ["M1"] and found[0].subjects == ("G9",)
    found = check_structure(orders_from({"G1": ("COMPLETE",) * 3}, start="COMPLETE"))
    assert "terminal" in found[0].message


def test_two_starts_are_m1() -> None:
    orders = orders_from({"G1": ("COMPLETE",) * 3, "G2": ("ABORT",) * 3}, start=None)
    orders = orders.model_copy(update={"start": ["G1", "G2"]})
    found = check_structure(orders)
    assert codes(found) == ["M1"] and found[0].subjects == ("G1", "G2")


def test_duplicate_ids_across_goals_terminals_constraints() -> None:
    orders = orders_from(
        {"G1": ("COMPLETE",) * 3},
        constraints=[{"id": "G1", "expr": "x > 1"}, {"id": "C1"}, {"id": "C1"}],
    )
    found = [f for f in check_structure(orders) if f.code == "DUP"]
    assert sorted(f.subjects for f in found) == [("C1",), ("G1",)]


def test_sink_and_dangling_target() -> None:
    found = check_structure(orders_from({"G1": ("G2", None, "NOWHERE"), "G2": ("COMPLETE",) * 3}))
    assert [(f.code, f.subjects, f.details.get("outcome")) for f in found] == [
        ("SINK", ("G1",), "fail"),
        ("G3", ("G1", "NOWHERE"), "violate"),
    ]


def test_several_successors_for_one_outcome_is_g5() -> None:
    orders = Orders.model_validate({
        "id": "g5", "start": "G1",
        "goals": [{"id": "G1", "next": {"succeed": ["COMPLETE", "ABORT"], "fail": "ABORT",
                                        "violate": "ABORT"}}],
    })
    found = check_structure(orders)
    assert codes(found) == ["G5"] and found[0].subjects == ("G1", "COMPLETE", "ABORT")


def test_self_loop_reported_once_even_with_three_edges() -> None:
    found = check_structure(orders_from({"G1": ("G2", "ABORT", "ABORT"), "G2": ("G2",) * 3}))
    loops = [f for f in found if f.code == "G7"]
    assert len(loops) == 1
    assert loops[0].subjects == ("G2",)
    assert loops[0].details["reached_by"] == ["succeed"]
    assert loops[0].details["loop_outcomes"] == [["succeed", "fail", "violate"]]


def test_loop_starts_where_the_mission_enters_it() -> None:
    edges = {
        "G1": ("G2", "ABORT", "ABORT"),
        "G2": ("G3", "G4", "ABORT"),
        "G3": ("G4", "ABORT", "ABORT"),
        "G4": ("COMPLETE", "G3", "ABORT"),
    }
    loops = [f for f in check_structure(orders_from(edges)) if f.code == "G7"]
    assert len(loops) == 1
    # G4 is reached after (succeed, fail), G3 after (succeed, succeed): same depth, so the
    # first goal in the orders wins the tie.
    assert loops[0].subjects == ("G3", "G4")
    assert loops[0].details["reached_by"] == ["succeed", "succeed"]
    assert "first enters it after the outcomes succeed, succeed" in loops[0].message


def test_unreachable_goal_and_unreachable_loop() -> None:
    edges = {
        "G1": ("COMPLETE", "ABORT", "ABORT"),
        "G2": ("G3", "ABORT", "ABORT"),
        "G3": ("G2", "ABORT", "ABORT"),
    }
    found = check_structure(orders_from(edges))
    assert sorted(f.subjects for f in found if f.code == "G10") == [("G2",), ("G3",)]
    loop = next(f for f in found if f.code == "G7")
    assert loop.subjects == ("G2", "G3") and loop.details["reached_by"] is None
    assert "never reaches" in loop.message


def test_loop_reports_are_bounded() -> None:
    # A complete digraph on 8 goals has thousands of elementary cycles.
    ids = [f"G{i}" for i in range(1, 9)]
    edges: dict[str, tuple[str | None, str | None, str | None]] = {}
    for i, gid in enumerate(ids):
        a, b = ids[(i + 1) % 8], ids[(i + 3) % 8]
        edges[gid] = (a, b, ids[(i + 5) % 8])
    loops = [f for f in check_structure(orders_from(edges)) if f.code == "G7"]
    assert len(loops) == MAX_LOOPS_REPORTED + 1
    assert loops[-1].details["truncated"] is True
    assert set(loops[-1].subjects) == set(ids)
