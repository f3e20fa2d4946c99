"""Plain-language orders (seed 000 Figures 3 and 4)."""

from __future__ import annotations

from typing import Any

import pytest

from countersign.orders.examples import load_example
from countersign.orders.model import Orders
from countersign.orders.plain import join_english, plain_orders


@pytest.fixture(scope="module")
def exemplar() -> str:
    return plain_orders(load_example("search-and-sample"))


def paragraphs(text: str) -> list[str]:
    return text.rstrip("\n").split("\n\n")


def paragraph(text: str, prefix: str) -> str:
    found = [p for p in paragraphs(text) if p.startswith(prefix)]
    assert len(found) == 1, f"expected one paragraph starting {prefix!r}, found {found}"
    return found[0]


def orders(goals: list[dict[str, Any]], **extra: Any) -> Orders:
    data: dict[str, Any] = {"id": "t", "title": "Test", "start": goals[0]["id"], "goals": goals}
    data.update(extra)
    return Orders.model_validate(data)


def goal(goal_id: str, **next_: str) -> dict[str, Any]:
    return {"id": goal_id, "title": f"Do {goal_id}", "next": next_}


ALL_DONE = {"succeed": "COMPLETE", "fail": "ABORT", "violate": "ABORT"}


# The exemplar


def test_header(exemplar: str) -> None:
    assert paragraphs(exemplar)[0] == (
        "Mission orders search-and-sample: Search and sample (seed 000 exemplar)\n"
        "Vehicle: REMUS 100 AUV (remus-100)\n"
        "Start: Goal 1 (Search Area A)"
    )


def test_goal_1_branches_three_ways(exemplar: str) -> None:
    assert paragraph(exemplar, "Goal 1:") == (
        "Goal 1: Search Area A (behaviour: area search). Next, if the goal succeeds, "
        "execute Goal 2. If it fails, execute Goal 3. If a constraint is about to be violated, "
        "execute Goal 4."
    )


def test_goal_3_merges_all_outcomes(exemplar: str) -> None:
    assert paragraph(exemplar, "Goal 3:") == (
        "Goal 3: Search Area B (behaviour: area search). Next, whatever the outcome "
        "(success, failure or an imminent constraint violation), execute Goal 4."
    )


def test_goal_5_ends_the_mission(exemplar: str) -> None:
    assert paragraph(exemplar, "Goal 5:") == (
        "Goal 5: Return to Base (behaviour: transit, in Recovery position off Moss Landing). "
        "Next, if the goal succeeds, the mission is complete. "
        "If it fails or a constraint is about to be violated, abort the mission."
    )


def test_constraints_as_in_figure_4(exemplar: str) -> None:
    assert paragraph(exemplar, "Constraint 1:") == (
        "Constraint 1: The vehicle must maintain navigational accuracy within acceptable "
        "limits. Checked as: navigation error at most 10 m (`nav_error_m <= 10`). "
        "Applies to entire mission."
    )
    assert paragraph(exemplar, "Constraint 3:") == (
        "Constraint 3: All mission systems must be operational. "
        "Checked as: mission systems operational (`mission_systems_ok`). "
        "Applies to Goal 1, Goal 2, and Goal 3."
    )
    assert paragraph(exemplar, "Constraint 4:").endswith(
        "Applies to Goal 1, Goal 2, Goal 3, and Goal 4."
    )
    assert paragraph(exemplar, "Constraint 7:") == (
        "Constraint 7: Minimum depth of 20 meters is to be maintained. "
        "Checked as: depth at least 20 m (`depth_m >= 20`). Applies to Goal 5."
    )


def test_sections_and_norms(exemplar: str) -> None:
    blocks = paragraphs(exemplar)
    assert blocks.index("Goals") < blocks.index("Constraints") < blocks.index("Norms")
    assert blocks.index("Norms") < blocks.index("Vehicle profile")
    assert paragraph(exemplar, "Norm 1:") == (
        "Norm 1: In a marine protected area: forbidden: behavior == 'sample'. "
        "No sampling inside a marine protected area. "
        "Checked as: behavior is 'sample' (`behavior == 'sample'`)."
    )


def test_text_is_deterministic_and_tidy(exemplar: str) -> None:
    assert plain_orders(load_example("search-and-sample")) == exemplar
    assert exemplar.endswith("\n") and not exemplar.endswith("\n\n")
    assert all(line == line.rstrip() for line in exemplar.splitlines())


