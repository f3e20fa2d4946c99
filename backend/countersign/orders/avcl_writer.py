"""Write orders as AVCL mission XML for the NPS AUV Workbench and its tools.

Goals keep their successors as nextOnSuccess / nextOnFailure / nextOnException; terminals
become terminal goals (no successors), which is how AVCL ends a mission. The registry charts
the orders were checked with (issue 21) travel in the head, one `<meta name="countersign:chart">`
each holding the chart as JSON (AVCL has no mission-wide area element; tools ignore meta names
they do not know), and `read_avcl` reads them back. Writing uses the standard library (only
reading untrusted XML needs defusedxml).
"""

from __future__ import annotations

import json
import xml.etree.ElementTree as ET

from .model import Orders

CHART_META = "countersign:chart"
HANDLERS = (("succeed", "nextOnSuccess"), ("fail", "nextOnFailure"),
            ("violate", "nextOnException"))


def _element_name(behavior: str) -> str:
    return "".join(part.capitalize() for part in behavior.split("_")) or "SpecialGoal"


def write_avcl(orders: Orders) -> str:
    root = ET.Element("AVCL", {"version": "3.1"})
    vehicle = orders.target_vehicle()
    if orders.vehicle:
        root.set("vehicleName", vehicle.title or vehicle.id if vehicle else orders.vehicle)
    head = ET.SubElement(root, "head")
    ET.SubElement(head, "meta", {"name": "title", "content": f"{orders.id}.xml"})
    if orders.title:
        ET.SubElement(head, "meta", {"name": "description", "content": orders.title})
    ET.SubElement(head, "meta", {"name": "generator", "content": "Countersign"})
    for chart in orders.charts:
        content = json.dumps(chart.model_dump(mode="json", exclude_unset=True),
                             ensure_ascii=False, separators=(",", ":"))
        ET.SubElement(head, "meta", {"name": CHART_META, "content": content})
    body = ET.SubElement(root, "body")
    definition = ET.SubElement(body, "MissionDefinition",
                               {"description": orders.description or orders.title})
    goal_list = ET.SubElement(ET.SubElement(definition, "AgendaMission"), "GoalList")
    start = orders.start if isinstance(orders.start, str) else None
    # AVCL starts with the first goal listed, so the start goal goes first.
    goals = sorted(orders.goals, key=lambda g: g.id != start)
    for goal in goals:
        attributes = {"id": goal.id, "title": goal.title or goal.id}
        if goal.description:
            attributes["description"] = goal.description
        for outcome, attribute in HANDLERS:
            targets = goal.successors(outcome)
            if targets:
                attributes[attribute] = targets[0]
        element = ET.SubElement(goal_list, "Goal", attributes)
        if goal.behavior:
            ET.SubElement(element, _element_name(goal.behavior))
        if goal.cost and goal.cost.duration_s is not None:
            ET.SubElement(element, "Duration", {"value": f"{goal.cost.duration_s:g}"})
    for terminal in orders.effective_terminals:
        ET.SubElement(goal_list, "Goal", {
            "id": terminal.id, "title": terminal.label,
            "description": "Mission complete, final success state" if terminal.kind == "complete"
            else "Mission aborted, final failure state",
        })
    ET.indent(root)
    return '<?xml version="1.0" encoding="UTF-8"?>\n' + ET.tostring(root, "unicode") + "\n"
