from __future__ import annotations

import asyncio
import json
from typing import Any

import pytest

from countersign.orders.examples import example_bytes
from countersign.orders.reader import read_bytes
from countersign.store import missions as missions_store
from countersign.web.routes import missions as missions_routes
from countersign.web.routes.schemas import FindingOut, MissionDetail

from .conftest import World, count_rows
from .described import assert_described
from .write_lock import probe_write_lock

EXAMPLE = "search-and-sample"


def _copy(world: World, new_id: str) -> dict[str, object]:
    orders = world.client("operator").get(f"/api/missions/{EXAMPLE}").json()["orders"]
    orders["id"] = new_id
    return dict(orders)


def test_mission_detail_has_report_summary_and_etag(world: World) -> None:
    response = world.client("auditor").get(f"/api/missions/{EXAMPLE}")
    assert response.status_code == 200
    assert response.headers["etag"] == '"1"'
    body = response.json()
    assert body["ok"] is True and body["errors"] == 0 and body["revision"] == 1
    assert body["draft_digest"].startswith("sha256:")


def test_draft_updates_need_the_current_etag(world: World) -> None:
    client = world.client("operator")
    orders = client.get(f"/api/missions/{EXAMPLE}").json()["orders"]
    orders["title"] = "Edited"
    missing = client.put(f"/api/missions/{EXAMPLE}/draft", json={"orders": orders})
    assert missing.status_code == 428
    first = client.put(f"/api/missions/{EXAMPLE}/draft", json={"orders": orders},
                       headers={"If-Match": '"1"'})
    assert first.status_code == 200 and first.headers["etag"] == '"2"'
    orders["title"] = "Edited again from a stale copy"
    stale = client.put(f"/api/missions/{EXAMPLE}/draft", json={"orders": orders},
                       headers={"If-Match": '"1"'})
    assert stale.status_code == 412
    assert stale.json()["current_revision"] == 2
    assert client.get(f"/api/missions/{EXAMPLE}").json()["title"] == "Edited"


def test_versions_are_immutable_snapshots_and_block_deletion(world: World) -> None:
    client = world.client("operator")
    version = client.post(f"/api/missions/{EXAMPLE}/versions")
    assert version.status_code == 201 and version.json()["number"] == 1
    orders = client.get(f"/api/missions/{EXAMPLE}").json()["orders"]
    orders["title"] = "Changed after version 1"
    client.put(f"/api/missions/{EXAMPLE}/draft", json={"orders": orders},
               headers={"If-Match": '"1"'})
    snapshot = client.get(f"/api/missions/{EXAMPLE}/versions/1").json()
    assert snapshot["orders"]["title"] != "Changed after version 1"
    assert client.delete(f"/api/missions/{EXAMPLE}").status_code == 409
    created = client.post("/api/missions", json=_copy(world, "scratch"))
    assert created.status_code == 201
    assert client.delete("/api/missions/scratch").status_code == 204
    assert client.get("/api/missions/scratch").status_code == 404


def test_list_filters_and_paginates(world: World) -> None:
    client = world.client("operator")
    for i in range(5):
        assert client.post("/api/missions", json=_copy(world, f"m-{i}")).status_code == 201
    page = client.get("/api/missions", params={"q": "m-", "limit": 2}).json()
    assert [m["id"] for m in page["items"]] == ["m-0", "m-1"]
    following = client.get("/api/missions", params={"q": "m-", "limit": 2,
                                                    "cursor": page["next_cursor"]}).json()
    assert [m["id"] for m in following["items"]] == ["m-2", "m-3"]
    assert client.get("/api/missions", params={"status": "approved"}).json()["items"] == []


