"""Each role signs in through the browser and sees only what that role may do.

The server enforces the roles on every route (tests/web); these tests prove the app shell
offers each role exactly its own actions, and that the server still refuses a forbidden
action when a page's buttons are bypassed.
"""

from __future__ import annotations

import re
from pathlib import Path

import pytest
from playwright.sync_api import Page, expect

from .conftest import PASSWORD, ROLES, Server, submit_sign_in
from .screens import tables_fit_each_screen

NAV_LINKS = {
    "operator": ["Missions", "Import"],
    "supervisor": ["Missions", "Activity", "Reviews", "Audit", "Keys"],
    "auditor": ["Missions", "Activity", "Audit"],
    "admin": ["Missions", "Activity", "Audit", "Users", "Vehicles"],
}
MISSION_TABS = {
    "operator": ["Orders", "Findings", "Paths", "Plan view", "Versions", "Rehearse", "Edit orders",
                 "Graph editor"],
    "supervisor": ["Orders", "Findings", "Paths", "Plan view", "Versions", "Rehearse"],
    "auditor": ["Orders", "Findings", "Paths", "Plan view", "Versions", "Rehearse"],
    "admin": ["Orders", "Findings", "Paths", "Plan view", "Versions", "Rehearse"],
}


def sign_in(page: Page, role: str, password: str | None = None,
            username: str | None = None) -> None:
    """Sign in as the shared account of `role`, or as `username` (an account of that role);
    with a wrong `password` and no username, the sign-in is expected to fail."""
    page.goto("/")
    submit_sign_in(page, username or role, password or PASSWORD[role])
    if password is None or username is not None:
        expect(page.get_by_test_id("current-role")).to_have_text(role.title())


def link_names(page: Page, container: str) -> list[str]:
    nav = page.get_by_role("navigation", name=container)
    return [name.strip() for name in nav.get_by_role("link").all_inner_texts()]


def test_wrong_password_shows_a_clear_error(page: Page) -> None:
    sign_in(page, "operator", password="not-the-password")
    expect(page.get_by_role("alert")).to_have_text("Wrong username or password.")
    expect(page.get_by_label("Password")).to_have_value("")
    expect(page.get_by_test_id("current-user")).to_have_count(0)


@pytest.mark.parametrize("role", ROLES)
def test_each_role_sees_only_its_own_actions(page: Page, role: str, seeded_mission: str) -> None:
    sign_in(page, role)
    expect(page.get_by_test_id("current-user")).to_have_text(f"E2E {role.title()}")
    expect(page.get_by_role("heading", name="Missions", level=1)).to_be_visible()
    assert link_names(page, "Main") == NAV_LINKS[role]
    expect(page.get_by_role("link", name="Import or create mission")).to_have_count(
        1 if role == "operator" else 0)

    # Every role reads missions: the list, then the mission page with its views.
    # Other tests add missions to the shared server, so the list's first page may not hold this
    # one: find it with the list's search, then pick it by address.
    page.get_by_role("searchbox", name="Search").fill(seeded_mission)
    page.get_by_role("searchbox", name="Search").press("Enter")
    page.locator(f'a[href="/missions/{seeded_mission}"]').click()
    expect(page.get_by_role("heading", name="Search and sample", level=1)).to_be_visible()
    tabs = [t.strip() for t in page.get_by_role("tab").all_inner_texts()]
    assert [re.sub(r" \(\d+\)$", "", t) for t in tabs] == MISSION_TABS[role]
    page.get_by_role("tab", name=re.compile("^Versions")).click()
    expect(page.get_by_role("heading", name="Versions")).to_be_visible()
    expect(page.get_by_role("button", name="Create version")).to_have_count(
        1 if role == "operator" else 0)

    # Pages of other roles are not offered, and typing their address does not open them.
    for path, allowed in (("/users", role == "admin"), ("/import", role == "operator"),
                          ("/events", role != "operator"), ("/vehicles", role == "admin")):
        page.goto(path)
        refused = page.get_by_role("heading", name="Not available to your role")
        expect(refused).to_have_count(0 if allowed else 1)


@pytest.mark.parametrize("role", ["supervisor", "auditor", "admin"])
def test_server_refuses_an_import_that_the_page_does_not_offer(
    page: Page, role: str, server: Server
) -> None:
    sign_in(page, role)
    status = page.evaluate(
        """async () => {
            const me = await (await fetch("/api/auth/me")).json();
            const answer = await fetch("/api/import", {
                method: "POST",
                headers: {"Content-Type": "application/json", "X-CSRF-Token": me.csrf_token},
                body: JSON.stringify({format: "countersign.orders/1", id: "sneaky", goals: []}),
            });
            return answer.status;
        }"""
    )
    assert status == 403


