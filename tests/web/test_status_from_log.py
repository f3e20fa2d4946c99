"""A mission's status, and a submission's state, are read from the log.

A database writer sets `submissions.state` (and `missions.status`) to 'approved' for a version
that is only submitted: the mission list, the mission page and the submission show the log's
'submitted' and name the forged rows in `integrity`, instead of showing them as approved."""

from __future__ import annotations

from sqlalchemy import text

from .approval_helpers import MISSION, approve, new_version, register_key, submit
from .conftest import World


def _forge_approved(world: World, submission: int) -> None:
    with world.database.engine.begin() as connection:
        connection.execute(text("UPDATE submissions SET state = 'approved' WHERE id = :s"),
                           {"s": submission})
        connection.execute(text("UPDATE missions SET status = 'approved' WHERE id = :m"),
                           {"m": MISSION})


def test_a_forged_approval_in_the_tables_is_named_not_shown(world: World) -> None:
    submission = submit(world, new_version(world))
    _forge_approved(world, submission)
    client = world.client("auditor")
    named = f"mission {MISSION}: the table says approved, the log says submitted"
    listed = next(m for m in client.get("/api/missions").json()["items"] if m["id"] == MISSION)
    assert (listed["status"], listed["integrity"]) == ("submitted", [named])
    page = client.get(f"/api/missions/{MISSION}").json()
    assert (page["status"], page["integrity"]) == ("submitted", [named])
    row = client.get(f"/api/submissions/{submission}").json()
    assert row["state"] == "submitted"
    assert row["integrity"] == [f"submission {submission}: the table says approved, the log "
                                "says submitted"]


def test_statuses_the_app_wrote_agree_with_the_log(world: World) -> None:
    client = world.client("auditor")
    assert client.get(f"/api/missions/{MISSION}").json()["status"] == "draft"
    supervisor = world.client("supervisor")
    submission = submit(world, new_version(world))
    assert client.get(f"/api/missions/{MISSION}").json()["status"] == "submitted"
    approve(world, supervisor, register_key(supervisor), submission)
    page = client.get(f"/api/missions/{MISSION}").json()
    assert (page["status"], page["integrity"]) == ("approved", [])
    assert client.get("/api/missions?status=approved").json()["items"][0]["integrity"] == []