def test_import_avcl_and_json_and_export(world: World) -> None:
    client = world.client("operator")
    avcl = b"""<?xml version="1.0"?><AVCL><head><meta name="title" content="Tiny.xml"/></head>
      <body><MissionDefinition><AgendaMission><GoalList>
      <Goal id="A" title="Search" nextOnSuccess="B"/><Goal id="B" title="Done"/>
      </GoalList></AgendaMission></MissionDefinition></body></AVCL>"""
    imported = client.post("/api/import", content=avcl,
                           headers={"Content-Type": "application/xml"})
    assert imported.status_code == 201, imported.text
    assert {f["code"] for f in imported.json()["import_findings"]} == {"SINK"}
    _assert_reader_findings(avcl, imported.json()["import_findings"])
    data = json.loads(example_bytes("harbor-approach-survey"))
    assert client.post("/api/import", content=json.dumps(data)).status_code == 201
    plain = client.get(f"/api/missions/{EXAMPLE}/export", params={"format": "plain"})
    assert "Goal 1: Search Area A" in plain.text
    dot = client.get(f"/api/missions/{EXAMPLE}/export", params={"format": "dot"})
    assert dot.text.startswith("digraph")
    assert client.get(f"/api/missions/{EXAMPLE}/export",
                      params={"format": "exe"}).status_code == 422
    turtle = client.get(f"/api/missions/{EXAMPLE}/export", params={"format": "turtle"})
    assert turtle.headers["content-type"].startswith("text/turtle")
    assert "meo:startsWith" in turtle.text or "startsWith" in turtle.text
    avcl = client.get(f"/api/missions/{EXAMPLE}/export", params={"format": "avcl"})
    assert avcl.text.startswith("<?xml") and 'nextOnSuccess="G2"' in avcl.text


def _assert_reader_findings(data: bytes, answered: object) -> None:
    """The answer is what the reader found, which FindingOut describes field for field."""
    found = [f.to_json() for f in read_bytes(data, "the uploaded file").findings]
    assert answered == found
    assert_described(list[FindingOut], found)


def test_paths_pages_stream_and_traces(world: World) -> None:
    client = world.client("supervisor")
    first = client.get(f"/api/missions/{EXAMPLE}/paths", params={"limit": 50}).json()
    assert first["count"] == 75 and len(first["items"]) == 50
    rest = client.get(f"/api/missions/{EXAMPLE}/paths",
                      params={"limit": 50, "cursor": first["next_cursor"]}).json()
    assert len(rest["items"]) == 25 and rest["next_cursor"] is None
    assert rest["items"][-1]["outcomes"] == ["violate", "violate", "violate"]
    streamed = client.get(f"/api/missions/{EXAMPLE}/paths", params={"format": "ndjson"})
    assert len(streamed.text.splitlines()) == 75
    trace = client.get(f"/api/missions/{EXAMPLE}/paths", params={"format": "trace",
                                                                 "limit": 1})
    assert trace.text.startswith("Ethical Mission Execution Trace #1:")


def test_reports_are_cached_by_digest(world: World) -> None:
    client = world.client("operator")
    client.get(f"/api/missions/{EXAMPLE}/report")
    before = count_rows(world.database, "SELECT count(*) FROM validation_reports")
    report = client.get(f"/api/missions/{EXAMPLE}/report").json()
    assert report["paths"]["count"] == 75
    assert count_rows(world.database, "SELECT count(*) FROM validation_reports") == before


def test_event_log_records_every_change(world: World) -> None:
    client = world.client("operator")
    client.post("/api/missions", json=_copy(world, "logged"))
    orders = _copy(world, "logged")
    orders["title"] = "Logged edit"
    client.put("/api/missions/logged/draft", json={"orders": orders}, headers={"If-Match": '"1"'})
    client.post("/api/missions/logged/versions")
    events = world.client("auditor").get("/api/events", params={"mission": "logged"}).json()
    assert [e["kind"] for e in events] == ["mission.created", "draft.updated", "version.created"]
    assert events[1]["before_digest"] == events[0]["after_digest"]
    assert events[1]["after_digest"] != events[1]["before_digest"]
    assert all(e["actor"] == "operator1" for e in events)


