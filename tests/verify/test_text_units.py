"""TEXT reads units: a number written with a unit is converted to the unit of the quantity the
condition reads before it is compared, so "1 km" over `lane_distance_m >= 1000` agrees while
"4 knots" over a limit in m/s does not. Still a warning: a number the condition lacks, a unit
of another kind, a different value once converted.

Conversions are held against the units' definitions (1 nmi = 1852 m, 1 kn = 1852/3600 m/s,
1 kWh = 1000 Wh), not against pint's own tables.
"""

from __future__ import annotations

import json
from typing import Any

import pytest

from countersign.orders.examples import example_bytes
from countersign.orders.expressions.vocabulary import MARITIME_QUANTITIES
from countersign.orders.model import Orders, Quantity
from countersign.verify import validate
from countersign.verify.text import check_text, disagreements
from countersign.verify.units import KNOWN, REL_TOL, Unit, convert, parse_unit, registry

from ..cli.test_cli_startup import _loaded_after

QUANTITIES: dict[str, Quantity] = {
    **MARITIME_QUANTITIES,
    "leg_time_min": Quantity(),  # unit from the name: minutes
    "range_nm": Quantity(unit="nm"),  # declared "nm": nautical miles
    "reserve_kwh": Quantity(unit="kWh"),
}
NMI_M = 1852
KNOT_MPS = 1852 / 3600


def _agrees(text: str, expr: str) -> None:
    assert disagreements(text, expr, QUANTITIES) == [], (text, expr)


def _warns(text: str, expr: str) -> str:
    (problem,) = disagreements(text, expr, QUANTITIES)
    return problem


@pytest.mark.parametrize(("text", "expr"), [
    # m / km / nautical miles
    ("Keep at least 1 km from shipping lanes", "lane_distance_m >= 1000"),
    ("Keep at least 1,000 m from shipping lanes", "lane_distance_m >= 1000"),
    ("Stay within 2.5 kilometres of the recovery point", "base_distance_m <= 2500"),
    ("Keep 1 nm from shore", f"shore_distance_m >= {NMI_M}"),
    ("Keep 1 NM from shore", f"shore_distance_m >= {NMI_M}"),
    ("Keep 2 nmi from shore", f"shore_distance_m >= {2 * NMI_M}"),
    ("Keep 3 nautical miles from shore", f"shore_distance_m >= {3 * NMI_M}"),
    ("Keep 1 nautical mile from shore", f"shore_distance_m >= {NMI_M}"),
    ("Range at most 1852 m", "range_nm <= 1"),
    # m/s / knots
    ("Speed at most 2 knots", "speed_mps <= 1.03"),
    ("Speed at most 3 kn", f"speed_mps <= {round(3 * KNOT_MPS, 3)}"),
    ("Speed at most 1.5 m/s", "speed_mps <= 1.5"),
    # seconds / minutes / hours
    ("Surface within 20 minutes", "elapsed_s <= 1200"),
    ("Surface within 2 hours", "elapsed_s <= 7200"),
    ("Surface within 90 seconds", "elapsed_s <= 90"),
    ("Legs under 1 h", "leg_time_min <= 60"),
    ("Legs under 45 min", "leg_time_min <= 45"),
    ("Legs under 30 s", "leg_time_min <= 0.5"),
    # Wh / kWh
    ("Use at most 1.5 kWh", "energy_wh <= 1500"),
    ("Use at most 1500 Wh", "energy_wh <= 1500"),
    ("Keep 200 Wh in reserve", "reserve_kwh >= 0.2"),
    # several numbers, each with its own quantity
    ("1 km from shipping lanes or deeper than 20 m", "lane_distance_m >= 1000 or depth_m >= 20"),
    # words pint would read as units, and numbers without units
    ("Stop after 3 in a row", "contact_count < 3"),
    ("No more than 5 contacts", "contact_count <= 5"),
])
def test_the_same_amount_in_another_unit_agrees(text: str, expr: str) -> None:
    _agrees(text, expr)


@pytest.mark.parametrize(("text", "expr", "problem"), [
    # a different value once converted
    ("Speed at most 4 knots", "speed_mps <= 2",
     "the text says 4 knots, which is 2.058 m/s, but the condition contains no 2.058"),
    ("Speed at most 4 knots", "speed_mps <= 4",
     "the text says 4 knots, which is 2.058 m/s, but the condition contains no 2.058"),
    ("Minimum depth of 20 feet", "depth_m >= 20",
     "the text says 20 feet, which is 6.096 m, but the condition contains no 6.096"),
    ("Use at most 1.5 kWh", "energy_wh <= 1.5",
     "the text says 1.5 kWh, which is 1,500 Wh, but the condition contains no 1,500"),
    ("Surface within 20 minutes", "elapsed_s <= 20",
     "the text says 20 minutes, which is 1,200 s, but the condition contains no 1,200"),
    ("Keep at least 1 km from shipping lanes", "lane_distance_m >= 1",
     "the text says 1 km, which is 1,000 m, but the condition contains no 1,000"),
    # "nm" is the nautical mile: as a nanometre 1 nm would be 0.000000001 m, never 1 m
    ("Keep 1 nm from shore", "shore_distance_m >= 1",
     "the text says 1 nm, which is 1,852 m, but the condition contains no 1,852"),
    # a number with no matching limit, in the quantity's own unit or with none
    ("Keep 3 m above the seabed", "altitude_m >= 0.5",
     "the text says 3 m but the condition contains no 3"),
    ("Sea state at most 5", "sea_state <= 4",
     "the text says 5 but the condition contains no 5"),
    # a unit of another kind
    ("Keep 20 minutes of depth", "depth_m >= 20",
     "the text says 20 minutes but the condition reads only quantities in m, which minutes "
     "cannot be converted to"),
    ("Keep 2 knots from shipping lanes", "lane_distance_m >= 2",
     "the text says 2 knots but the condition reads only quantities in m, which knots cannot "
     "be converted to"),
])
def test_a_different_amount_or_kind_warns(text: str, expr: str, problem: str) -> None:
    assert _warns(text, expr) == problem


