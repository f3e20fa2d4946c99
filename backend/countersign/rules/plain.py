"""The rules in plain English for the supervisor (one sentence per rule)."""

from __future__ import annotations

from .syntax import Literal, is_variable
from .theory import DO_SAFE, GOAL, NEXT_ACTION, DefaultTheory, Rule

_KIND_WORDS = {
    "observation": "fact",
    "estimation": "estimation",
    "goal": "goal",
    "safety": "safety",
    "action": "action check",
}


def _words(name: str) -> str:
    return name.replace("_", " ")


def literal_words(literal: Literal) -> str:
    """`do_safe`, `goal` and `next_action` read as what they mean; any other atom is quoted
    with its truth value, which stays unambiguous whatever words the author chose."""
    arg = literal.arg
    shown = None if arg is None else (arg if is_variable(arg) else _words(arg))
    if literal.name == DO_SAFE and shown is not None:
        return f"{shown} now" if literal.positive else f"do not {shown}"
    if literal.name == GOAL and shown is not None:
        return f"the goal is {shown}" if literal.positive else f"{shown} is not a goal"
    if literal.name == NEXT_ACTION and shown is not None:
        planned = f"the planned action is {shown}"
        return planned if literal.positive else f"the planned action is not {shown}"
    words = _words(literal.name) if shown is None else f"{_words(literal.name)} ({shown})"
    return f"'{words}' is {'true' if literal.positive else 'false'}"


def rule_sentence(rule: Rule) -> str:
    body = " and ".join(literal_words(lit) for lit in rule.body)
    head = literal_words(rule.head)
    if rule.is_fact:
        sentence = f"Known: {head}."
    elif rule.is_default:
        when = f"when {body}, " if body else ""
        sentence = f"Normally, {when}{head}, unless that contradicts what is known."
    else:
        sentence = f"If {body}, then {head}." if body else f"Always: {head}."
    variables = rule.variables
    if variables:
        sentence = f"For any {' and '.join(variables)}: {sentence[0].lower()}{sentence[1:]}"
    label = f"{rule.id} ({_KIND_WORDS.get(rule.kind, rule.kind)}"
    label += " default)" if rule.is_default else " rule)" if rule.body else ")"
    text = f" [{rule.text}]" if rule.text and rule.text.strip() else ""
    return f"{label}: {sentence}{text}"


def plain_rules(theory: DefaultTheory) -> list[str]:
    """Every rule of the theory as one English sentence, facts, strict rules, then defaults."""
    return [rule_sentence(rule) for rule in theory.rules]
