"""AVCL 3.1 for the NPS tools, with notes of what AVCL cannot carry (as for IMC and MOOS-IvP).

The document itself is written by `orders.avcl_writer` (it is also an orders format, read back by
`orders.avcl`); this adds what the orders say beyond goals, successors, terminals, behaviours,
phases, areas and durations: constraints (AVCL's Risk names only the NPS risk taxonomy),
requirements, envelopes, energy costs, outcome probabilities, vehicle details, norms, rules and
path properties. A team member's orders are written as a document of their own (AVCL has one
vehicle per mission); its meetings, which AVCL cannot state, are notes.
"""

from __future__ import annotations

from ..orders.avcl_writer import avcl_document
from ..orders.model import Orders
from .common import uncarried
from .notes import ExportFile, ExportNote, VehicleExport
from .team import Member

FORMAT = "AVCL"


def export_avcl(orders: Orders, member: Member | None = None) -> VehicleExport:
    """AVCL of one vehicle's orders; `member`: those are a team member's own orders."""
    document = avcl_document(orders)
    notes = [ExportNote(gap.code, gap.path, gap.message) for gap in document.gaps]
    for index, goal in enumerate(orders.goals):
        where = f"/goals/{index}"
        meeting = member.meeting_of(goal.meet) if member is not None else None
        if meeting is not None:
            notes.append(ExportNote("MEET", f"{where}/meet", f"goal {goal.id} is meeting "
                                    f"{meeting.meet} with "
                                    f"{', '.join(meeting.partners) or 'no other member'}: AVCL "
                                    "has no meeting of vehicles: the goal is written, the "
                                    "wait for every member is not"))
        if goal.refines is not None:
            notes.append(ExportNote("REFINE", f"{where}/refines", f"goal {goal.id}: its "
                                    "refinement has no AVCL form; not written"))
        if goal.requires:
            notes.append(ExportNote("REQUIRES", f"{where}/requires", f"goal {goal.id}: "
                                    "requirements have no AVCL form; not written"))
        for quantity in sorted(goal.envelope):
            notes.append(ExportNote("ENVELOPE", f"{where}/envelope/{quantity}",
                                    f"goal {goal.id}: the bound on {quantity} is not carried"))
        if goal.cost is not None and goal.cost.energy_wh is not None:
            notes.append(ExportNote("COST", f"{where}/cost/energy_wh", f"goal {goal.id}: AVCL "
                                    "has a Duration but no energy cost; not written"))
        if goal.p is not None:
            notes.append(ExportNote("PROBABILITY", f"{where}/p", f"goal {goal.id}: outcome "
                                    "probabilities have no AVCL form; not written"))
    for index, constraint in enumerate(orders.constraints):
        notes.append(ExportNote("CONSTRAINT", f"/constraints/{index}",
                                f"constraint {constraint.id} has no AVCL form (a Risk names only "
                                "the NPS risk taxonomy); not written"))
    for index, vehicle in enumerate(orders.vehicles):
        notes.append(ExportNote("VEHICLE", f"/vehicles/{index}", f"vehicle {vehicle.id}: only "
                                "the target vehicle's name and type are written"))
    uncarried(orders, FORMAT, notes)
    name = f"{orders.id}.xml"
    return VehicleExport("avcl", (ExportFile(name, "application/xml",
                                             document.text.encode("utf-8")),), tuple(notes))
