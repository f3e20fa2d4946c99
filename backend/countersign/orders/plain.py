"""Plain-language orders: the text a supervisor reads and signs (seed 000 Figures 3 and 4).

Every constraint and norm shows its text and the condition that is checked, in words and in
symbols; every terminal is named by its own title; path properties and the vehicle profile
that was checked follow (the contingency rules are appended by `rules.plain_orders`), so nothing
the signature covers is left unread.

Goals and constraints are numbered by their position in the orders; successors are named by
those numbers. Outcomes that lead to the same place are merged into one sentence, and every
defect (a missing outcome, an unknown target or scope) is said in words rather than hidden, so
the text never reads better than the orders are. Author text is folded onto one line so that a
title cannot forge a paragraph of its own.
"""

from __future__ import annotations

import re
from collections.abc import Sequence

from .conditions import condition_words, quantities_of
from .model import OUTCOMES, Area, Constraint, Goal, Norm, Orders, Quantity, Terminal
from .plain_profile import plain_properties, plain_vehicle
from .profile import profile_of

_CONDITIONS: dict[tuple[str, ...], str] = {
    ("succeed",): "if the goal succeeds",
    ("fail",): "if it fails",
    ("violate",): "if a constraint is about to be violated",
    ("succeed", "fail"): "whether the goal succeeds or fails",
    ("succeed", "violate"): "if the goal succeeds or a constraint is about to be violated",
    ("fail", "violate"): "if it fails or a constraint is about to be violated",
    OUTCOMES: "whatever the outcome (success, failure or an imminent constraint violation)",
}
_NOT_SAID = "the orders do not say what comes next"
_TAG = re.compile(r"[A-Za-z_][A-Za-z0-9_]*")


def _one_line(text: str) -> str:
    return " ".join(text.split())


def _sentence(text: str) -> str:
    text = _one_line(text)
    return text if not text or text[-1] in ".!?" else text + "."


def _numbered(kind: str, number: int, item_id: str) -> str:
    """'Goal 3', or 'Goal 3 (PSMD13.1)' when the id is not simply G3 / Goal3."""
    initial = kind[0]
    match = re.fullmatch(rf"(?:{initial}|{kind})[_-]?(\d+)", item_id, re.IGNORECASE)
    if match and int(match.group(1)) == number:
        return f"{kind} {number}"
    return f"{kind} {number} ({item_id})"


def join_english(items: Sequence[str], conjunction: str = "and") -> str:
    """'A', 'A and B', 'A, B, and C' (Oxford comma)."""
    if len(items) <= 2:
        return f" {conjunction} ".join(items)
    return f"{', '.join(items[:-1])}, {conjunction} {items[-1]}"


class Names:
    """Resolves ids to what the text calls them: goal numbers, terminal phrases."""

    def __init__(self, orders: Orders) -> None:
        self.goal_numbers: dict[str, int] = {}
        for number, goal in enumerate(orders.goals, start=1):
            self.goal_numbers.setdefault(goal.id, number)
        self.terminals: dict[str, Terminal] = orders.terminal_index()
        self.areas: dict[str, Area] = orders.area_index()

    def goal(self, goal_id: str) -> str:
        number = self.goal_numbers.get(goal_id)
        return f"Goal {number}" if number else f"{goal_id} (not a goal of these orders)"

    def action(self, target: str) -> str:
        # A goal wins over a terminal with the same id, as in the mission graph.
        if target in self.goal_numbers:
            return f"execute Goal {self.goal_numbers[target]}"
        terminal = self.terminals.get(target)
        if terminal is None:
            return f"go to {target}, which is neither a goal nor a terminal of these orders"
        return terminal_action(terminal)


_DEFAULT_TITLES = {"", "mission complete", "mission abort", "complete", "abort"}


def terminal_action(terminal: Terminal) -> str:
    """'abort the mission', or with the terminal's own title when it has one: two terminals
    with different titles are different orders and must never read as one."""
    plain = "the mission is complete" if terminal.kind == "complete" else "abort the mission"
    title = _one_line(terminal.title).rstrip(".")
    if title.lower() in _DEFAULT_TITLES:
        return plain
    return f"{plain}: {title}"


def _outcome_action(goal: Goal, outcome: str, names: Names) -> str:
    targets = goal.successors(outcome)
    if not targets:
        return _NOT_SAID
    if len(targets) == 1:
        return names.action(targets[0])
    choices = join_english([names.action(t) for t in targets], "or")
    return f"the orders name more than one next step: {choices}"


def outcome_sentences(goal: Goal, names: Names) -> str:
    """'Next, if the goal succeeds, execute Goal 2. If it fails, ...' with equal outcomes merged."""
    groups: dict[str, list[str]] = {}
    for outcome in OUTCOMES:
        groups.setdefault(_outcome_action(goal, outcome, names), []).append(outcome)
    if list(groups) == [_NOT_SAID]:
        return "The orders do not say what comes next, whatever the outcome."
    sentences = []
    for position, (action, outcomes) in enumerate(groups.items()):
        condition = _CONDITIONS[tuple(outcomes)]
        if position == 0:
            sentences.append(f"Next, {condition}, {action}.")
        else:
            sentences.append(f"{condition[0].upper()}{condition[1:]}, {action}.")
    return " ".join(sentences)


