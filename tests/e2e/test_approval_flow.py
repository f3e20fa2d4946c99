"""In the browser: an operator submits the exemplar, a supervisor creates a key in the
browser (WebCrypto, non-extractable, IndexedDB), registers it with a password confirmation and
signs the approval in the browser, and an auditor verifies the record in the browser and exports
a bundle that the offline verifier (`countersign audit verify`, a subprocess) accepts. Then one
byte of the stored envelope is changed directly in the database (bypassing the append-only
trigger) and both the audit page and the offline verifier name the failing log entry; changed
key, version orders and log entry are then named on the audit page as well. The auditor pins
the log key on first use; a different pinned key fails the pin check, naming both keys."""

from __future__ import annotations

import json
import re
import sqlite3
import subprocess
from collections.abc import Iterator
from pathlib import Path
from typing import Any

import pytest
from playwright.sync_api import Browser, BrowserContext, Page, expect

from countersign.approvals import dsse

from .conftest import PATIENCE_MS, Server, _cli, _server_env, make_user
from .screens import tables_fit_each_screen
from .test_roles import sign_in

MISSION = "e2e-approval"


@pytest.fixture()
def contexts(browser: Browser, server: Server) -> Iterator[list[BrowserContext]]:
    """Separate browser contexts (cookies, IndexedDB) for the other roles of the test."""
    opened: list[BrowserContext] = []
    yield opened
    for context in opened:
        context.close()


def new_page(browser: Browser, server: Server, opened: list[BrowserContext],
             errors: list[str]) -> Page:
    context = browser.new_context(base_url=server.url, viewport={"width": 1280, "height": 900},
                                  accept_downloads=True)
    context.set_default_timeout(PATIENCE_MS)
    opened.append(context)
    page = context.new_page()
    page.on("pageerror", lambda error: errors.append(f"page error: {error}"))
    return page


def audit_verify(server: Server, bundle: Path) -> subprocess.CompletedProcess[str]:
    return subprocess.run(_cli("audit", "verify", str(bundle)), capture_output=True, text=True,
                          env=_server_env(server.data_dir), timeout=120)


def export_bundle(page: Page, target: Path) -> Path:
    with page.expect_download() as download:
        page.get_by_role("link", name="Export bundle").click()
    download.value.save_as(str(target))
    bundle = json.loads(target.read_text())
    assert bundle["format"] == "countersign.audit-bundle/1"
    return target


def bypass(server: Server, table: str, sql: str, *params: Any) -> None:
    """Runs one UPDATE directly on the server's SQLite database, dropping the table's
    append-only trigger (if any) for it and putting it back, as an attacker would."""
    connection = sqlite3.connect(server.data_dir / "countersign.db", timeout=30)
    try:
        found = connection.execute(
            "SELECT sql FROM sqlite_master WHERE type = 'trigger' AND name = ?",
            (f"{table}_no_update",)).fetchone()
        with connection:
            if found:
                connection.execute(f"DROP TRIGGER {table}_no_update")
            assert connection.execute(sql, params).rowcount == 1
            if found:
                connection.execute(found[0])
    finally:
        connection.close()


def delete_row(server: Server, table: str, sql: str, *params: Any) -> None:
    """Runs one DELETE directly on the server's SQLite database past the table's no-delete
    trigger, as an attacker would."""
    connection = sqlite3.connect(server.data_dir / "countersign.db", timeout=30)
    try:
        found = connection.execute(
            "SELECT sql FROM sqlite_master WHERE type = 'trigger' AND name = ?",
            (f"{table}_no_delete",)).fetchone()
        with connection:
            if found:
                connection.execute(f"DROP TRIGGER {table}_no_delete")
            assert connection.execute(sql, params).rowcount == 1
            if found:
                connection.execute(found[0])
    finally:
        connection.close()


def stored(server: Server, sql: str, *params: Any) -> Any:
    connection = sqlite3.connect(server.data_dir / "countersign.db", timeout=30)
    try:
        return connection.execute(sql, params).fetchone()[0]
    finally:
        connection.close()


