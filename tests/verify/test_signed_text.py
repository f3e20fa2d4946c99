"""What the supervisor reads is what they sign.

Plain orders show each condition in words and symbols, each terminal by its own title and the
vehicle profile checked; TEXT flags a text that says another number than its condition;
VEHICLE flags orders whose vehicle has no profile; M7 flags an untrusted behaviour; asserted
canTest / NPS canMeasure are honoured on re-import.
"""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

import pytest

from countersign.orders.avcl import read_avcl
from countersign.orders.canonical import orders_to_json
from countersign.orders.examples import example_bytes, load_example
from countersign.orders.model import Orders, Vehicle
from countersign.orders.plain import plain_orders
from countersign.orders.reader import read_json
from countersign.orders.turtle import read_turtle, write_nps_turtle, write_turtle
from countersign.verify.report import validate
from countersign.verify.vehicle import with_registry_profile

from ..cli.test_bad_input import run_cli


def _reference() -> Path | None:
    here = Path(__file__).resolve()
    for root in (*here.parents, Path("/work")):
        candidate = root / "shared" / "reference" / "nps-ethical-control" / "missions" / "avcl"
        if candidate.is_dir():
            return candidate
    return None


AVCL = _reference()
needs_nps = pytest.mark.skipif(AVCL is None, reason="NPS reference missions not present")


def exemplar() -> dict[str, Any]:
    data: dict[str, Any] = json.loads(example_bytes("search-and-sample"))
    return data


def codes(orders: Orders) -> list[str]:
    return [f.code for f in validate(orders).findings]


# A. Plain orders


def test_changing_only_a_condition_changes_the_plain_orders() -> None:
    data = exemplar()
    before = plain_orders(read_json(json.dumps(data).encode()))
    data["constraints"][6]["expr"] = "depth_m >= 0.5"
    after = plain_orders(read_json(json.dumps(data).encode()))
    assert before != after
    assert "Checked as: depth at least 20 m (`depth_m >= 20`)." in before
    assert "Checked as: depth at least 0.5 m (`depth_m >= 0.5`)." in after


@needs_nps
def test_sailor_overboard_terminals_print_by_their_own_titles() -> None:
    assert AVCL is not None
    text = plain_orders(read_avcl((AVCL / "SailorOverboard.xml").read_bytes()).orders)
    goal1 = next(p for p in text.split("\n\n") if p.startswith("Goal 1"))
    assert "If it fails, abort the mission: Halt and deploy recovery beacon." in goal1
    assert ("If a constraint is about to be violated, abort the mission: Halt and await "
            "further orders.") in goal1


def test_plain_orders_show_the_vehicle_profile_and_properties() -> None:
    data = exemplar()
    data["properties"] = [{"id": "P1", "never": "depth_m > 90", "text": "Stay shallow"}]
    text = plain_orders(read_json(json.dumps(data).encode()))
    assert "Trusted behaviours: area search, sample, rendezvous, transit." in text
    assert "Feature sampler (Water sampler): fulfils sample; measures nothing." in text
    assert "Envelope: depth 0 to 100 m (`depth_m`)" in text
    assert "Budget: energy 1,500 Wh, duration 43,200 s." in text
    assert ("Property 1 (P1): on every path, never. Stay shallow. "
            "Checked as: depth above 90 m (`depth_m > 90`).") in text


# B. TEXT


def test_exemplar_text_agrees_with_its_conditions() -> None:
    assert "TEXT" not in codes(load_example("search-and-sample"))


@pytest.mark.parametrize(
    ("where", "index", "field", "value"),
    [
        ("constraints", 6, "expr", "depth_m >= 2"),  # text says 20 meters
        ("constraints", 4, "text", "Detect surface contacts within 4000 meters."),
        ("constraints", 6, "text", "Minimum depth of 20 feet is to be maintained."),
        ("norms", 0, "text", "No sampling within 500 m of a marine protected area"),
    ],
)
def test_planted_mismatch_gives_one_text_warning(
    where: str, index: int, field: str, value: str
) -> None:
    data = exemplar()
    data[where][index][field] = value
    findings = [f for f in validate(read_json(json.dumps(data).encode())).findings
                if f.code == "TEXT"]
    assert len(findings) == 1
    assert findings[0].severity == "warning"
    assert findings[0].subjects == (data[where][index]["id"],)


