"""A team's orders rehearse through the app, every vehicle in one scene (real
manager, real viser server); its status and record are described by the OpenAPI models;
sources other than the simulation, unknown vehicles and bad faults are refused in words."""

from __future__ import annotations

import json
import time
from collections.abc import Iterator
from typing import Any

import pytest
from fastapi.testclient import TestClient

from countersign.orders.examples import example_bytes
from countersign.store.rehearsals import get_record
from countersign.web.routes.rehearsal_schemas import RehearsalRecordOut, RehearsalStatus

from .conftest import World
from .described import assert_described

MISSION = "search-and-sample"


@pytest.fixture
def team_world(world: World) -> Iterator[World]:
    """The world with the exemplar's mission draft replaced by the two-vehicle team."""
    with TestClient(world.app):
        operator = world.client("operator")
        mission = operator.get(f"/api/missions/{MISSION}")
        team: dict[str, Any] = json.loads(example_bytes("search-and-sample-team"))
        team["id"] = MISSION
        saved = operator.put(f"/api/missions/{MISSION}/draft", json={"orders": team},
                             headers={"If-Match": mission.headers["ETag"]})
        assert saved.status_code == 200, saved.text
        yield world


def _wait_finished(client: TestClient, rid: str) -> dict[str, Any]:
    # Generous: it bounds a hang on a shared machine and times nothing.
    deadline = time.monotonic() + 300
    while True:
        status: dict[str, Any] = client.get(f"/api/rehearsals/{rid}").json()["status"]
        if status["state"] == "finished":
            return status
        assert time.monotonic() < deadline, status
        time.sleep(0.1)


def test_a_team_rehearses_every_vehicle_and_records_the_joint_run(team_world: World) -> None:
    operator = team_world.client("operator")
    started = operator.post(f"/api/missions/{MISSION}/rehearsals",
                            json={"source": "simulate", "speed": 100_000,
                                  "faults": ["vehicle-2:gps_loss"]})
    assert started.status_code == 201, started.text
    rid = started.json()["id"]
    first = started.json()["status"]
    assert_described(RehearsalStatus, first)
    assert [m["vehicle"] for m in first["team"]["members"]] == ["remus-100", "vehicle-2"]
    # A fault for one vehicle by name; an unknown vehicle is refused naming it.
    fault = operator.post(f"/api/rehearsals/{rid}/faults", json={"fault": "remus-100:leak"})
    if fault.status_code == 200:
        assert "remus-100: Fault injected: leak." in fault.json()["status"]["fault_notice"]["text"]
    else:  # remus-100 may already have ended at this speed
        assert fault.status_code == 409, fault.text
    unknown = operator.post(f"/api/rehearsals/{rid}/faults", json={"fault": "vehicle-9:leak"})
    assert unknown.status_code == 422 and "vehicle-9" in unknown.json()["detail"]
    chosen = operator.post(f"/api/rehearsals/{rid}/outcome", json={"outcome": "succeed"})
    assert chosen.status_code == 409 and "no outcome to choose" in chosen.json()["detail"]

    status = _wait_finished(operator, rid)
    assert_described(RehearsalStatus, status)
    assert status["team"]["joint_end"]
    assert all(e["vehicle"] in ("remus-100", "vehicle-2") for e in status["events"])

    stopped = operator.post(f"/api/rehearsals/{rid}/stop")
    assert stopped.status_code == 200, stopped.text
    digest = stopped.json()["digest"]
    record = team_world.client("auditor").get(f"/api/rehearsal-records/{digest}").json()
    with team_world.database.session() as db:
        stored = get_record(db, digest).record
    assert record["record"] == stored
    assert_described(RehearsalRecordOut, stored)
    assert stored["team"]["vehicles"] == ["remus-100", "vehicle-2"]
    assert any(f.startswith("vehicle-2:gps_loss@") for f in stored["inputs"]["faults"])
    assert all(e["vehicle"] in ("remus-100", "vehicle-2") for e in stored["events"])


def test_team_sources_and_faults_are_refused_in_words(team_world: World) -> None:
    operator = team_world.client("operator")
    for body, words in (({"source": "manual"}, "simulate or replay"),
                        ({"source": "tour"}, "simulate or replay"),
                        ({"source": "simulate", "faults": ["vehicle-9:leak"]}, "vehicle-9"),
                        ({"source": "simulate", "faults": ["remus-100:melt"]}, "melt")):
        answer = operator.post(f"/api/missions/{MISSION}/rehearsals", json=body)
        assert answer.status_code == 422, (body, answer.text)
        assert words in json.dumps(answer.json()), (body, answer.text)
    # Markup in a fault's vehicle is not even a name the API reads.
    bad = operator.post(f"/api/missions/{MISSION}/rehearsals",
                        json={"source": "simulate", "faults": ["<b>x</b>:leak"]})
    assert bad.status_code == 422
    # Roles are the server's: auditors and admins do not rehearse a team either.
    for role in ("auditor", "admin"):
        refused = team_world.client(role).post(f"/api/missions/{MISSION}/rehearsals",
                                                json={"source": "simulate"})
        assert refused.status_code == 403


def test_a_member_replays_one_path_of_its_own_orders(team_world: World) -> None:
    operator = team_world.client("operator")
    started = operator.post(f"/api/missions/{MISSION}/rehearsals",
                            json={"source": "simulate", "speed": 100_000,
                                  "member_paths": {"vehicle-2": 19}})
    assert started.status_code == 201, started.text
    rid = started.json()["id"]
    status = _wait_finished(operator, rid)
    # Path 19 of vehicle 2's orders aborts before Area C: vehicle 1 is left waiting.
    assert status["team"]["joint_end"] == "remus-100:waiting + vehicle-2:ABORT"
    digest = operator.post(f"/api/rehearsals/{rid}/stop").json()["digest"]
    with team_world.database.session() as db:
        stored = get_record(db, digest).record
    assert stored["team"]["paths"] == {"vehicle-2": 19}
    member = next(m for m in stored["team"]["members"] if m["vehicle"] == "vehicle-2")
    assert member["runs"][0]["path_index"] == 19 and member["terminal"] == "ABORT"


def test_member_paths_are_bounded_and_refused_naming_the_member(team_world: World) -> None:
    operator = team_world.client("operator")
    for paths, words in (({"vehicle-9": 1}, "vehicle-9"),
                         ({"vehicle-2": 100_000}, "member vehicle-2: path index must be "
                          "between 1 and"),
                         ({"vehicle-2": 0}, "member_paths"),
                         ({"<b>x</b>": 1}, "member_paths"),
                         ({f"v{i}": 1 for i in range(9)}, "member_paths")):
        answer = operator.post(f"/api/missions/{MISSION}/rehearsals",
                               json={"source": "simulate", "member_paths": paths})
        assert answer.status_code == 422, (paths, answer.text)
        assert words in json.dumps(answer.json()), (paths, answer.text)
    # One vehicle's orders take path_index, not member paths.
    solo = team_world.client("operator")
    mission = solo.get("/api/missions/search-and-sample")
    single = json.loads(example_bytes("search-and-sample"))
    assert solo.put(f"/api/missions/{MISSION}/draft", json={"orders": single},
                    headers={"If-Match": mission.headers["ETag"]}).status_code == 200
    answer = solo.post(f"/api/missions/{MISSION}/rehearsals",
                       json={"source": "simulate", "member_paths": {"vehicle-2": 1}})
    assert answer.status_code == 422 and "member paths are for a team's orders" in answer.text
