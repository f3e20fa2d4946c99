"""`serve --demo` seeds the vehicle registry with the examples' vehicles, so a
first run's new mission picks a registered vehicle instead of opening with a VEHICLE error; a
second start adds nothing and keeps what an admin changed."""

from __future__ import annotations

import argparse
import os
from pathlib import Path

import pytest
from sqlalchemy import select

from countersign.cli.server import _seed_demo, open_database
from countersign.orders.examples import example_bytes, example_names
from countersign.orders.reader import read_bytes
from countersign.store.tables import Event, VehicleProfile, VehicleVersion


def test_demo_seeds_the_registry_once(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> None:
    for name in [k for k in os.environ if k.startswith("COUNTERSIGN_")]:
        monkeypatch.delenv(name)
    _, database = open_database(argparse.Namespace(data_dir=tmp_path))
    _seed_demo(database)
    wanted = {v.id for name in example_names()
              for v in read_bytes(example_bytes(name), name).orders.vehicles}
    assert wanted, "the examples carry vehicle profiles"
    with database.session() as db:
        assert set(db.scalars(select(VehicleProfile.id))) == wanted
        saved = [e.detail for e in db.scalars(select(Event).where(Event.kind == "vehicle.saved"))]
        assert sorted(d["vehicle"] for d in saved) == sorted(wanted)
        # An admin's change survives the next demo start.
        row = db.get(VehicleProfile, sorted(wanted)[0])
        assert row is not None
        row.title = "changed by the admin"
    _seed_demo(database)
    with database.session() as db:
        assert db.get(VehicleProfile, sorted(wanted)[0]).title == "changed by the admin"  # type: ignore[union-attr]
        assert len(list(db.scalars(select(VehicleVersion)))) == len(wanted)
