"""Every IMC export is read by a strict reader generated from IMC.xml (pyimclsts, plus the
bitfield and ASCII checks it leaves out) as well as by imcpy, and both read the same plan."""

from __future__ import annotations

from collections.abc import Iterator
from pathlib import Path
from typing import Any
from urllib.parse import unquote

import imcpy
import pytest

from countersign.export.notes import ExportError
from countersign.export.vehicle import export_vehicle
from countersign.orders.examples import example_bytes, example_names
from countersign.orders.model import Orders
from countersign.orders.reader import read_bytes, read_file

from .readers import AVCL, read_imc
from .strict_imc import StrictReader, imc_xml_or_skip

# refined_twice.json: refinements two deep, maneuver ids such as G1/G1.2#2/G1.2.1
SOURCES = [f"example:{name}" for name in example_names()] + [str(p) for p in AVCL] + \
    [str(Path(__file__).with_name("refined_twice.json"))]


@pytest.fixture(scope="module")
def strict(tmp_path_factory: pytest.TempPathFactory) -> Iterator[StrictReader]:
    yield StrictReader(imc_xml_or_skip(), tmp_path_factory.mktemp("pyimclsts"))


def _orders(source: str) -> Orders:
    if source.startswith("example:"):
        name = source.removeprefix("example:")
        return read_bytes(example_bytes(name), name).orders
    return read_file(source).orders


def _plan_of(maneuver: Any) -> bytes:
    step = imcpy.PlanManeuver()
    step.maneuver_id = "G1"
    step.data = maneuver
    plan = imcpy.PlanSpecification()
    plan.plan_id, plan.start_man_id = "p", "G1"
    plan.maneuvers.append(step)
    return bytes(plan.serialize())


def _loiter(**fields: Any) -> Any:
    loiter = imcpy.Loiter()
    loiter.type = int(imcpy.Loiter.LoiterTypeEnum.CIRCULAR)
    loiter.radius, loiter.length = 20.0, 40.0
    for name, value in fields.items():
        setattr(loiter, name, value)
    return loiter


def _popup(flags: int) -> Any:
    popup = imcpy.PopUp()
    popup.radius, popup.flags = 20.0, flags
    return popup


def test_the_strict_reader_reads_a_plan_within_imc_xml(strict: StrictReader) -> None:
    assert strict.read(_plan_of(_loiter()))["maneuvers"][0]["data"]["length"] == 40.0


@pytest.mark.parametrize(("maneuver", "refusal"), [
    # The reported case: imcpy writes and reads it, IMC.xml says min="1".
    (lambda: _loiter(length=0.0), "minimum value for attribute length is 1"),
    (lambda: _loiter(radius=0.5), "minimum value for attribute radius is 1"),
    (lambda: _loiter(z_units=7), "not a valid ZUnits"),
    (lambda: _popup(0x80), "sets bits IMC.xml does not define"),
    (lambda: _loiter(custom="title=caf\u00e9"), "not printable ASCII"),
], ids=["loiter-length-0", "loiter-radius-0.5", "loiter-z-units-7", "popup-flag-0x80",
        "custom-non-ascii"])
def test_the_strict_reader_refuses_what_imc_xml_forbids(
        strict: StrictReader, maneuver: Any, refusal: str) -> None:
    data = _plan_of(maneuver())
    imcpy.Packet.deserialize(data)  # imcpy is lenient: it reads every one of these
    with pytest.raises((ValueError, AssertionError), match=refusal):
        strict.read(data)


@pytest.mark.parametrize("source", SOURCES, ids=[Path(s).name for s in SOURCES])
def test_every_imc_export_passes_the_strict_reader(strict: StrictReader, source: str) -> None:
    data = export_vehicle(_orders(source), "imc").primary.content
    plan = strict.read(data)
    lenient, _ = read_imc(data)
    # Both readers see the same maneuvers and transitions.
    assert [(m["maneuver_id"], m["data"]["msg"]) for m in plan["maneuvers"]] == \
        [(m.maneuver_id, m.data.msg_name) for m in lenient.maneuvers]
    assert [(t["source_man"], t["dest_man"], t["conditions"]) for t in plan["transitions"]] \
        == [(t.source_man, t.dest_man, t.conditions) for t in lenient.transitions]


def _rendezvous(**goal: Any) -> Orders:
    data = _orders("example:search-and-sample").model_dump(mode="json", exclude_unset=True)
    data["goals"] = [{**g, **goal} if g["id"] == "G4" else g for g in data["goals"]]
    return Orders.model_validate(data)


def test_user_text_and_large_areas_stay_within_imc_xml(strict: StrictReader) -> None:
    title = "Caf\u00e9; rendezvous=\u00fcber 100% \u2028 line"
    data = _rendezvous(title=title).model_dump(mode="json", exclude_unset=True)
    # Area C grows to ~ 4 degrees of latitude: half its side is far over Loiter's 100 km radius.
    data["areas"] = [{**a, "polygon": [[38.7, -121.88], [38.7, -119.0], [34.7, -119.0],
                                       [34.7, -121.88]]} if a["id"] == "C" else a
                     for a in data["areas"]]
    plan = strict.read(export_vehicle(Orders.model_validate(data), "imc").primary.content)
    loiter = next(m["data"] for m in plan["maneuvers"] if m["maneuver_id"] == "G4")
    assert loiter["msg"] == "Loiter"
    assert loiter["radius"] == 100_000.0 and 1 <= loiter["length"] <= 100_000
    custom = dict(kv.split("=", 1) for kv in loiter["custom"].split(";"))
    assert unquote(custom["title"]) == title  # percent-escaped, not lost


def test_a_goal_longer_than_an_imc_duration_is_refused_by_name() -> None:
    orders = _rendezvous(cost={"duration_s": 70_000})
    with pytest.raises(ExportError, match=r"goal G4 lasts 70,000 s.*at most 65,535 s"):
        export_vehicle(orders, "imc")