def test_read_orders_stores_nothing_and_examples_list(world: World) -> None:
    client = world.client("operator")
    before = client.get("/api/missions").json()["items"]
    avcl = b"""<?xml version="1.0"?><AVCL><head><meta name="title" content="Tiny.xml"/></head>
      <body><MissionDefinition><AgendaMission><GoalList>
      <Goal id="A" title="Search" nextOnSuccess="B"/><Goal id="B" title="Done"/>
      </GoalList></AgendaMission></MissionDefinition></body></AVCL>"""
    read = client.post("/api/read", content=avcl, headers={"Content-Type": "application/xml"})
    assert read.status_code == 200, read.text
    assert read.json()["orders"]["goals"][0]["id"] == "A"
    assert {f["code"] for f in read.json()["findings"]} == {"SINK"}
    _assert_reader_findings(avcl, read.json()["findings"])
    data = json.loads(example_bytes("harbor-approach-survey"))
    read = client.post("/api/read", content=json.dumps(data),
                       headers={"Content-Type": "application/json"})
    assert read.status_code == 200, read.text
    assert read.json()["orders"]["id"] == data["id"]
    assert client.get("/api/missions").json()["items"] == before
    assert client.post("/api/read", content=b"not orders").status_code in (400, 422)
    assert world.client("auditor").post("/api/read", content=avcl).status_code == 403

    examples = client.get("/api/examples").json()
    names = {e["name"] for e in examples}
    assert "search-and-sample" in names
    exemplar = next(e for e in examples if e["name"] == "search-and-sample")
    assert exemplar["goals"] > 0 and exemplar["title"]
    orders = client.get("/api/examples/search-and-sample").json()
    assert orders["id"] == exemplar["id"] and len(orders["goals"]) == exemplar["goals"]
    assert client.get("/api/examples/nope").status_code == 404


def test_orders_are_validated_without_holding_the_write_lock(
        world: World, monkeypatch: pytest.MonkeyPatch) -> None:
    """A validation runs up to 8 s of solver CPU (32 s of wall time): on SQLite, validating
    inside the write transaction made every other user's writes wait for it. Creating,
    importing and editing all validate first, in a read session."""
    writable_meanwhile = probe_write_lock(world, monkeypatch, missions_store, "lookup_report")
    client = world.client("operator")
    orders = _copy(world, "copy")
    assert client.post("/api/missions", json=orders).status_code == 201
    orders["title"] = "Edited"
    edited = client.put("/api/missions/copy/draft", json={"orders": orders},
                        headers={"If-Match": '"1"'})
    assert edited.status_code == 200, edited.text
    imported = client.post("/api/import", content=example_bytes("transect-survey"),
                           headers={"content-type": "application/json"})
    assert imported.status_code == 201, imported.text
    assert len(writable_meanwhile) >= 3 and all(writable_meanwhile), writable_meanwhile


def test_read_orders_answers_off_the_event_loop(world: World,
                                               monkeypatch: pytest.MonkeyPatch) -> None:
    """Orders read back as JSON (up to 8 MiB: 0.4 s to encode 3 MB) were written and encoded
    on the event loop, stalling every other request of the process meanwhile."""
    on_the_loop: list[bool] = []
    real = missions_routes.orders_to_json

    def probe(orders: Any) -> Any:
        try:
            asyncio.get_running_loop()
            on_the_loop.append(True)
        except RuntimeError:
            on_the_loop.append(False)
        return real(orders)

    monkeypatch.setattr(missions_routes, "orders_to_json", probe)
    data = example_bytes("search-and-sample")
    read = world.client("operator").post("/api/read", content=data,
                                         headers={"Content-Type": "application/json"})
    assert read.status_code == 200, read.text
    assert on_the_loop == [False]
    assert read.json() == {"orders": real(read_bytes(data, "x").orders), "findings": []}


def test_an_import_answers_encoded_in_the_worker_thread(world: World,
                                                      monkeypatch: pytest.MonkeyPatch) -> None:
    """The import's answer carries the whole orders: returned as a model from the worker
    thread, FastAPI validated and encoded it on the event loop (an async route), stalling every
    other request of the process meanwhile."""
    answers: list[object] = []
    real = missions_routes._import

    def probe(*args: Any) -> Any:
        answers.append(real(*args))
        return answers[-1]

    monkeypatch.setattr(missions_routes, "_import", probe)
    imported = world.client("operator").post(
        "/api/import", content=example_bytes("transect-survey"),
        headers={"content-type": "application/json"})
    assert imported.status_code == 201, imported.text
    assert imported.headers["etag"] == '"1"'
    assert [type(a).__name__ for a in answers] == ["JSONResponse"]
    body = imported.json()
    assert body["id"] == "transect-survey" and body["orders"]["id"] == "transect-survey"
    assert_described(MissionDetail, body)