def tamper_envelope(server: Server, approval: int) -> None:
    """Changes one byte of the stored envelope: its signature's first character."""
    text = stored(server, "SELECT envelope FROM approvals WHERE id = ?", approval)
    marker = '"sig":"' if '"sig":"' in text else '"sig": "'
    at = text.index(marker) + len(marker)
    changed = text[:at] + ("B" if text[at] == "A" else "A") + text[at + 1:]
    assert len(changed) == len(text) and changed != text
    bypass(server, "approvals", "UPDATE approvals SET envelope = ? WHERE id = ?", changed,
           approval)


def test_submit_sign_verify_export_and_detect_tampering(
    page: Page, browser: Browser, server: Server, contexts: list[BrowserContext],
    tmp_path: Path, tmp_path_factory: pytest.TempPathFactory,
) -> None:
    from countersign.orders.examples import example_bytes

    errors: list[str] = []
    upload = tmp_path / f"{MISSION}.json"
    upload.write_bytes(example_bytes("search-and-sample").replace(
        b'"id": "search-and-sample"', f'"id": "{MISSION}"'.encode()))

    # The operator imports the exemplar, creates version 1 and submits it.
    operator = page
    sign_in(operator, "operator")
    operator.get_by_role("link", name="Import or create mission").click()
    operator.get_by_label("Orders file (.json, .xml, .ttl)").set_input_files(str(upload))
    operator.get_by_role("button", name="Import file").click()
    expect(operator).to_have_url(re.compile(rf"/missions/{MISSION}\?tab=findings$"))
    operator.get_by_role("tab", name=re.compile("^Versions")).click()
    operator.get_by_role("button", name="Create version").click()
    expect(operator.get_by_role("status").filter(has_text="Version 1 created.")).to_be_visible()
    operator.get_by_role("button", name="Submit version 1").click()
    expect(operator.get_by_role("status").filter(has_text="Version 1 submitted for review.")
           ).to_be_visible()
    expect(operator.get_by_test_id("submission-state")).to_have_text("Submitted")
    expect(operator.get_by_role("button", name="Submit version 1")).to_be_disabled()
    expect(operator.get_by_test_id("submit-refusal")).to_contain_text("is submitted already")

    # A supervisor of this test's own (other tests register keys for the shared one) creates a
    # key in the browser and registers it (password confirmation).
    reviewer, reviewer_password = make_user(server, "supervisor")
    supervisor = new_page(browser, server, contexts, errors)
    sign_in(supervisor, "supervisor", reviewer_password, username=reviewer)
    supervisor.get_by_role("link", name="Keys", exact=True).click()
    expect(supervisor.get_by_role("heading", name="Signing keys", level=1)).to_be_visible()
    supervisor.get_by_label("Key name").fill("e2e browser")
    supervisor.get_by_label("Confirm your password").fill("wrong password")
    supervisor.get_by_role("button", name="Create and register key").click()
    expect(supervisor.get_by_role("alert")).to_contain_text("password confirmation is wrong")
    supervisor.get_by_label("Confirm your password").fill(reviewer_password)
    # The wrong try above is answered after the throttle's back-off and a hash in the
    # low-priority hashing process: on a loaded machine the button is busy for a while.
    supervisor.get_by_role("button", name="Create and register key").click(timeout=90_000)
    expect(supervisor.get_by_role("status").filter(has_text="registered")).to_be_visible()
    expect(supervisor.get_by_test_id("key-fingerprint")).to_have_count(1)
    expect(supervisor.get_by_role("cell", name="yes (can sign here)")).to_be_visible()
    extractable = supervisor.evaluate("""() => new Promise((resolve, reject) => {
        const open = indexedDB.open("countersign-keys");
        open.onsuccess = () => {
            const all = open.result.transaction("keys").objectStore("keys").getAll();
            all.onsuccess = () => resolve(all.result.map((k) => k.keyPair.privateKey.extractable));
            all.onerror = () => reject(all.error);
        };
        open.onerror = () => reject(open.error);
    })""")
    assert extractable == [False]

    # The review: state, no earlier approval, graph, plain orders, findings, paths; then sign.
    supervisor.get_by_role("link", name="Reviews", exact=True).click()
    supervisor.get_by_role("link", name=f"Review {MISSION} v1").click()
    expect(supervisor.get_by_role("heading", name=re.compile("^Review: .* v1$"))).to_be_visible()
    expect(supervisor.get_by_test_id("submission-state")).to_have_text("Submitted")
    expect(supervisor.get_by_test_id("diff-summary")).to_contain_text(
        "No earlier version of this mission was approved")
    expect(supervisor.get_by_test_id("orders-graph")).to_be_visible()
    expect(supervisor.get_by_test_id("review-plain")).to_contain_text("Search Area A")
    expect(supervisor.get_by_test_id("contingency-rules")).to_contain_text(
        "carry no contingency rules")
    expect(supervisor.get_by_test_id("review-verdict")).to_have_text(
        "The orders pass every check.")
    expect(supervisor.get_by_test_id("review-paths-to-COMPLETE")).to_have_text("25")
    expect(supervisor.get_by_test_id("review-paths-to-ABORT")).to_have_text("50")
    expect(supervisor.get_by_test_id("review-paths-status")).to_contain_text("All 75 paths")
    expect(supervisor.get_by_test_id("review-paths").get_by_role("listitem").first
           ).to_have_attribute("aria-label", re.compile(r"^Path 1: G1 "))
    # Without the password, a click signs nothing and nothing is sent.
    supervisor.get_by_role("button", name="Sign approval").click()
    expect(supervisor.get_by_role("alert")).to_contain_text("Enter your password")
    supervisor.get_by_label("Your password").fill(reviewer_password)
    supervisor.get_by_role("button", name="Sign approval").click()
    verdict = supervisor.get_by_test_id("decision-verdict")
    expect(verdict).to_contain_text("The server verified your signature and recorded the "
                                    "approval")
    expect(supervisor.get_by_test_id("submission-state")).to_have_text("Approved")
    expect(supervisor.get_by_role("button", name="Sign approval")).to_be_disabled()
    expect(supervisor.get_by_test_id("decision-refusal")).to_contain_text("is approved")
    # In the order things happened: the decision, then what follows from it.
    done, refused = (supervisor.get_by_test_id(t).bounding_box()
                     for t in ("decision-verdict", "decision-refusal"))
    assert done and refused and done["y"] + done["height"] <= refused["y"], (done, refused)

    # The operator changes a goal and submits version 2; the supervisor sees the diff.
    operator.get_by_role("tab", name="Edit orders").click()
    orders = json.loads(operator.get_by_label("Orders JSON").input_value())
    old_title = orders["goals"][0]["title"]
    orders["goals"][0]["title"] = f"{old_title}, north half"
    operator.get_by_label("Orders JSON").fill(json.dumps(orders, indent=2))
    operator.get_by_role("button", name="Save draft").click()
    expect(operator.get_by_role("status").filter(has_text="Draft saved.")).to_be_visible()
    operator.get_by_role("tab", name=re.compile("^Versions")).click()
    operator.get_by_role("button", name="Create version").click()
    expect(operator.get_by_role("status").filter(has_text="Version 2 created.")).to_be_visible()
    operator.get_by_role("button", name="Submit version 2").click()
    expect(operator.get_by_test_id("submission-state")).to_have_text("Submitted")
    supervisor.goto(f"/missions/{MISSION}/versions/2/review")
    expect(supervisor.get_by_test_id("diff-summary")).to_contain_text(
        "Compared with v1 (approval")
    expect(supervisor.get_by_test_id("diff-summary")).to_contain_text("1 difference.")
    diff = supervisor.get_by_test_id("orders-diff")
    expect(diff).to_contain_text(f"{orders['goals'][0]['id']}")
    expect(diff).to_contain_text(f"title: {old_title} → {old_title}, north half")
    tables_fit_each_screen(supervisor, tmp_path_factory, "review-diff",
                           [(diff, supervisor.locator("main"))])
    operator.get_by_role("button", name="Withdraw submission").click()
    expect(operator.get_by_test_id("submission-state")).to_have_text("Withdrawn")
    expect(operator.get_by_role("button", name="Submit version 2")).to_be_enabled()

    # The supervisor rotates the key (the old one is revoked) and revokes the approval with a
    # signed reason, using the new key.
    supervisor.get_by_role("link", name="Keys", exact=True).click()
    supervisor.get_by_label("Key name").fill("e2e rotated")
    supervisor.get_by_label("Confirm your password").fill(reviewer_password)
    supervisor.get_by_role("button", name="Rotate key").click()
    expect(supervisor.get_by_role("status").filter(has_text="Revoked")).to_be_visible()
    expect(supervisor.get_by_test_id("key-fingerprint")).to_have_count(2)
    expect(supervisor.get_by_role("cell", name="yes (can sign here)")).to_have_count(1)
    supervisor.get_by_role("link", name="Audit", exact=True).click()
    supervisor.get_by_label("Mission", exact=True).fill(MISSION)
    supervisor.get_by_role("button", name="Apply filters").click()
    # Other tests' records are listed until the filtered page arrives.
    approved = supervisor.get_by_role("link", name=re.compile(r"^Record \d+$"))
    expect(approved).to_have_count(1)
    approved.click()
    supervisor.get_by_label("Reason (signed)").fill("Area A is closed to sampling this week")
    supervisor.get_by_label("Your password").fill(reviewer_password)
    supervisor.get_by_role("button", name="Sign revocation").click()
    expect(supervisor.get_by_role("status").filter(has_text="Revocation recorded as record")
           ).to_be_visible()

    # The auditor finds the approval, sees every check pass in the browser (its key was revoked
    # only after it signed), and exports a bundle.
    auditor = new_page(browser, server, contexts, errors)
    sign_in(auditor, "auditor")
    auditor.get_by_role("link", name="Audit", exact=True).click()
    auditor.get_by_label("Mission", exact=True).fill(MISSION)
    auditor.get_by_label("Decision", exact=True).select_option("approved")
    auditor.get_by_role("button", name="Apply filters").click()
    records = auditor.get_by_role("link", name=re.compile(r"^Record \d+$"))
    expect(records).to_have_count(1)
    records.click()
    expect(auditor.get_by_role("heading", name=re.compile(rf"^Record \d+: {MISSION} v1$"))
           ).to_be_visible()
    verification = auditor.get_by_test_id("verification-verdict")
    expect(verification).to_have_text(re.compile(
        r"^All 13 checks passed, against a log key not pinned"))
    # Trust on first use: the auditor pins the log key the server presents, explicitly.
    checkpoint: dict[str, Any] = auditor.evaluate(
        "async () => (await fetch('/api/log/checkpoint')).json()")
    server_print = fingerprint(checkpoint["key_id"])
    expect(auditor.get_by_test_id("log-key-presented")).to_contain_text(checkpoint["key_id"])
    auditor.get_by_role("button", name="Pin this key…").click()
    auditor.get_by_role("button", name="Confirm: pin this key").click()
    expect(verification).to_have_text("All 14 checks passed.")
    expect(auditor.get_by_test_id("check-pin")).to_contain_text(
        f"signed by log key {server_print}, the key pinned in this browser")
    expect(auditor.get_by_test_id("approval-plain")).to_contain_text("Search Area A")
    expect(auditor.get_by_test_id("rehearsal")).to_have_text("None.")
    expect(auditor.get_by_test_id("check-key")).to_contain_text("not revoked before it")
    bundle = export_bundle(auditor, tmp_path / "bundle.json")
    checked = audit_verify(server, bundle)
    assert checked.returncode == 0, checked.stdout + checked.stderr
    record: dict[str, Any] = auditor.evaluate(
        f"""async () => (await (await fetch("/api/approvals?mission={MISSION}&decision=approved"))
            .json()).items[0]""")

    # Finding 5: the revocation's approvals row is deleted; the log still names it.
    delete_row(server, "approvals", "DELETE FROM approvals WHERE revokes = ?", record["id"])
    auditor.reload()
    expect(verification).to_contain_text("checks failed")
    expect(auditor.get_by_test_id("check-records")).to_contain_text(
        re.compile(rf"log entry \d+ revokes approval {record['id']}, but the server shows it "
                   "as not revoked"))

    # One byte of the stored envelope changes in the database: the page names the entry.
    tamper_envelope(server, int(record["id"]))
    auditor.reload()
    expect(verification).to_contain_text("checks failed")
    entry = f"log entry {record['log_index']}"
    expect(auditor.get_by_test_id("check-logged")).to_contain_text(
        f"the envelope differs from the one logged in {entry}")
    expect(auditor.get_by_test_id("check-signature")).to_contain_text(
        "the signature does not verify")
    expect(auditor.get_by_test_id("check-chain")).to_contain_text("each chained to the one before")
    tampered = audit_verify(server, export_bundle(auditor, tmp_path / "tampered.json"))
    assert tampered.returncode == 1, tampered.stdout + tampered.stderr
    assert f"approval {record['id']}: the envelope differs from the one logged in entry " \
           f"{record['log_index']}" in tampered.stdout + tampered.stderr

    # A changed key, version and log entry are named on the page too.
    key_id = record["key_id"]
    bypass(server, "signing_keys", "UPDATE signing_keys SET public_key = ? WHERE id = ?",
           "A" * 43 + "=", key_id)
    version = stored(server, "SELECT version_id FROM approvals WHERE id = ?", record["id"])
    orders = json.loads(stored(server, "SELECT orders FROM mission_versions WHERE id = ?",
                               version))
    orders["goals"][1]["title"] = "Take no sample"
    bypass(server, "mission_versions", "UPDATE mission_versions SET orders = ? WHERE id = ?",
           json.dumps(orders), version)
    first = stored(server, 'SELECT entry FROM log_entries WHERE "index" = 0')
    bypass(server, "log_entries", 'UPDATE log_entries SET entry = ? WHERE "index" = 0',
           first.replace('"at":"20', '"at":"19', 1))
    auditor.reload()
    expect(verification).to_contain_text("checks failed")
    expect(auditor.get_by_test_id("check-key")).to_contain_text(
        re.compile(r"differs from its registration in log entry \d+"))
    expect(auditor.get_by_test_id("check-orders")).to_contain_text(
        f"the stored orders of {MISSION}@v1 do not hash to the signed digest")
    expect(auditor.get_by_test_id("check-chain")).to_contain_text(
        "log entry 0 does not hash to the leaf hash recorded for it")
    expect(auditor.get_by_test_id("check-chain")).to_contain_text(
        "log entry 1 does not chain to entry 0")
    expect(auditor.get_by_test_id("check-root")).to_contain_text(
        "log entries 0..")
    # Entry 0 (an account's creation) is put back: the server reads roles from the log's
    # account entries and decides nothing while one is altered, and later tests share it.
    bypass(server, "log_entries", 'UPDATE log_entries SET entry = ? WHERE "index" = 0', first)

    # The auditor pins the published key by hand; the server presents another one: the pin
    # check fails and names both fingerprints.
    stored_pin = auditor.evaluate(
        "() => JSON.parse(localStorage.getItem('countersign.log-key-pin|' + location.origin))")
    assert stored_pin["keyId"] == checkpoint["key_id"]
    published = dsse.generate_key()
    auditor.get_by_text("Enter the published log key").click()
    auditor.get_by_label("Expected log key").fill(dsse.public_text(published))
    auditor.get_by_role("button", name="Pin entered key").click()
    pin = auditor.get_by_test_id("check-pin")
    expect(pin).to_contain_text(
        f"the server presents log key {server_print}, but this browser pinned log key "
        f"{fingerprint(dsse.key_id(dsse.public_text(published)))}")
    expect(verification).to_contain_text("Log key matches the pinned key")
    expect(auditor.get_by_test_id("log-key-state")).to_contain_text("a different log key")
    assert not errors, "the app raised errors in the browser:\n" + "\n".join(errors)


def fingerprint(key_id: str) -> str:
    """The browser's fingerprint of a key id: its first 16 hex digits in groups of four."""
    return " ".join(key_id[i:i + 4] for i in range(0, 16, 4))