def test_operator_imports_the_example_and_reads_findings_paths_and_orders(
    page: Page, tmp_path: Path, tmp_path_factory: pytest.TempPathFactory
) -> None:
    from countersign.orders.examples import example_bytes

    orders = example_bytes("search-and-sample").replace(
        b'"id": "search-and-sample"', b'"id": "e2e-imported"')
    assert b"e2e-imported" in orders
    upload = tmp_path / "e2e-imported.json"
    upload.write_bytes(orders)

    sign_in(page, "operator")
    page.get_by_role("link", name="Import or create mission").click()
    page.get_by_label("Orders file (.json, .xml, .ttl)").set_input_files(str(upload))
    page.get_by_role("button", name="Import file").click()

    # The import lands on the new mission's findings.
    expect(page).to_have_url(re.compile(r"/missions/e2e-imported\?tab=findings$"))
    expect(page.get_by_test_id("verdict")).to_contain_text("The orders pass every check")
    expect(page.get_by_test_id("verdict")).to_contain_text("75 paths in all")

    page.get_by_role("tab", name="Paths").click()
    expect(page.get_by_test_id("paths-to-COMPLETE")).to_have_text("25")
    expect(page.get_by_test_id("paths-to-ABORT")).to_have_text("50")
    tables_fit_each_screen(page, tmp_path_factory, "paths-counts",
                           [(page.locator("table.counts"), page.locator("main"))])
    page.get_by_role("button", name="Trace of path 1", exact=True).click()
    trace = page.locator("pre.trace")
    expect(trace).to_contain_text("Ethical Mission Execution Trace #1:")
    expect(trace).to_contain_text("Commence: Search Area A.")
    page.get_by_role("button", name="Next →").click()
    expect(page.get_by_text("Page 2")).to_be_visible()

    page.get_by_role("tab", name="Orders", exact=True).click()
    expect(page.get_by_test_id("plain-orders")).to_contain_text("Search Area A")

    page.get_by_role("tab", name=re.compile("^Versions")).click()
    page.get_by_role("button", name="Create version").click()
    expect(page.get_by_role("status").filter(has_text="Version 1 created.")).to_be_visible()
    expect(page.get_by_role("cell", name="v1", exact=True)).to_be_visible()

    page.get_by_role("link", name="Missions", exact=True).first.click()
    page.get_by_label("Search").fill("e2e-imp")
    page.get_by_role("button", name="Search").click()
    expect(page.get_by_role("link", name="Search and sample")).to_have_count(1)
    expect(page.locator("table.missions tbody tr")).to_have_count(1)


def test_admin_manages_users_and_a_disabled_user_cannot_sign_in(page: Page) -> None:
    sign_in(page, "admin")
    page.get_by_role("link", name="Users").click()
    expect(page.get_by_role("heading", name="Users", level=1)).to_be_visible()
    for role in ROLES:
        expect(page.get_by_role("cell", name=role, exact=True)).to_be_visible()

    page.get_by_label("Username").fill("e2e-new-auditor")
    page.get_by_label("Display name").fill("New Auditor")
    page.get_by_label("Role", exact=True).select_option("auditor")
    page.get_by_label("Initial password").fill("a-long-enough-password-1")
    page.get_by_role("button", name="Create user").click()
    expect(page.get_by_role("status").filter(has_text="Created auditor e2e-new-auditor.")
           ).to_be_visible()
    # A supervisor can decide: the form asks for the admin's own password, a wrong one refused.
    page.get_by_label("Username").fill("e2e-new-supervisor")
    page.get_by_label("Role", exact=True).select_option("supervisor")
    page.get_by_label("Initial password").fill("a-long-enough-password-1")
    page.get_by_label("Your password (to create a supervisor)").fill("not the admin's password")
    page.get_by_role("button", name="Create user").click()
    expect(page.get_by_role("alert")).to_contain_text("no user was created")
    page.get_by_label("Your password (to create a supervisor)").fill(PASSWORD["admin"])
    page.get_by_role("button", name="Create user").click()
    expect(page.get_by_role("status").filter(
        has_text="Created supervisor e2e-new-supervisor.")).to_be_visible()
    page.get_by_role("button", name="Disable e2e-new-auditor").click()
    expect(page.get_by_role("status").filter(has_text="e2e-new-auditor disabled.")).to_be_visible()

    page.get_by_role("button", name="Sign out").click()
    expect(page.get_by_role("heading", name="Sign in to Countersign")).to_be_visible()
    sign_in(page, "e2e-new-auditor", password="a-long-enough-password-1")
    expect(page.get_by_role("alert")).to_be_visible()
    expect(page.get_by_test_id("current-user")).to_have_count(0)


def test_sign_out_ends_the_session(page: Page) -> None:
    sign_in(page, "auditor")
    page.get_by_role("button", name="Sign out").click()
    expect(page.get_by_role("status")).to_have_text("You have signed out.")
    page.goto("/missions")
    expect(page.get_by_role("heading", name="Sign in to Countersign")).to_be_visible()
