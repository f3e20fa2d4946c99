"""Every user-controlled string is text, never markup (an attacker's review of every page).

Markup and markdown put into the orders' texts come back from the new routes exactly as typed,
as data for the page to show as text: the printable approval document (JSON for its page, and a
plain-text download that a browser must not sniff or open inline), and the activity log's words.
The campaign sweep's names are a closed set, so markup there is refused with a 422 naming the
field instead of being stored and shown."""

from __future__ import annotations

from typing import Any

from .approval_helpers import MISSION, new_version
from .conftest import World

MARKUP = "<img src=x onerror=alert(1)>"
MARKDOWN = "[x](javascript:alert(1))"
HOSTILE = f"{MARKUP} {MARKDOWN}"


def _hostile_draft(world: World) -> dict[str, Any]:
    operator = world.client("operator")
    mission = operator.get(f"/api/missions/{MISSION}")
    orders = mission.json()["orders"]
    orders["title"] = f"Mission {HOSTILE}"
    orders["goals"][0]["title"] = f"Goal {HOSTILE}"
    orders["constraints"][0]["text"] = f"Constraint {HOSTILE}"
    saved = operator.put(f"/api/missions/{MISSION}/draft", json={"orders": orders},
                         headers={"If-Match": mission.headers["ETag"]})
    assert saved.status_code == 200, saved.text
    return orders


def test_the_document_carries_user_text_verbatim_as_text(world: World) -> None:
    _hostile_draft(world)
    number = new_version(world)
    path = f"/api/missions/{MISSION}/versions/{number}/document"
    document = world.client("auditor").get(path).json()
    plain = next(s["text"] for s in document["sections"]
                 if s["heading"] == "Plain-language orders")
    # Verbatim: neither escaped into entities (the page would show "&lt;") nor stripped.
    for text in (f"Goal {HOSTILE}", f"Constraint {HOSTILE}"):
        assert text in plain and text in document["text"]
    assert "&lt;" not in document["text"]

    download = world.client("auditor").get(path + ".txt")
    assert download.status_code == 200
    assert download.headers["content-type"].startswith("text/plain")
    assert download.headers["x-content-type-options"] == "nosniff"
    assert download.headers["content-disposition"].startswith("attachment")
    assert f"Goal {HOSTILE}" in download.text


def test_the_activity_log_words_keep_user_text_as_text(world: World) -> None:
    browser, csrf = world.browser("supervisor")
    browser.headers["X-CSRF-Token"] = csrf
    made = browser.post("/api/tokens", json={"name": HOSTILE, "scopes": ["read"]})
    assert made.status_code == 201, made.text
    response = world.client("auditor").get("/api/events", params={"kind": "token.created",
                                                                  "order": "newest"})
    assert response.status_code == 200, response.text
    assert response.headers["content-type"].startswith("application/json")
    # The words quote the name as typed (the page puts them in text nodes).
    assert response.json()[0]["change"] == f"token “{HOSTILE}” created (read)"


def test_campaign_sweep_names_refuse_markup(world: World) -> None:
    number = new_version(world)
    client = world.client("operator")
    url = f"/api/missions/{MISSION}/versions/{number}/campaigns"
    for field in ("faults", "goals"):
        for name in (MARKUP, MARKDOWN):
            response = client.post(url, json={"simulations": 1, field: [name]})
            assert response.status_code == 422, (field, name, response.text)
            assert field in response.text, response.text
