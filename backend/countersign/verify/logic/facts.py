"""The items of a goal's facts: its behaviour, its area, whether its area carries a tag.

Each is made once per goal (and suffix) and model, through the model's memo; `model` is the
model they belong to.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from ...orders.model import Goal
from ..expressions import in_tag, smt_int, tag_state
from .items import Item, _with_suffix

if TYPE_CHECKING:
    from .model import LogicModel


def behavior_item(model: LogicModel, goal: Goal, label: str, suffix: str) -> Item:
    key = f"beh:{goal.id}{suffix}"

    def behavior() -> Item:
        code_of = goal.behavior
        return Item(
            key, "behavior", goal.id,
            lambda: (f"{label} has behavior {goal.behavior!r}" if goal.behavior
                     else f"{label} names no behavior"),
            f"{key}|{goal.title}|{goal.behavior}",
            _with_suffix(
                lambda t: f"(= {t.special('behavior')} {smt_int(t.string_code(code_of))})",
                suffix,
            ),
            shared=False,
            meaning=None if suffix else ("fact", "behavior", goal.behavior),
        )

    return model._memo(key, behavior)


def area_item(model: LogicModel, goal: Goal, label: str, suffix: str) -> Item:
    key = f"area:{goal.id}{suffix}"

    def area() -> Item:
        code_of = goal.area
        return Item(
            key, "area", goal.id,
            lambda: (f"{label} runs in {model.area_label(goal.area)}" if goal.area
                     else f"{label} names no area"),
            f"{key}|{goal.title}|{goal.area}|{model.area_label(goal.area or '')}",
            _with_suffix(
                lambda t: f"(= {t.special('area')} {smt_int(t.string_code(code_of))})",
                suffix,
            ),
            shared=False,
            meaning=None if suffix else ("fact", "area", goal.area),
        )

    return model._memo(key, area)


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
