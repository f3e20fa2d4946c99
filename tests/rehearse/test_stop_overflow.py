"""Stopping a rehearsal whose figures overflow (goal costs near the largest
double, so energy and time sum to infinity) stores a record that names what it could not hold,
instead of failing on its digest and losing the record."""

from __future__ import annotations

import math

import rfc8785

from countersign.orders.examples import load_example
from countersign.rehearse.manager import Rehearsal, RehearsalOptions
from countersign.rehearse.record import RehearsalRecord, representable


def test_an_overflowing_rehearsal_stops_into_a_record_with_a_digest() -> None:
    orders = load_example("search-and-sample")
    huge = orders.model_copy(update={"goals": [
        goal.model_copy(update={"energy_wh": 1.7e308, "duration_s": 1.7e308})
        for goal in orders.goals]})
    rehearsal = Rehearsal(huge, owner="test", headless=True,
                          options=RehearsalOptions(source="simulate", seed=1))
    rehearsal.run_headless(max_wall_s=120)
    record = rehearsal.stop()
    assert record.digest.startswith("sha256:")
    data = record.to_json()
    rfc8785.dumps(data)  # every number representable


def test_records_without_overflow_keep_their_digest() -> None:
    data = {"format": "x", "energy": {"used_wh": 1.5}, "steps": 3, "runs": [[1, 2.0]]}
    assert representable(data) == data
    assert RehearsalRecord(dict(data)).canonical_bytes() == rfc8785.dumps(data)


def test_a_record_with_an_infinite_figure_has_a_digest_and_says_why() -> None:
    record = RehearsalRecord({"format": "x", "sim_time_s": math.inf,
                              "energy": {"used_wh": math.nan}})
    assert record.digest.startswith("sha256:")
    assert record.to_json()["unrepresentable"] == ["$.sim_time_s", "$.energy.used_wh"]


def test_unrepresentable_numbers_are_null_and_named() -> None:
    cleaned = representable({"a": math.inf, "b": [1, math.nan], "c": {"d": 2**60}, "e": True})
    assert cleaned == {"a": None, "b": [1, None], "c": {"d": None}, "e": True,
                       "unrepresentable": ["$.a", "$.b[1]", "$.c.d"]}