def test_harbor_example_reads_cleanly() -> None:
    text = plain_orders(load_example("harbor-approach-survey"))
    assert "not a goal" not in text and "do not say" not in text
    assert paragraph(text, "Goal 4:") == (
        "Goal 4: Cross the main ship channel at right angles "
        "(behaviour: transit, in San Diego Bay main ship channel). Next, if the goal succeeds, "
        "execute Goal 5. If it fails or a constraint is about to be violated, execute Goal 7."
    )


# Merging outcomes


@pytest.mark.parametrize(
    ("next_", "expected"),
    [
        (
            {"succeed": "G2", "fail": "G2", "violate": "ABORT"},
            "Next, whether the goal succeeds or fails, execute Goal 2. "
            "If a constraint is about to be violated, abort the mission.",
        ),
        (
            {"succeed": "G2", "fail": "ABORT", "violate": "G2"},
            "Next, if the goal succeeds or a constraint is about to be violated, "
            "execute Goal 2. If it fails, abort the mission.",
        ),
        (
            {"succeed": "COMPLETE", "fail": "COMPLETE", "violate": "COMPLETE"},
            "Next, whatever the outcome (success, failure or an imminent constraint "
            "violation), the mission is complete.",
        ),
    ],
)
def test_outcomes_with_one_target_share_a_sentence(next_: dict[str, str], expected: str) -> None:
    text = plain_orders(orders([goal("G1", **next_), goal("G2", **ALL_DONE)]))
    assert paragraph(text, "Goal 1:") == f"Goal 1: Do G1. {expected}"


# Defects are said, not hidden


def test_missing_outcome() -> None:
    text = plain_orders(orders([goal("G1", succeed="G2", violate="ABORT"), goal("G2", **ALL_DONE)]))
    assert paragraph(text, "Goal 1:") == (
        "Goal 1: Do G1. Next, if the goal succeeds, execute Goal 2. "
        "If it fails, the orders do not say what comes next. "
        "If a constraint is about to be violated, abort the mission."
    )


def test_two_missing_outcomes_merge() -> None:
    text = plain_orders(orders([goal("G1", succeed="COMPLETE")]))
    assert paragraph(text, "Goal 1:").endswith(
        "If it fails or a constraint is about to be violated, "
        "the orders do not say what comes next."
    )


def test_no_outcome_at_all() -> None:
    text = plain_orders(orders([goal("G1")]))
    assert paragraph(text, "Goal 1:") == (
        "Goal 1: Do G1. The orders do not say what comes next, whatever the outcome."
    )


def test_unknown_target_is_named_verbatim() -> None:
    text = plain_orders(orders([goal("G1", succeed="G9", fail="ABORT", violate="ABORT")]))
    assert paragraph(text, "Goal 1:") == (
        "Goal 1: Do G1. Next, if the goal succeeds, go to G9, which is neither a goal nor a "
        "terminal of these orders. If it fails or a constraint is about to be violated, "
        "abort the mission."
    )


def test_several_successors_for_one_outcome() -> None:
    g1 = goal("G1", fail="ABORT", violate="ABORT")
    g1["next"]["succeed"] = ["G2", "COMPLETE"]
    text = plain_orders(orders([g1, goal("G2", **ALL_DONE)]))
    assert paragraph(text, "Goal 1:").startswith(
        "Goal 1: Do G1. Next, if the goal succeeds, the orders name more than one next step: "
        "execute Goal 2 or the mission is complete."
    )


def test_custom_terminals_by_kind() -> None:
    terminals = [{"id": "HOME", "kind": "complete"}, {"id": "SCUTTLE", "kind": "abort"}]
    o = orders([goal("G1", succeed="HOME", fail="SCUTTLE", violate="SCUTTLE")], terminals=terminals)
    assert (
        "the mission is complete. If it fails or a constraint is about to be violated, "
        "abort the mission." in plain_orders(o)
    )


def test_start_problems() -> None:
    two = orders([goal("G1", **ALL_DONE), goal("G2", **ALL_DONE)], start=["G1", "G2"])
    assert "Start: the orders name more than one start: Goal 1 and Goal 2" in plain_orders(two)
    unknown = orders([goal("G1", **ALL_DONE)], start="G7")
    assert "Start: G7 (not a goal of these orders)" in plain_orders(unknown)
    none = orders([goal("G1", **ALL_DONE)], start=None)
    assert "Start: not named" in plain_orders(none)


# Numbering