# C. VEHICLE, M7, canTest


def test_unknown_vehicle_is_a_vehicle_error(tmp_path: Path) -> None:
    data = exemplar()
    data["vehicle"] = "no-such-auv"
    path = tmp_path / "orders.json"
    path.write_text(json.dumps(data))
    result = run_cli("validate", str(path))
    assert result.returncode == 1, result.stdout + result.stderr
    assert "VEHICLE" in result.stdout and "no-such-auv" in result.stdout


def test_built_in_examples_carry_their_profiles() -> None:
    from countersign.orders.examples import example_names

    for name in example_names():
        assert "VEHICLE" not in codes(load_example(name)), name


def test_registry_profile_is_copied_into_the_orders() -> None:
    data = exemplar()
    profile = Vehicle.model_validate(data.pop("vehicles")[0])
    orders = read_json(json.dumps(data).encode())
    assert "VEHICLE" in codes(orders)
    filled = with_registry_profile(orders, {profile.id: profile}.get)
    assert filled.target_vehicle() == profile
    assert "VEHICLE" not in codes(filled)
    assert orders_to_json(filled)["vehicles"][0]["id"] == profile.id


def test_behaviour_the_vehicle_lacks_is_m7() -> None:
    data = exemplar()
    data["goals"][0]["behavior"] = "hover"
    findings = [f for f in validate(read_json(json.dumps(data).encode())).findings
                if f.code == "M7"]
    assert [f.subjects for f in findings] == [("G1", "remus-100")]
    assert "hover" in findings[0].message


@needs_nps
def test_avcl_vehicle_name_alone_is_not_a_profile() -> None:
    assert AVCL is not None
    orders = read_avcl((AVCL / "SailorOverboard.xml").read_bytes()).orders
    assert codes(orders).count("VEHICLE") == 1


def test_nps_export_of_the_exemplar_reimports_with_no_m6() -> None:
    nps = write_nps_turtle(load_example("search-and-sample"))
    orders = read_turtle(nps.encode()).orders
    assert "M6" not in codes(orders)


def test_asserted_cantest_is_honoured() -> None:
    data = exemplar()
    for feature in data["vehicles"][0]["features"]:
        feature["measures"] = [q for q in feature["measures"] if q != "depth_m"]
    m6 = [f.subjects for f in validate(read_json(json.dumps(data).encode())).findings
          if f.code == "M6"]
    assert ("C7", "remus-100") in m6
    data["vehicles"][0]["features"][0]["tests"] = ["C7", "C4"]
    orders = read_json(json.dumps(data).encode())
    assert "M6" not in codes(orders)
    # and it survives our own Turtle
    assert "M6" not in codes(read_turtle(write_turtle(orders).encode()).orders)


# D. Imported reader findings stay with the orders


@needs_nps
def test_pirates_sink_warnings_survive_storage_as_json() -> None:
    assert AVCL is not None
    loaded = read_avcl((AVCL / "PiratesSeizingMerchantDefense.xml").read_bytes())
    reader_sinks = [f for f in loaded.findings if f.code == "SINK"]
    assert len(reader_sinks) == 19
    # as the server stores it: the orders JSON alone, no reader findings
    stored = read_json(json.dumps(orders_to_json(loaded.orders)).encode())
    sinks = [f for f in validate(stored).findings if f.code == "SINK" and f.severity == "warning"]
    assert [f.message for f in sinks] == [f.message for f in reader_sinks]
    # given by the reader too, they are not repeated
    both = validate(loaded.orders, loaded.findings).findings
    assert sum(f.code == "SINK" and f.severity == "warning" for f in both) == 19


def test_a_default_the_author_replaced_is_no_longer_reported() -> None:
    data = exemplar()
    goal = data["goals"][0]
    goal["defaulted"] = {"violate": "fail"}
    goal["next"]["violate"] = goal["next"]["fail"]
    orders = read_json(json.dumps(data).encode())
    assert [f.subjects for f in validate(orders).findings if f.code == "SINK"] == [("G1",)]
    goal["next"]["violate"] = "ABORT" if goal["next"]["fail"] != "ABORT" else "COMPLETE"
    orders = read_json(json.dumps(data).encode())
    assert "SINK" not in codes(orders)