def _goal_details(goal: Goal, names: Names) -> str:
    title = _one_line(goal.title)
    details = []
    if goal.behavior:
        details.append(f"behaviour: {_one_line(goal.behavior).replace('_', ' ')}")
    if goal.area:
        area = names.areas.get(goal.area)
        where = _one_line(area.title) if area and area.title else f"area {goal.area}"
        # "Search Area A" already says where; repeating it would not read well.
        if where.lower() not in title.lower():
            details.append(f"in {where}")
    return f" ({', '.join(details)})" if details else ""


def plain_goal_paragraph(goal: Goal, number: int, names: Names) -> str:
    title = _one_line(goal.title).rstrip(".") or goal.id
    heading = _numbered("Goal", number, goal.id)
    return f"{heading}: {title}{_goal_details(goal, names)}. {outcome_sentences(goal, names)}"


def _scope(constraint: Constraint, names: Names) -> str:
    if constraint.applies_to == "mission":
        return "Applies to entire mission."
    goals = [names.goal(goal_id) for goal_id in dict.fromkeys(constraint.applies_to)]
    if not goals:
        return "Applies to no goal."
    return f"Applies to {join_english(goals)}."


def plain_constraint(
    constraint: Constraint, number: int, names: Names,
    quantities: dict[str, Quantity] | None = None,
) -> str:
    text = _sentence(constraint.text) or _sentence(constraint.expr or "")
    text = text or "(The orders give neither a text nor an expression.)"
    checked = condition_words(constraint.expr, quantities or {})
    heading = _numbered("Constraint", number, constraint.id)
    return f"{heading}: {text} {checked} {_scope(constraint, names)}"


def _article(words: str) -> str:
    return ("an " if words[:1].lower() in "aeiou" else "a ") + words


def plain_norm(
    norm: Norm, number: int, orders: Orders, quantities: dict[str, Quantity] | None = None
) -> str:
    context = _one_line(norm.context)
    if _TAG.fullmatch(context):
        where = f"In {_article(context.replace('_', ' '))}"
        areas = [_one_line(a.title) or a.id for a in orders.areas if context in a.contexts]
    else:
        where, areas = f"When {context}", []
    modality, rule = next(
        (name, rule)
        for name, rule in (
            ("forbidden", norm.forbidden),
            ("obligated", norm.obligated),
            ("permitted", norm.permitted),
        )
        if rule
    )
    parts = [f"{_numbered('Norm', number, norm.id)}: {where}: {modality}: {_sentence(rule)}"]
    if norm.text:
        parts.append(_sentence(norm.text))
    parts.append(condition_words(rule, quantities if quantities is not None else {}))
    if areas:
        parts.append(f"Applies in {join_english(areas)}.")
    return " ".join(parts)


def _header(orders: Orders, names: Names) -> list[str]:
    title = _one_line(orders.title) or orders.id
    lines = [f"Mission orders {orders.id}: {title}"]
    profile = orders.target_vehicle()
    if profile is not None and profile.title:
        lines.append(f"Vehicle: {_one_line(profile.title)} ({profile.id})")
    else:
        vehicle_id = profile.id if profile is not None else orders.vehicle
        lines.append(f"Vehicle: {vehicle_id or 'not named'}")
    start = orders.start
    if start is None or start == []:
        lines.append("Start: not named")
    elif isinstance(start, str):
        goal = orders.goal_index().get(start)
        start_title = _one_line(goal.title).rstrip(".") if goal else ""
        suffix = f" ({start_title})" if start_title else ""
        lines.append(f"Start: {names.goal(start)}{suffix}")
    else:
        named = join_english([names.goal(s) for s in start])
        lines.append(f"Start: the orders name more than one start: {named}")
    return lines


def plain_orders(orders: Orders) -> str:
    """The whole plain-language document: header, goals, constraints and norms."""
    from .plain_refine import refinement_paragraphs  # it builds on this module's Names

    names = Names(orders)
    quantities = quantities_of(orders)
    blocks = ["\n".join(_header(orders, names))]
    if orders.description:
        blocks.append(_sentence(orders.description))
    blocks.append("Goals")
    if not orders.goals:
        blocks.append("The orders include no goal.")
    for number, goal in enumerate(orders.goals, start=1):
        blocks.append(plain_goal_paragraph(goal, number, names))
        # A refined goal is followed by how it is carried out.
        blocks.extend(refinement_paragraphs(goal, str(number), names))
    if orders.constraints:
        blocks.append("Constraints")
        blocks.extend(
            plain_constraint(constraint, number, names, quantities)
            for number, constraint in enumerate(orders.constraints, start=1)
        )
    if orders.norms:
        blocks.append("Norms")
        blocks.extend(
            plain_norm(norm, number, orders, quantities)
            for number, norm in enumerate(orders.norms, start=1)
        )
    blocks.extend(plain_properties(orders, quantities))
    blocks.extend(plain_vehicle(profile_of(orders), quantities))
    return "\n\n".join(blocks) + "\n"