def test_ids_other_than_the_position_are_shown() -> None:
    goals = [
        goal("G1", succeed="PSMD13.1", fail="ABORT", violate="ABORT"),
        goal("PSMD13.1", succeed="goal3", fail="G2", violate="ABORT"),
        goal("goal3", **ALL_DONE),
        goal("G2", **ALL_DONE),
    ]
    text = plain_orders(orders(goals))
    assert paragraph(text, "Goal 1:").startswith(
        "Goal 1: Do G1. Next, if the goal succeeds, execute Goal 2."
    )
    assert paragraph(text, "Goal 2 (PSMD13.1):") == (
        "Goal 2 (PSMD13.1): Do PSMD13.1. Next, if the goal succeeds, execute Goal 3. "
        "If it fails, execute Goal 4. If a constraint is about to be violated, abort the mission."
    )
    assert paragraph(text, "Goal 3:").startswith("Goal 3: Do goal3.")
    assert paragraph(text, "Goal 4 (G2):").startswith("Goal 4 (G2): Do G2.")


def test_constraint_numbering_scope_and_fallback() -> None:
    constraints = [
        {"id": "nav-accuracy", "text": "Keep navigation accurate", "applies_to": "mission"},
        {"id": "C2", "expr": "depth_m >= 20", "applies_to": ["G2", "G1", "G1"]},
        {"id": "C3", "text": "Stay clear.", "applies_to": ["G1", "G9"]},
        {"id": "C4", "applies_to": []},
    ]
    goals = [goal("G1", succeed="G2", fail="ABORT", violate="ABORT"), goal("G2", **ALL_DONE)]
    text = plain_orders(orders(goals, constraints=constraints))
    assert paragraph(text, "Constraint 1") == (
        "Constraint 1 (nav-accuracy): Keep navigation accurate. "
        "Not checked: the orders give no condition. Applies to entire mission."
    )
    assert paragraph(text, "Constraint 2:") == (
        "Constraint 2: depth_m >= 20. Checked as: depth at least 20 m (`depth_m >= 20`). "
        "Applies to Goal 2 and Goal 1."
    )
    assert paragraph(text, "Constraint 3:") == (
        "Constraint 3: Stay clear. Not checked: the orders give no condition. "
        "Applies to Goal 1 and G9 (not a goal of these orders)."
    )
    assert paragraph(text, "Constraint 4:") == (
        "Constraint 4: (The orders give neither a text nor an expression.) "
        "Not checked: the orders give no condition. Applies to no goal."
    )


def test_norm_context_expression_and_areas() -> None:
    norms = [
        {"id": "no-loiter", "context": "shipping_lane", "forbidden": "behavior == 'loiter'"},
        {
            "id": "N2",
            "context": "depth_m < 5",
            "obligated": "behavior == 'transit'",
            "text": "Keep moving in shallow water",
        },
    ]
    areas = [
        {"id": "L", "title": "Traffic lane", "contexts": ["shipping_lane"]},
        {"id": "M", "contexts": ["shipping_lane"]},
    ]
    text = plain_orders(orders([goal("G1", **ALL_DONE)], norms=norms, areas=areas))
    assert paragraph(text, "Norm 1") == (
        "Norm 1 (no-loiter): In a shipping lane: forbidden: behavior == 'loiter'. "
        "Checked as: behavior is 'loiter' (`behavior == 'loiter'`). "
        "Applies in Traffic lane and M."
    )
    assert paragraph(text, "Norm 2:") == (
        "Norm 2: When depth_m < 5: obligated: behavior == 'transit'. "
        "Keep moving in shallow water. "
        "Checked as: behavior is 'transit' (`behavior == 'transit'`)."
    )


# Author text cannot shape the document


def test_titles_are_folded_onto_one_line() -> None:
    g1 = goal("G1", **ALL_DONE)
    g1["title"] = "Search  Area A \n\nGoal 2: Abort nothing.  "
    text = plain_orders(orders([g1]))
    assert paragraph(text, "Goal 1:").startswith("Goal 1: Search Area A Goal 2: Abort nothing.")
    assert all(line == line.rstrip() for line in text.splitlines())


def test_area_already_in_the_title_is_not_repeated() -> None:
    g1 = {
        **goal("G1", **ALL_DONE),
        "title": "Search Area A",
        "area": "A",
        "behavior": "area_search",
    }
    g2 = {**goal("G2", **ALL_DONE), "title": "Loiter", "area": "Q"}
    areas = [{"id": "A", "title": "Area A"}]
    text = plain_orders(orders([g1, g2], areas=areas))
    assert paragraph(text, "Goal 1:").startswith("Goal 1: Search Area A (behaviour: area search).")
    assert paragraph(text, "Goal 2:").startswith("Goal 2: Loiter (in area Q).")


def test_join_english() -> None:
    assert join_english([]) == ""
    assert join_english(["a"]) == "a"
    assert join_english(["a", "b"]) == "a and b"
    assert join_english(["a", "b", "c"], "or") == "a, b, or c"