def test_tolerance_takes_rounding_not_a_wrong_unit() -> None:
    # Two knots is 1.0289 m/s: 1.03 is it rounded (0.1 % off), 1.0 is not (2.8 % off).
    assert REL_TOL == 0.01
    assert abs(2 * KNOT_MPS - 1.03) / 1.03 < REL_TOL < abs(2 * KNOT_MPS - 1.0)
    _agrees("Speed at most 2 knots", "speed_mps <= 1.03")
    _warns("Speed at most 2 knots", "speed_mps <= 1.0")
    # 1 nmi is 1852 m: a limit of 1900 m (2.6 % off) is another distance, not a rounding
    _warns("Keep 1 nmi from shore", "shore_distance_m >= 1900")


def _exemplar() -> dict[str, Any]:
    data: dict[str, Any] = json.loads(example_bytes("search-and-sample"))
    return data


def _text_findings(data: dict[str, Any]) -> list[tuple[tuple[str, ...], str]]:
    return [(f.subjects, f.message) for f in check_text(Orders.model_validate(data))]


def test_product_owner_examples_give_no_text_warning_in_orders() -> None:
    data = _exemplar()
    data["constraints"][3].update(text="Keep at least 1 km from shipping lanes",
                                  expr="lane_distance_m >= 1000")
    # A quantity only the vehicle measures: no declared unit, so `_m` in its name gives it.
    data["vehicles"][0]["features"][0]["measures"].append("mothership_distance_m")
    data["constraints"].append({"id": "C8", "text": "Within 2 km of the mothership",
                                "applies_to": "mission", "expr": "mothership_distance_m <= 2000"})
    report = validate(Orders.model_validate(data))
    assert [f for f in report.findings if f.code == "TEXT"] == []


def test_a_speed_in_knots_over_a_limit_in_mps_is_one_text_warning() -> None:
    data = _exemplar()
    data["quantities"]["speed_mps"] = {"unit": "m/s", "min": 0, "title": "Speed"}
    data["constraints"].append({"id": "C8", "text": "Speed at most 4 knots",
                                "applies_to": "mission", "expr": "speed_mps <= 4"})
    assert _text_findings(data) == [(("C8",), (
        "Constraint C8: the text says 4 knots, which is 2.058 m/s, but the condition contains "
        "no 2.058 (`speed_mps <= 4`). The supervisor reads the text; the vehicle tests the "
        "condition."))]


def test_norm_texts_are_read_the_same_way() -> None:
    data = _exemplar()
    data["norms"][0].update(text="No sampling within 1 nm of a protected area",
                            forbidden=f"behavior == 'sample' and shore_distance_m < {NMI_M}")
    assert _text_findings(data) == []
    data["norms"][0]["forbidden"] = "behavior == 'sample' and shore_distance_m < 1"
    ((subjects, message),) = _text_findings(data)
    assert subjects == (data["norms"][0]["id"],)
    assert "the text says 1 nm, which is 1,852 m" in message


def test_pint_loads_only_when_a_text_may_write_a_unit() -> None:
    # pint costs about a second to import and set up: orders whose texts write no number
    # followed by a word, and every command that never validates, must not pay for it.
    data = _exemplar()
    for constraint in data["constraints"]:
        constraint["text"] = "Keep within limits"
    data["constraints"][0]["text"] = "Navigation error at most 10"
    probe = ("from countersign.orders.model import Orders\n"
             "from countersign.verify.text import check_text\n"
             "check_text(Orders.model_validate_json({!r}))\n")
    assert "pint" not in _loaded_after(probe.format(json.dumps(data)))
    # The exemplar writes its numbers in the units its conditions read ("1000 meters"), which
    # the known units cover; "1 km" over a quantity in metres needs pint's conversion.
    assert "pint" not in _loaded_after(probe.format(json.dumps(_exemplar())))
    data = _exemplar()
    data["constraints"][3]["text"] = "A lateral standoff of 1 km from shipping lanes."
    data["constraints"][3]["expr"] = "lane_distance_m >= 1000"
    assert "pint" in _loaded_after(probe.format(json.dumps(data)))


@pytest.mark.parametrize("word", sorted(KNOWN))
def test_the_units_known_without_pint_are_as_pint_reads_them(word: str) -> None:
    """KNOWN (the units read without importing pint) names each unit as pint does, and a
    number in the unit it is compared in is what pint's conversion gives."""
    assert str(registry().parse_units(word)) == KNOWN[word]
    unit = parse_unit(word)
    assert unit is not None and unit.name == KNOWN[word]
    for value in (1000.0, 0.1, 3.3333333333333335, 1e-300, 5e20):
        by_pint = float(registry().Quantity(value, registry().parse_units(word)).to(
            registry().parse_units(KNOWN[word])).magnitude)
        assert convert(value, unit, Unit(KNOWN[word], KNOWN[word])) == by_pint == value
