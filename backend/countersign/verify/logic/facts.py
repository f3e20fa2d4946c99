"""The items of a goal's facts: its behaviour, its area, whether its area carries a tag.

Each is made once per goal (and suffix) and model, through the model's memo; `model` is the
model they belong to.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import TYPE_CHECKING, Literal

from ...orders.model import Goal
from ..expressions import in_tag, smt_int, tag_state
from .items import Item, _with_suffix

if TYPE_CHECKING:
    from .model import LogicModel


def behavior_item(model: LogicModel, goal: Goal, label: str, suffix: str) -> Item:
    return _named_code_item(
        model, goal, "beh", "behavior", goal.behavior, suffix,
        lambda: (f"{label} has behavior {goal.behavior!r}" if goal.behavior
                 else f"{label} names no behavior"),
        lambda: f"{goal.behavior}")


def area_item(model: LogicModel, goal: Goal, label: str, suffix: str) -> Item:
    return _named_code_item(
        model, goal, "area", "area", goal.area, suffix,
        lambda: (f"{label} runs in {model.area_label(goal.area)}" if goal.area
                 else f"{label} names no area"),
        lambda: f"{goal.area}|{model.area_label(goal.area or '')}")


def _named_code_item(model: LogicModel, goal: Goal, prefix: str,
                     kind: Literal["behavior", "area"],
                     value: str | None, suffix: str, sentence: Callable[[], str],
                     text_tail: Callable[[], str]) -> Item:
    """A goal's fact that names one thing (its behaviour, its area) as a string code."""
    key = f"{prefix}:{goal.id}{suffix}"

    def made() -> Item:
        return Item(
            key, kind, goal.id, sentence, f"{key}|{goal.title}|{text_tail()}",
            _with_suffix(lambda t: f"(= {t.special(kind)} {smt_int(t.string_code(value))})",
                         suffix),
            shared=False,
            meaning=None if suffix else ("fact", kind, value),
        )

    return model._memo(key, made)


def context_item(model: LogicModel, goal: Goal, label: str, tag: str, holds: bool,
                 suffix: str) -> Item:
    key = f"ctx:{goal.id}:{tag}{suffix}"

    def context() -> Item:
        def phrase() -> str:
            if goal.area:
                return f"{model.area_label(goal.area)} {tag_state(tag, holds)}"
            return f"{label} names no area, so it is not {in_tag(tag)}"

        return Item(
            key, "context", goal.area or goal.id, phrase,
            f"{key}|{goal.title}|{goal.area}|{model.area_label(goal.area or '')}|{holds}",
            _with_suffix(
                lambda t: t.context(tag) if holds else f"(not {t.context(tag)})", suffix
            ),
            shared=False,
            meaning=None if suffix else ("fact", ("ctx", tag), holds),
        )

    return model._memo(key, context)
