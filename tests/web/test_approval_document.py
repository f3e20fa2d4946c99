"""The printable approval document of a version. Its plain-orders section is
what `countersign export --format plain` writes; it carries the digest, findings, path counts
by terminal, the rehearsal summary, the decision, the signer and the key fingerprint; changing
only a condition changes it."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path
from typing import Any

from countersign.approvals.document import key_fingerprint
from countersign.orders.examples import example_bytes

from .approval_helpers import MISSION, approve, new_version, register_key, submit
from .conftest import World


def _document(world: World, mission: str, number: int) -> dict[str, Any]:
    response = world.client("auditor").get(f"/api/missions/{mission}/versions/{number}/document")
    assert response.status_code == 200, response.text
    data: dict[str, Any] = response.json()
    return data


def _section(document: dict[str, Any], heading: str) -> str:
    return next(str(s["text"]) for s in document["sections"] if s["heading"] == heading)


def _cli_plain(orders: dict[str, Any], tmp_path: Path) -> str:
    source = tmp_path / "orders.json"
    source.write_text(json.dumps(orders))
    cli = Path(sys.executable).with_name("countersign")
    done = subprocess.run([str(cli), "export", str(source), "--format", "plain"],
                          capture_output=True, text=True, check=True)
    return done.stdout


def test_the_document_of_an_approved_version(world: World, tmp_path: Path) -> None:
    number = new_version(world)
    supervisor = world.client("supervisor")
    signer = register_key(supervisor, name="desk key")
    undecided = _document(world, MISSION, number)
    assert "Not decided yet" in _section(undecided, "Decision")
    approval = approve(world, supervisor, signer, submit(world, number), reason="clear sea")

    document = _document(world, MISSION, number)
    headings = [s["heading"] for s in document["sections"]]
    assert headings == ["Version", "Plain-language orders", "Findings", "Paths by terminal",
                        "Rehearsal", "Decision", "Signer"]
    version = world.client("auditor").get(f"/api/missions/{MISSION}/versions/{number}").json()
    assert document["digest"] == version["digest"] and version["digest"] in document["text"]
    # The very text the CLI writes for the same orders.
    assert _section(document, "Plain-language orders") == _cli_plain(version["orders"],
                                                                     tmp_path)
    assert "checked as:" in _section(document, "Plain-language orders").lower()
    review = world.client("auditor").get(f"/api/missions/{MISSION}/versions/{number}/review")
    paths = review.json()["paths"]
    counted = _section(document, "Paths by terminal")
    assert f"{paths['count']} path(s)" in counted
    for terminal, count in paths["by_terminal"].items():
        assert f"- {terminal} (" in counted and f"): {count}" in counted
    assert "None: no rehearsal record" in _section(document, "Rehearsal")
    decided = _section(document, "Decision")
    assert f"Approved (approval {approval['id']})" in decided and "clear sea" in decided
    signed = _section(document, "Signer")
    assert world.usernames["supervisor"] in signed and "“desk key”" in signed
    assert key_fingerprint(signer.key_id) in signed
    assert key_fingerprint(signer.key_id).startswith(signer.key_id[:4] + " ")

    text = world.client("operator").get(
        f"/api/missions/{MISSION}/versions/{number}/document.txt")
    assert text.status_code == 200 and text.headers["content-type"].startswith("text/plain")
    assert text.text == document["text"]
    assert world.client("auditor").get(
        f"/api/missions/{MISSION}/versions/99/document").status_code == 404


def test_changing_only_a_condition_changes_the_document(world: World) -> None:
    data = json.loads(example_bytes("search-and-sample"))
    operator = world.client("operator")
    texts = {}
    for mission, expr in (("doc-depth-20", "depth_m >= 20"), ("doc-depth-half",
                                                             "depth_m >= 0.5")):
        data["id"] = mission
        data["constraints"][6]["expr"] = expr  # the text stays "... 20 meters ..."
        assert operator.post("/api/missions", json=data).status_code == 201
        number = operator.post(f"/api/missions/{mission}/versions").json()["number"]
        texts[expr] = _document(world, mission, number)
    twenty, half = texts["depth_m >= 20"], texts["depth_m >= 0.5"]
    assert "(`depth_m >= 20`)" in _section(twenty, "Plain-language orders")
    assert "(`depth_m >= 0.5`)" in _section(half, "Plain-language orders")
    assert "(`depth_m >= 0.5`)" not in twenty["text"]
    assert twenty["digest"] != half["digest"]
    # The changed condition no longer matches its text: a TEXT finding in the document.
    assert "TEXT" in _section(half, "Findings") and "TEXT" not in _section(twenty, "Findings")
