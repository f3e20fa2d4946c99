"""GET /api/missions/{id}/versions/{n}/vehicle/{format}: listing with notes, downloads, roles,
the approval named in the plan once the version is signed."""

from __future__ import annotations

import json

import pytest

from tests.export.readers import description, read_bhv, read_imc

from .approval_helpers import MISSION, approve, new_version, register_key, submit
from .conftest import World

BASE = f"/api/missions/{MISSION}/versions"


@pytest.mark.parametrize("role", ["operator", "supervisor", "auditor", "admin"])
def test_every_signed_in_reader_lists_and_downloads(world: World, role: str) -> None:
    number = new_version(world)
    client = world.client(role)
    listing = client.get(f"{BASE}/{number}/vehicle/moos")
    assert listing.status_code == 200, listing.text
    body = listing.json()
    assert [f["name"] for f in body["files"]] == [f"{MISSION}.bhv", f"{MISSION}.moos"]
    assert {"code": "NORM", "path": "/norms/0"}.items() <= body["notes"][-1].items()
    bhv = client.get(f"{BASE}/{number}/vehicle/moos/{MISSION}.bhv")
    assert bhv.status_code == 200
    assert "attachment" in bhv.headers["content-disposition"]
    assert read_bhv(bhv.text).start == "G1"


def test_anonymous_is_refused(world: World) -> None:
    number = new_version(world)
    assert world.client().get(f"{BASE}/{number}/vehicle/imc").status_code == 401


def test_unknown_file_and_format_are_problems(world: World) -> None:
    number = new_version(world)
    client = world.client("auditor")
    missing = client.get(f"{BASE}/{number}/vehicle/imc/other.imc")
    assert missing.status_code == 404 and "search-and-sample.imc" in missing.json()["detail"]
    assert client.get(f"{BASE}/{number}/vehicle/kml").status_code == 422
    assert client.get(f"{BASE}/99/vehicle/imc").status_code == 404


def test_imc_names_version_and_approval(world: World) -> None:
    supervisor = world.client("supervisor")
    signer = register_key(supervisor)
    number = new_version(world)
    client = world.client("auditor")
    before = read_imc(client.get(f"{BASE}/{number}/vehicle/imc/{MISSION}.imc").content)[0]
    assert before.plan_id == f"{MISSION}@v{number}" and description(before)["approval"] is None
    approve(world, supervisor, signer, submit(world, number))
    listing = client.get(f"{BASE}/{number}/vehicle/imc").json()
    assert listing["approved"] is True
    plan = read_imc(client.get(f"{BASE}/{number}/vehicle/imc/{MISSION}.imc").content)[0]
    meta = description(plan)
    assert meta["approval"]["decision"] == "approved"
    assert meta["approval"]["envelope_digest"].startswith("sha256:")
    assert meta["orders_digest"] == listing["orders_digest"]
    json.dumps(meta)
