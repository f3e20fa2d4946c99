"""Campaigns of a team's orders through the API: started like a vehicle's, every simulation
runs the team, and the record's results are the joint table (joint ends against the
verifier's counts, meetings, member terminals); the per-person bound and cancel hold."""

from __future__ import annotations

import json
from typing import Any

import pytest

from countersign.orders.examples import example_bytes
from countersign.store import campaigns as store
from countersign.web.routes.campaign_schemas import CampaignRecord, TeamCampaignResults

from .approval_helpers import MISSION, new_version
from .conftest import World
from .described import assert_described
from .test_campaigns import _start, _wait_finished

DRIFT_END = "remus-100:waiting + vehicle-2:ABORT"


def _team_version(world: World) -> int:
    team: dict[str, Any] = json.loads(example_bytes("search-and-sample-team"))
    team["id"] = MISSION
    operator = world.client("operator")
    mission = operator.get(f"/api/missions/{MISSION}")
    saved = operator.put(f"/api/missions/{MISSION}/draft", json={"orders": team},
                         headers={"If-Match": mission.headers["ETag"]})
    assert saved.status_code == 200, saved.text
    return new_version(world)


def test_a_team_campaign_reports_joint_ends_meetings_and_members(world: World) -> None:
    if world.database.engine.dialect.name != "sqlite":
        pytest.skip("the in-process runner runs the jobs on SQLite")
    number = _team_version(world)
    operator = world.client("operator")
    started = _start(operator, number, simulations=2, faults=["vehicle-2:nav_drift"])
    assert started.status_code == 201, started.text
    done = _wait_finished(operator, started.json()["id"])
    assert done["state"] == "finished", done
    results = done["results"]
    assert_described(TeamCampaignResults, results)
    team = results["team"]
    assert team["vehicles"] == ["remus-100", "vehicle-2"]
    rows = {r["end"]: r for r in team["joint"]}
    assert rows[DRIFT_END]["count"] == 2 and rows[DRIFT_END]["executions"] == 8
    assert team["meetings"][0]["deadlocked"]["count"] == 2
    assert team["findings"] == []
    stored = operator.get(f"/api/missions/{MISSION}/campaigns").json()[0]
    assert stored["id"] == done["id"]
    with world.database.session(write=False) as db:
        assert_described(CampaignRecord, store.get(db, done["id"]).record)
    # Fault reach speaks of the member a fault is injected into.
    reach = operator.get(f"/api/missions/{MISSION}/versions/{number}/fault-reach",
                         params={"fault": ["vehicle-2:nav_drift"]}).json()
    assert reach[0]["reacts"] and "vehicle-2:" in reach[0]["because"]


def test_team_campaigns_are_bounded_and_queued_per_person(world: World) -> None:
    class Idle:  # no runner: the campaigns stay queued, as behind busy workers
        def enqueue(self, campaign_id: str, chunks: list[tuple[int, int]]) -> None:
            pass

        def close(self) -> None:
            pass

    world.app.state.campaign_runner = Idle()
    number = _team_version(world)
    operator = world.client("operator")
    for body, word in [({"simulations": 5001}, "team of 2"),
                       ({"faults": ["auv-9:leak"]}, "auv-9"),
                       ({"faults": ["vehicle-2:boom"]}, "boom")]:
        response = _start(operator, number, **body)
        assert response.status_code == 422, (body, response.text)
        assert word in response.text
    ids = [_start(operator, number, simulations=5000).json()["id"]
           for _ in range(store.MAX_ACTIVE_PER_USER)]
    assert _start(operator, number).status_code == 429
    assert world.client("supervisor").post(f"/api/campaigns/{ids[0]}/cancel").status_code == 403
    assert operator.post(f"/api/campaigns/{ids[0]}/cancel").json()["state"] == "cancelled"
    assert _start(operator, number).status_code == 201
