"""In the browser: moving a user's role drop-down changes nothing until the
admin confirms in a dialog with their own password, which the server checks."""

from __future__ import annotations

from playwright.sync_api import Page, expect

from .conftest import PASSWORD, Server
from .test_roles import sign_in
from .test_vehicle_registry import client


def test_role_change_is_confirmed_with_the_admins_password(page: Page, server: Server) -> None:
    with client(server, "admin") as admin:
        made = admin.post("/api/users", json={"username": "e2e-grace", "role": "operator",
                                              "password": "Qz8-another-long-pass"})
        assert made.status_code == 201, made.text

    sign_in(page, "admin")
    page.get_by_role("link", name="Users", exact=True).click()
    role = page.get_by_label("Role of e2e-grace", exact=True)
    role.select_option("admin")
    dialog = page.get_by_role("dialog", name="Change the role of e2e-grace")
    expect(dialog.get_by_test_id("role-change-summary")).to_contain_text(
        "From Operator to Admin")
    expect(role).to_have_value("operator")  # nothing applied yet
    dialog.get_by_role("button", name="Cancel").click()
    expect(dialog).to_have_count(0)

    role.select_option("auditor")
    dialog.get_by_label("Your password").fill("not the admin password")
    dialog.get_by_role("button", name="Change role").click()
    expect(dialog.get_by_role("alert")).to_contain_text("password is wrong; no role was changed")
    expect(dialog.get_by_role("alert")).not_to_contain_text("signed")
    expect(role).to_have_value("operator")
    dialog.get_by_label("Your password").fill(PASSWORD["admin"])
    dialog.get_by_role("button", name="Change role").click()
    expect(page.get_by_role("status").filter(has_text="e2e-grace is now auditor.")).to_be_visible()
    expect(role).to_have_value("auditor")
