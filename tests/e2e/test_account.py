"""Account page: a user changes their own password in the browser; a weak one
is refused with the policy's words; the change ends the user's other sessions and revokes their
API tokens; the old password stops working and the new one works. An admin resets a user's
password on the users page, which ends that user's sessions too."""

from __future__ import annotations

import contextlib
import uuid
from collections.abc import Iterator

import httpx
from playwright.sync_api import Browser, BrowserContext, Page, expect

from .conftest import PASSWORD, PATIENCE_MS, Server, api_login

FIRST = "Kq8-first-Zt4-pass"
SECOND = "Wm3-second-Hx7-pass"
RESET = "Pv5-reset-Nc2-pass"


def _create_user(server: Server, username: str) -> None:
    with httpx.Client(base_url=server.url, timeout=30) as client:
        login = api_login(client, "admin", PASSWORD["admin"])
        login.raise_for_status()
        made = client.post("/api/users", json={"username": username, "role": "operator",
                                                "display_name": "", "password": FIRST},
                           headers={"X-CSRF-Token": login.json()["csrf_token"]})
        assert made.status_code == 201, made.text


@contextlib.contextmanager
def _context(browser: Browser, server: Server) -> Iterator[BrowserContext]:
    context = browser.new_context(base_url=server.url, viewport={"width": 1280, "height": 900})
    context.set_default_timeout(PATIENCE_MS)
    try:
        yield context
    finally:
        context.close()


def _sign_in(page: Page, username: str, password: str) -> None:
    page.goto("/")
    page.get_by_label("Username").fill(username)
    page.get_by_label("Password").fill(password)
    page.get_by_role("button", name="Sign in").click()


def _signed_in(page: Page, username: str) -> None:
    expect(page.get_by_test_id("current-user")).to_have_text(username)


def _change(page: Page, current: str, new: str) -> None:
    page.get_by_label("Current password").fill(current)
    page.get_by_label("New password", exact=True).fill(new)
    page.get_by_label("New password again").fill(new)
    page.get_by_role("button", name="Change password").click()


def test_password_change_in_the_browser(browser: Browser, server: Server) -> None:
    username = f"pw{uuid.uuid4().hex[:8]}"
    _create_user(server, username)
    with _context(browser, server) as mine, _context(browser, server) as other:
        page, elsewhere = mine.new_page(), other.new_page()
        _sign_in(page, username, FIRST)
        _signed_in(page, username)
        _sign_in(elsewhere, username, FIRST)
        _signed_in(elsewhere, username)

        page.get_by_role("link", name="Account").click()
        expect(page.get_by_role("heading", name="Your account", level=1)).to_be_visible()
        page.get_by_label("Token name").fill("ci")
        page.get_by_role("button", name="Create token").click()
        expect(page.get_by_test_id("new-token")).to_contain_text("cst_")
        expect(page.get_by_test_id("token-row")).to_contain_text("Active")
        # A token that can decide needs the password, entered again.
        page.get_by_label("Token name").fill("decider")
        page.get_by_role("checkbox", name="decide").check()
        page.get_by_label("Your password (for the decide scope)").fill(FIRST)
        page.get_by_role("button", name="Create token").click()
        expect(page.get_by_test_id("token-row").filter(has_text="decider")).to_contain_text(
            "decide")

        # A weak password: the API's refusal, in its own words, and nothing changed.
        _change(page, FIRST, "password12")
        expect(page.get_by_role("alert")).to_contain_text("the password is too weak")
        _change(page, "not the password", SECOND)
        expect(page.get_by_role("alert")).to_contain_text("the current password is wrong")

        _change(page, FIRST, SECOND)
        expect(page.get_by_role("status").filter(has_text="Password changed")).to_be_visible()
        expect(page.get_by_test_id("token-row").filter(has_text="Revoked")).to_have_count(2)
        page.reload()
        _signed_in(page, username)  # the session that asked stays

        elsewhere.reload()  # the other session has ended
        expect(elsewhere.get_by_role("button", name="Sign in")).to_be_visible()
        expect(elsewhere.get_by_test_id("current-user")).to_have_count(0)

    with _context(browser, server) as fresh:
        page = fresh.new_page()
        _sign_in(page, username, FIRST)
        expect(page.get_by_role("alert")).to_have_text("Wrong username or password.")
        _sign_in(page, username, SECOND)
        _signed_in(page, username)


def test_admin_resets_a_password(browser: Browser, server: Server) -> None:
    username = f"rs{uuid.uuid4().hex[:8]}"
    _create_user(server, username)
    with _context(browser, server) as theirs, _context(browser, server) as admins:
        page, admin = theirs.new_page(), admins.new_page()
        _sign_in(page, username, FIRST)
        _signed_in(page, username)
        _sign_in(admin, "admin", PASSWORD["admin"])
        admin.get_by_role("link", name="Users").click()
        admin.get_by_role("button", name=f"Reset password of {username}").click()
        form = admin.get_by_role("form", name=f"Reset password of {username}")
        form.get_by_label(f"New password for {username}").fill(username + "12")
        form.get_by_label("Your password").fill(PASSWORD["admin"])
        form.get_by_role("button", name="Set password").click()
        expect(form.get_by_role("alert")).to_contain_text("may not contain the username")
        form.get_by_label(f"New password for {username}").fill(RESET)
        form.get_by_role("button", name="Set password").click()
        expect(admin.get_by_role("status")).to_contain_text(f"Password of {username} reset")

        page.reload()
        expect(page.get_by_role("button", name="Sign in")).to_be_visible()
        _sign_in(page, username, FIRST)
        expect(page.get_by_role("alert")).to_have_text("Wrong username or password.")
        _sign_in(page, username, RESET)
        _signed_in(page, username)
