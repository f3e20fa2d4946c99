"""Separation of duties by person, checked from the log by every verifier.

An operator edits a draft, is promoted to supervisor and approves the version it led to. The
app refuses that (tests/web/test_decision_guards.py); here the guard is switched off, as a
server that forgot it (or a writer behind its back) would, and `countersign audit verify` and
the offline verifier's log-wide rule must name the decision, the person and the edit. The
vectors in frontend/src/crypto/__fixtures__/duties.json are shared with the browser's copy
(src/crypto/dutyRules.test.ts)."""

from __future__ import annotations

import json
from pathlib import Path
from typing import Any

import pytest

from countersign import cli
from countersign.approvals.bundle import verify_bundle
from countersign.approvals.duty_rules import check_duties
from countersign.approvals.log_rules import check_log
from countersign.approvals.role_rules import check_roles
from countersign.store.accounts import create_token, create_user
from countersign.store.approvals import decisions

from .approval_helpers import MISSION, approve, new_version, register_key, submit
from .conftest import PASSWORD, World

VECTORS = (Path(__file__).parents[2] / "frontend" / "src" / "crypto" / "__fixtures__"
           / "duties.json")
CASES: list[dict[str, Any]] = json.loads(VECTORS.read_text())["cases"]


@pytest.mark.parametrize("case", CASES, ids=[c["name"] for c in CASES])
def test_shared_duty_vectors(case: dict[str, Any]) -> None:
    assert check_duties(case["events"]) == case["problems"]


def test_check_log_carries_the_duty_rule() -> None:
    # The vector's log creates no accounts, so the roles rule (role_rules.py) names its own.
    assert check_log(CASES[0]["events"]) == CASES[0]["problems"] + check_roles(
        CASES[0]["events"])


def test_an_editor_promoted_to_supervisor_who_approves_is_named(
        world: World, monkeypatch: pytest.MonkeyPatch, tmp_path: Path,
        capsys: pytest.CaptureFixture[str]) -> None:
    with world.database.session() as db:
        eve = create_user(db, username="eve", role="operator", password=PASSWORD,
                          signer=world.database.log_signer)
        eve_id, token = eve.id, create_token(db, user=eve, name="tests",
                                             signer=world.database.log_signer)[1]
    editor = world.client()
    editor.headers["Authorization"] = f"Bearer {token}"
    mission = editor.get(f"/api/missions/{MISSION}")
    orders = mission.json()["orders"]
    orders["goals"][0]["title"] = "Search Area E"
    edited = editor.put(f"/api/missions/{MISSION}/draft", json={"orders": orders},
                        headers={"If-Match": mission.headers["ETag"]})
    assert edited.status_code == 200, edited.text
    submission = submit(world, new_version(world))  # operator1 cuts and submits it
    promoted = world.client("admin").patch(f"/api/users/{eve_id}", json={
        "role": "supervisor", "admin_password": PASSWORD})
    assert promoted.status_code == 200, promoted.text
    signer = register_key(editor)
    # The app refuses eve (test_decision_guards.py); without the guard it would not.
    monkeypatch.setattr(decisions, "_check_duties", lambda *a, **k: None)
    approval = approve(world, editor, signer, submission)

    bundle = world.client("auditor").get("/api/audit/bundle").json()
    report = verify_bundle(bundle, trusted_log_key=bundle["log_key"]["public_key"])
    index = approval["log_index"]
    edit = next(i for i, e in enumerate(_events(bundle))
                if e["kind"] == "draft.updated" and e["actor"] == "eve")
    named = (f"log entry {index} (approval.approved) by eve decides submission {submission} "
             f"of {MISSION} version {approval['version']}, but eve edited it in log entry "
             f"{edit} (draft.updated): separation of duties")
    assert named in report.problems, report.problems
    assert named in check_log(_events(bundle))

    path = tmp_path / "bundle.json"
    path.write_text(json.dumps(bundle))
    assert cli.main(["audit", "verify", str(path), "--log-key",
                     bundle["log_key"]["public_key"], "--format", "json"]) == 1
    assert named in json.loads(capsys.readouterr().out)["problems"]


def _events(bundle: dict[str, Any]) -> list[dict[str, Any]]:
    return [json.loads(text)["event"] for text in bundle["entries"]]
