"""The activity log names each event's target and change (whose role, from what
to what), lists newest first, filters by kind, actor, target and time on the server, pages
with a bound, and numbers each event by its entry's index in the transparency log."""

from __future__ import annotations

import json
from datetime import datetime, timedelta

from .approval_helpers import MISSION, bypass_triggers, new_version, submit
from .conftest import PASSWORD, World


def _role_change(world: World, username: str) -> None:
    admin = world.client("admin")
    made = admin.post("/api/users", json={"username": username, "role": "operator",
                                          "password": "another long password 7"})
    assert made.status_code == 201, made.text
    changed = admin.patch(f"/api/users/{made.json()['id']}",
                          json={"role": "supervisor", "admin_password": PASSWORD})
    assert changed.status_code == 200, changed.text


def test_a_role_change_names_whose_role_from_what_to_what_newest_first(world: World) -> None:
    _role_change(world, "frank")
    submit(world, new_version(world))
    log = world.client("auditor").get("/api/events", params={"order": "newest",
                                                             "limit": 1000}).json()
    ids = [e["id"] for e in log]
    assert ids == sorted(ids, reverse=True) and log[0]["kind"] == "submission.created"
    assert log[0]["target"] == f"mission {MISSION} v1"
    role = next(e for e in log if e["kind"] == "user.updated")
    assert role["target"] == "user frank"
    assert role["change"] == "role from operator to supervisor"
    created = next(e for e in log if e["kind"] == "user.created")
    assert created["target"] == "user frank" and created["change"] == "created with role operator"


def test_event_numbers_are_the_log_entries_indexes(world: World) -> None:
    _role_change(world, "grace")
    auditor = world.client("auditor")
    entries = auditor.get("/api/log/entries", params={"limit": 5000}).json()
    index_of = {json.loads(e["entry"])["event"]["id"]: e["index"] for e in entries}
    log = auditor.get("/api/events", params={"order": "newest", "limit": 1000}).json()
    assert log and all(e["index"] == index_of[e["id"]] for e in log)
    # The log starts at 0; event ids start at 1 (the old page showed ids: one off).
    assert min(e["index"] for e in log) == 0


def test_filters_by_kind_actor_target_and_time(world: World) -> None:
    _role_change(world, "heidi")
    submit(world, new_version(world))
    auditor = world.client("auditor")

    def listed(**params: object) -> list[dict[str, object]]:
        response = auditor.get("/api/events", params={"order": "newest", **params})
        assert response.status_code == 200, response.text
        result: list[dict[str, object]] = response.json()
        return result

    family = listed(kind="user")
    assert family and {str(e["kind"]).split(".")[0] for e in family} == {"user"}
    assert {e["kind"] for e in listed(kind="user.updated")} == {"user.updated"}
    admin_name = world.usernames["admin"]
    assert {e["actor"] for e in listed(actor=admin_name)} == {admin_name}
    assert listed(actor="nobody-at-all") == []
    assert {e["target"] for e in listed(target="HEIDI")} == {"user heidi"}
    assert {e["kind"] for e in listed(target=f"{MISSION} v1")} >= {"version.created",
                                                                  "submission.created"}
    # A literal % in the target filter is text, not a wildcard.
    assert listed(target="%") == []

    role = listed(kind="user.updated")[0]
    at = datetime.fromisoformat(str(role["at"]))
    since = listed(since=at.isoformat())
    assert role["id"] in [e["id"] for e in since]
    assert all(datetime.fromisoformat(str(e["at"])) >= at for e in since)
    until = listed(until=at.isoformat())
    assert role["id"] not in [e["id"] for e in until]
    assert listed(since=(at + timedelta(days=1)).isoformat()) == []


def test_pages_newest_first_without_overlap_and_bounded(world: World) -> None:
    for name in ("ivan", "judy"):
        _role_change(world, name)
    auditor = world.client("auditor")
    everything = auditor.get("/api/events", params={"order": "newest", "limit": 1000}).json()
    seen: list[int] = []
    before = None
    for _ in range(len(everything) + 1):  # bounded: a cursor that does not move fails, not hangs
        params: dict[str, object] = {"order": "newest", "limit": 2}
        if before is not None:
            params["before"] = before
        page = auditor.get("/api/events", params=params).json()
        if not page:
            break
        assert len(page) <= 2
        seen += [e["id"] for e in page]
        before = page[-1]["id"]
    assert seen == [e["id"] for e in everything]
    assert auditor.get("/api/events", params={"limit": 1001}).status_code == 422
    assert auditor.get("/api/events", params={"target": "x" * 201}).status_code == 422
    assert auditor.get("/api/events", params={"order": "sideways"}).status_code == 422
    assert auditor.get("/api/events", params={"since": "yesterday"}).status_code == 422
    # The default stays oldest first from `after` (the audit tools read it that way).
    oldest = auditor.get("/api/events", params={"limit": 1000}).json()
    assert [e["id"] for e in oldest] == sorted(e["id"] for e in everything)


def test_a_target_edited_behind_the_apps_back_is_reported(world: World) -> None:
    _role_change(world, "mallory")
    bypass_triggers(world.database, "events",
                    "UPDATE events SET target = 'user someone-else' WHERE kind = 'user.updated'")
    shown = world.client("auditor").get("/api/events", params={"kind": "user.updated"}).json()
    assert shown and all("target" in " ".join(e["integrity"]) for e in shown)


def test_a_wrong_admin_password_says_no_role_changed(world: World) -> None:
    admin = world.client("admin")
    made = admin.post("/api/users", json={"username": "oscar", "role": "operator",
                                          "password": "another long password 7"})
    wrong = admin.patch(f"/api/users/{made.json()['id']}",
                        json={"role": "admin", "admin_password": "not my password"})
    assert wrong.status_code == 403
    assert "no role was changed" in wrong.json()["detail"]
    assert "signed" not in wrong.json()["detail"]


def test_revision_0009_gives_logged_events_their_target_and_keeps_them_append_only(
        database_url: str) -> None:
    from alembic import command
    from sqlalchemy import text

    from countersign.store.db import Database, alembic_config

    database = Database(database_url)
    config = alembic_config(database_url)
    with database.engine.begin() as connection:
        config.attributes["connection"] = connection
        command.upgrade(config, "0008")
    with database.engine.begin() as connection:
        connection.execute(text(
            "INSERT INTO events (at, actor_id, kind, mission_id, detail) VALUES "
            "(:at, NULL, 'user.updated', NULL, :detail)"),
            {"at": datetime(2026, 1, 1).astimezone(),
             "detail": json.dumps({"user": "old", "previous_role": "operator",
                                   "role": "admin"})})
    database.migrate()
    with database.engine.connect() as connection:
        assert connection.execute(text("SELECT target FROM events")).scalar_one() == "user old"
    refused = False
    try:
        with database.engine.begin() as connection:
            connection.execute(text("UPDATE events SET target = 'x'"))
    except Exception as exc:  # the append-only trigger is back
        refused = "append-only" in str(exc)
    assert refused
