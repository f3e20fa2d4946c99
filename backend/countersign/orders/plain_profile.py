"""Plain words for what the orders carry besides goals and constraints: path properties
and the vehicle profile that the checks ran against (M6, M7, BUDGET).

All of it is inside the signed digests (the orders', and the profile copied into the version),
so all of it is shown to the supervisor who signs. The contingency rules follow in words from
`rules.plain_orders` (the section the plain export appends).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence

from .conditions import condition_words
from .expressions import number_words, quantity_words, with_unit
from .model import Orders, Quantity, Vehicle
from .pattern_words import pattern_sentence
from .profile import lists_behaviors, trusted_behaviors


def _one_line(text: str) -> str:
    return " ".join(text.split())


def _sentence(text: str) -> str:
    text = _one_line(text)
    return text if not text or text[-1] in ".!?" else text + "."


def _list(items: Sequence[str]) -> str:
    return ", ".join(_one_line(i) for i in items) if items else "nothing"


def plain_properties(orders: Orders, quantities: Mapping[str, Quantity]) -> list[str]:
    if not orders.properties:
        return []
    blocks = ["Path properties"]
    for number, prop in enumerate(orders.properties, start=1):
        if prop.pattern is not None:
            blocks.append(f"Property {number} ({prop.id}): {pattern_sentence(prop)}"
                          + (f" {_sentence(prop.text)}" if prop.text else ""))
            continue
        mode, expr = ("always", prop.always) if prop.always else ("never", prop.never)
        checked = condition_words(expr, quantities)
        # "always" must hold at every goal of every path; "never" at no goal of any path.
        parts = [f"Property {number} ({prop.id}): on every path, {mode}."]
        if prop.text:
            parts.append(_sentence(prop.text))
        parts.append(checked)
        blocks.append(" ".join(parts))
    return blocks


def _interval(name: str, low: float, high: float, quantities: Mapping[str, Quantity]) -> str:
    spec = quantities.get(name)
    unit = spec.unit if spec is not None else ""
    span = f"{number_words(low)} to {number_words(high)}"
    return f"{quantity_words(name, quantities)} {with_unit(span, unit)} (`{name}`)"


def plain_vehicle(vehicle: Vehicle | None, quantities: Mapping[str, Quantity]) -> list[str]:
    """The profile the checks ran against: features, behaviours, envelope, speed and budget."""
    if vehicle is None:
        return ["Vehicle profile", "No profile of the target vehicle was checked."]
    title = _one_line(vehicle.title)
    lines = [f"Profile: {title} ({vehicle.id})" if title else f"Profile: {vehicle.id}"]
    trusted = _list([b.replace("_", " ") for b in trusted_behaviors(vehicle)])
    derived = "" if lists_behaviors(vehicle) else " (those its features fulfil)"
    lines.append(f"Trusted behaviours: {trusted}{derived}.")
    for feature in vehicle.features:
        name = f"{feature.id} ({_one_line(feature.title)})" if feature.title else feature.id
        measured = [f"{quantity_words(q, quantities)} (`{q}`)" for q in feature.measures]
        lines.append(
            f"Feature {name}: fulfils {_list(feature.fulfills)}; measures {_list(measured)}."
        )
    if vehicle.envelope:
        limits = [_interval(n, lo, hi, quantities) for n, (lo, hi) in vehicle.envelope.items()]
        lines.append(f"Envelope: {'; '.join(limits)}.")
    if vehicle.speed_mps is not None:
        lines.append(f"Speed: {number_words(vehicle.speed_mps)} m/s.")
    if vehicle.power_w is not None:
        lines.append(f"Power: {number_words(vehicle.power_w)} W.")
    budget = vehicle.budget
    if budget is not None and (budget.energy_wh is not None or budget.duration_s is not None):
        parts = []
        if budget.energy_wh is not None:
            parts.append(f"energy {number_words(budget.energy_wh)} Wh")
        if budget.duration_s is not None:
            parts.append(f"duration {number_words(budget.duration_s)} s")
        lines.append(f"Budget: {', '.join(parts)}.")
    else:
        lines.append("Budget: none given.")
    return ["Vehicle profile", "\n".join(lines)]
