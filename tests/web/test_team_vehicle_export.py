"""A team's version exported for one member's vehicle (`?member=VEHICLE`): that member's files
and meetings; a team without a member, an unknown member, or a member of one vehicle's orders
is 422 naming `member`."""

from __future__ import annotations

from .approval_helpers import MISSION, new_version
from .conftest import World
from .test_team_approval import _clean_team

BASE = f"/api/missions/{MISSION}/versions"


def _team_version(world: World) -> int:
    operator = world.client("operator")
    mission = operator.get(f"/api/missions/{MISSION}")
    saved = operator.put(f"/api/missions/{MISSION}/draft", json={"orders": _clean_team()},
                         headers={"If-Match": mission.headers["ETag"]})
    assert saved.status_code == 200, saved.text
    return new_version(world)


def test_a_members_files_and_the_refusals_naming_member(world: World) -> None:
    number = _team_version(world)
    client = world.client("operator")
    listing = client.get(f"{BASE}/{number}/vehicle/moos", params={"member": "vehicle-2"})
    assert listing.status_code == 200, listing.text
    body = listing.json()
    assert body["member"] == "vehicle-2"
    assert [f["name"] for f in body["files"]] == ["search-and-sample-v2.bhv",
                                                  "search-and-sample-v2.moos"]
    assert any(n["code"] == "MEET" for n in body["notes"])
    bhv = client.get(f"{BASE}/{number}/vehicle/moos/search-and-sample-v2.bhv",
                     params={"member": "vehicle-2"})
    assert bhv.status_code == 200 and "MEET_R1_ALL" in bhv.text
    imc = client.get(f"{BASE}/{number}/vehicle/imc", params={"member": "remus-100"})
    assert imc.status_code == 200, imc.text
    for params, named in (({}, "remus-100, vehicle-2"), ({"member": "auv-9"}, "'auv-9'")):
        refused = client.get(f"{BASE}/{number}/vehicle/moos", params=params)
        assert refused.status_code == 422, refused.text
        detail = refused.json()["detail"]
        assert detail.startswith("member: ") and named in detail
    too_long = client.get(f"{BASE}/{number}/vehicle/moos", params={"member": "x" * 201})
    assert too_long.status_code == 422


def test_a_member_of_one_vehicles_orders_is_refused(world: World) -> None:
    number = new_version(world)
    refused = world.client("operator").get(f"{BASE}/{number}/vehicle/imc",
                                           params={"member": "remus-100"})
    assert refused.status_code == 422 and "not a team's" in refused.json()["detail"]
