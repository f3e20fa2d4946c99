"""Browser tests: the real server (`countersign serve`) and the built app in Debian's Chromium.

Everything here runs against a fresh data directory: the accounts are made with the real
`countersign users create` command and the server is the real `countersign serve` process.
The tests skip with a message when Chromium, the Playwright package or frontend/dist is
missing; with COUNTERSIGN_REQUIRE_E2E=1 (for CI) that is a failure instead.
"""

from __future__ import annotations

import contextlib
import json
import os
import re
import secrets
import subprocess
import sys
import time
import urllib.error
import urllib.request
from collections.abc import Iterable, Iterator
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any

import pytest

from ..ports import free_port

if TYPE_CHECKING:
    import httpx
    from playwright.sync_api import Browser, Page, Playwright, StorageState

REPO = Path(__file__).resolve().parents[2]
DIST = REPO / "frontend" / "dist"


def _avcl() -> Path:
    """The NPS AVCL reference missions (../shared/reference): beside the checkout, or beside the
    main checkout for a worktree (a folder deeper), whose REPO.parent has no shared/."""
    for root in REPO.parents:
        candidate = root / "shared" / "reference" / "nps-ethical-control" / "missions" / "avcl"
        if candidate.is_dir():
            return candidate
    return REPO.parent / "shared" / "reference" / "nps-ethical-control" / "missions" / "avcl"


AVCL = _avcl()
CHROMIUM = Path(os.environ.get("COUNTERSIGN_CHROMIUM", "/usr/bin/chromium"))
# Debian's Chromium, headless, as root, on a machine whose only network is loopback.
CHROMIUM_ARGS = [
    "--headless", "--no-sandbox", "--disable-gpu", "--disable-quic", "--no-first-run",
    "--disable-background-networking", "--disable-component-update", "--disable-sync",
]
ROLES = ("operator", "supervisor", "auditor", "admin")
# Never containing the username (the password policy refuses that).
PASSWORD = {role: f"Xy7-{role[:3]}-e2e-Qw9-pass" for role in ROLES}


def missing_prerequisite() -> str | None:
    """Why the browser tests cannot run here, or None when they can."""
    if not CHROMIUM.is_file():
        return (f"{CHROMIUM} is missing: install Debian's Chromium (apt-get install -y chromium) "
                "to run the browser tests")
    if not (DIST / "index.html").is_file():
        return ("frontend/dist is missing: build the browser app with ./scripts/build-frontend "
                "to run the browser tests")
    try:
        import playwright.sync_api  # noqa: F401
    except ImportError:
        return "the playwright package is missing: pip install -e '.[dev]'"
    return None


def _required() -> bool:
    return os.environ.get("COUNTERSIGN_REQUIRE_E2E") == "1"


def pytest_collection_modifyitems(config: pytest.Config, items: list[pytest.Item]) -> None:
    """Skip every browser test (one clear reason) when something they need is missing."""
    reason = missing_prerequisite()
    if reason is None or _required():
        return
    skip = pytest.mark.skip(reason=reason)
    for item in items:
        if "server" in getattr(item, "fixturenames", ()):
            item.add_marker(skip)


def _cli(*args: str) -> list[str]:
    """The `countersign` command of the Python running the tests."""
    return [sys.executable, "-c", "import sys; from countersign.cli import main; "
            "sys.exit(main())", *args]


@dataclass(frozen=True)
class Server:
    url: str
    data_dir: Path
    log: Path

    def log_tail(self, lines: int = 40) -> str:
        try:
            return "\n".join(self.log.read_text(errors="replace").splitlines()[-lines:])
        except OSError:
            return "(no server log)"


def _server_env(data_dir: Path) -> dict[str, str]:
    env = {k: v for k, v in os.environ.items() if not k.startswith("COUNTERSIGN_")}
    env["COUNTERSIGN_DATA_DIR"] = str(data_dir)
    # The suite signs its shared accounts in many times a minute; the default limit (10 password
    # checks per account per minute) is the API suite's to test (tests/web/test_password_throttle).
    env["COUNTERSIGN_PASSWORD_CHECKS_PER_MINUTE"] = "600"
    return env


@pytest.fixture(scope="session")
def server(tmp_path_factory: pytest.TempPathFactory) -> Iterator[Server]:
    """The real app: accounts made by `countersign users create`, then `countersign serve`."""
    reason = missing_prerequisite()
    if reason is not None:
        # Only reached with COUNTERSIGN_REQUIRE_E2E=1: then a missing browser is a failure.
        if _required():
            pytest.fail(reason)
        pytest.skip(reason)
    data_dir = tmp_path_factory.mktemp("countersign-e2e")
    with running_server(data_dir, ROLES) as running:
        yield running


@contextlib.contextmanager
def running_server(data_dir: Path, roles: Iterable[str],
                   extra_env: dict[str, str] | None = None) -> Iterator[Server]:
    """`countersign users create` for each role, then `countersign serve` on data_dir (with
    extra_env, e.g. COUNTERSIGN_MAP_TILES), stopped on exit."""
    env = {**_server_env(data_dir), **(extra_env or {})}
    for role in roles:
        done = subprocess.run(
            _cli("users", "create", "--username", role, "--role", role,
                 "--display-name", f"E2E {role.title()}", "--password-stdin",
                 "--data-dir", str(data_dir)),
            input=PASSWORD[role] + "\n", capture_output=True, text=True, env=env, timeout=120,
        )
        assert done.returncode == 0, f"users create {role} failed:\n{done.stdout}{done.stderr}"
    port = free_port()
    log = data_dir / "server.log"
    with log.open("wb") as out:
        process = subprocess.Popen(
            _cli("serve", "--host", "127.0.0.1", "--port", str(port), "--data-dir",
                 str(data_dir)),
            stdout=out, stderr=subprocess.STDOUT, env=env, cwd=REPO,
        )
    running = Server(url=f"http://127.0.0.1:{port}", data_dir=data_dir, log=log)
    try:
        _wait_healthy(running, process)
        yield running
    finally:
        process.terminate()
        try:
            process.wait(timeout=15)
        except subprocess.TimeoutExpired:
            process.kill()
            process.wait(timeout=15)


def _wait_healthy(server: Server, process: subprocess.Popen[bytes]) -> None:
    deadline = time.monotonic() + 180  # a loaded machine starts a server slowly
    while time.monotonic() < deadline:
        if process.poll() is not None:
            pytest.fail(f"countersign serve exited with {process.returncode}:\n"
                        f"{server.log_tail()}")
        try:
            with urllib.request.urlopen(f"{server.url}/api/health", timeout=2) as answer:
                if answer.status == 200:
                    return
        except (urllib.error.URLError, OSError):
            pass
        time.sleep(0.2)
    pytest.fail(f"countersign serve did not answer /api/health within 180 s:\n{server.log_tail()}")


# How long an action (a click waits for its element to be visible, enabled and stable) or an
# assertion waits, in ms. Under load 11 on two cores a starved Chromium once took over 15 s to
# paint a stable sign-in button; what passes returns as soon as it holds, so only a failure waits
# this long. Every browser context of the suite uses it.
PATIENCE_MS = 60_000


@pytest.fixture(scope="session")
def playwright_instance() -> Iterator[Playwright]:
    from playwright.sync_api import expect, sync_playwright

    # Playwright's assertions give up after 5 s; a sign-in (its argon2 hash runs at low priority)
    # or a validation on a loaded 2-core machine takes longer. A passing check returns as soon as
    # it holds, so the longer bound only delays a real failure.
    expect.set_options(timeout=PATIENCE_MS)
    with sync_playwright() as instance:
        yield instance


@pytest.fixture(scope="session")
def browser(playwright_instance: Playwright, server: Server,
            tmp_path_factory: pytest.TempPathFactory) -> Iterator[Browser]:
    del server  # started first, so a server failure is reported before a browser one
    launched = playwright_instance.chromium.launch(
        executable_path=str(CHROMIUM), headless=True, args=CHROMIUM_ARGS,
        env={**os.environ, "HOME": str(tmp_path_factory.mktemp("chromium-home"))},
    )
    try:
        yield launched
    finally:
        launched.close()


# The two screens every page is looked at on (DESIGN: 1024x768 and 1280x800).
SCREENS = [(1024, 768), (1280, 800)]


@contextlib.contextmanager
def _fresh_page(browser: Browser, server: Server, viewport: dict[str, int],
                **options: Any) -> Iterator[Page]:
    """A page in a fresh browser context (no cookies; `options` such as accept_downloads go to
    the context), patient by PATIENCE_MS; the test fails when the app raised errors in the
    browser."""
    context = browser.new_context(base_url=server.url, viewport=viewport, **options)
    context.set_default_timeout(PATIENCE_MS)
    opened = context.new_page()
    problems: list[str] = []
    opened.on("pageerror", lambda error: problems.append(f"page error: {error}"))
    try:
        yield opened
        assert not problems, "the app raised errors in the browser:\n" + "\n".join(problems)
    finally:
        context.close()


@pytest.fixture(params=SCREENS, ids=lambda s: f"{s[0]}x{s[1]}")
def screen(request: pytest.FixtureRequest, browser: Browser, server: Server) -> Iterator[Page]:
    """A fresh browser context of one of SCREENS' sizes (the test runs once per screen)."""
    width, height = request.param
    with _fresh_page(browser, server, {"width": width, "height": height}) as opened:
        yield opened


@pytest.fixture(scope="module")
def operator_session(browser: Browser, server: Server) -> StorageState:
    """The operator signed in once for the module, in the browser: the session's storage state
    (its cookie), for each test's fresh context; one password check for the module rather than
    one per test and screen (signing in is test_roles.py's to test)."""
    from playwright.sync_api import expect

    context = browser.new_context(base_url=server.url)
    context.set_default_timeout(PATIENCE_MS)
    try:
        page = context.new_page()
        page.goto("/")
        submit_sign_in(page, "operator", PASSWORD["operator"])
        expect(page.get_by_test_id("current-role")).to_have_text("Operator")
        return context.storage_state()
    finally:
        context.close()


@pytest.fixture()
def page(browser: Browser, server: Server, request: pytest.FixtureRequest,
         tmp_path_factory: pytest.TempPathFactory) -> Iterator[Page]:
    """A fresh browser context (no cookies) per test; a screenshot is kept when a test fails
    (pytest's temporary directory, `screenshots/`, printed with the failure)."""
    with _fresh_page(browser, server, _viewport()) as opened:
        yield opened
        keep_failure_shot(opened, request, tmp_path_factory)


def keep_failure_shot(page: Page, request: pytest.FixtureRequest,
                      tmp_path_factory: pytest.TempPathFactory) -> None:
    """When the test failed, a full-page screenshot `screenshots/<test>.png` in pytest's
    temporary directory, printed with the failure."""
    if not _failed(request):
        return
    shot = tmp_path_factory.getbasetemp() / "screenshots" / f"{request.node.name}.png"
    shot.parent.mkdir(exist_ok=True)
    # A screenshot must never hide the real failure.
    with contextlib.suppress(Exception):
        page.screenshot(path=str(shot), full_page=True)
        print(f"screenshot of the failed page: {shot}")


def _viewport() -> dict[str, int]:
    """The page's window: 1280x900, or COUNTERSIGN_E2E_VIEWPORT (e.g. 1024x768) to run the tests
    that do not set their own size at another one."""
    wanted = os.environ.get("COUNTERSIGN_E2E_VIEWPORT", "1280x900")
    found = re.fullmatch(r"(\d{3,4})x(\d{3,4})", wanted)
    if not found:
        raise pytest.UsageError(f"COUNTERSIGN_E2E_VIEWPORT={wanted!r}: expected WIDTHxHEIGHT, "
                                "e.g. 1024x768")
    return {"width": int(found[1]), "height": int(found[2])}


def _failed(request: pytest.FixtureRequest) -> bool:
    report: Any = getattr(request.node, "rep_call", None)
    return bool(report is not None and report.failed)


@pytest.hookimpl(wrapper=True, tryfirst=True)
def pytest_runtest_makereport(item: pytest.Item, call: pytest.CallInfo[None]) -> Any:
    report = yield
    if report.when == "call":
        item.rep_call = report  # type: ignore[attr-defined]
    return report


@pytest.fixture(scope="session")
def seeded_mission(server: Server) -> str:
    """The paper's exemplar, imported once through the API by the operator."""
    from countersign.orders.examples import example_bytes

    return _api_import(server, example_bytes("search-and-sample"), "application/json")


@pytest.fixture()
def own_exemplar(server: Server) -> str:
    """A copy of the exemplar under an id of its own, for a test that counts what it adds
    (records, versions) and must not see what other tests left on the shared server."""
    from countersign.orders.examples import example_bytes

    orders = json.loads(example_bytes("search-and-sample"))
    orders["id"] = f"search-and-sample-{secrets.token_hex(4)}"
    return _api_import(server, json.dumps(orders).encode(), "application/json")


# The server checks at most ten passwords a minute per account, sign-ins included
# (store/login_throttle.py), and the suite signs the shared accounts in more often than that;
# a sign-in the throttle refuses is tried again once the wait it names is over.
THROTTLE_PATIENCE_S = 150
THROTTLED = re.compile(r"Too many requests: .*try again in (\d+) s")


def api_login(client: httpx.Client, username: str, password: str) -> httpx.Response:
    """POST /api/auth/login, waiting out the password throttle (429 with Retry-After)."""
    deadline = time.monotonic() + THROTTLE_PATIENCE_S
    while True:
        answer = client.post("/api/auth/login",
                             json={"username": username, "password": password})
        if answer.status_code != 429 or time.monotonic() > deadline:
            return answer
        time.sleep(int(answer.headers.get("Retry-After", "1")) + 0.2)


def submit_sign_in(page: Page, username: str, password: str) -> None:
    """Fill in and submit the sign-in form, submitting again after waiting out a throttle
    refusal; returns when the app shows a signed-in user or any other sign-in error."""
    from playwright.sync_api import expect

    deadline = time.monotonic() + THROTTLE_PATIENCE_S
    while True:
        page.get_by_label("Username").fill(username)
        page.get_by_label("Password").fill(password)
        page.get_by_role("button", name="Sign in").click()
        signed_in = page.get_by_test_id("current-user")
        alert = page.locator("form.login").get_by_role("alert")
        expect(signed_in.or_(alert)).to_be_visible()
        if signed_in.count() or not alert.count():
            return
        throttled = THROTTLED.search(alert.inner_text())
        if throttled is None or time.monotonic() > deadline:
            return
        time.sleep(int(throttled.group(1)) + 0.2)


def make_user(server: Server, role: str) -> tuple[str, str]:
    """A new account of `role` created by the admin through the API: (username, password), for a
    test whose assertions depend on that user's own state (keys, sessions) on the shared server."""
    import httpx

    username = f"{role}-{secrets.token_hex(4)}"
    password = f"Xy7-{secrets.token_hex(6)}-e2e-Qw9"
    with httpx.Client(base_url=server.url, timeout=60) as client:
        login = api_login(client, "admin", PASSWORD["admin"])
        login.raise_for_status()
        made = client.post("/api/users", headers={"X-CSRF-Token": login.json()["csrf_token"]},
                           json={"username": username, "role": role, "password": password,
                                 "admin_password": PASSWORD["admin"],
                                 "display_name": f"E2E {role.title()} {username[-8:]}"})
        assert made.status_code == 201, made.text
    return username, password


def _api_import(server: Server, body: bytes, content_type: str) -> str:
    import httpx

    with httpx.Client(base_url=server.url, timeout=30) as client:
        login = api_login(client, "operator", PASSWORD["operator"])
        login.raise_for_status()
        token = login.json()["csrf_token"]
        answer = client.post("/api/import", content=body,
                             headers={"Content-Type": content_type, "X-CSRF-Token": token})
        existing = re.search(r"a mission with id '([^']+)' exists already", answer.text)
        if answer.status_code == 409 and existing:
            return existing.group(1)  # an earlier test of the session imported the same file
        assert answer.status_code == 201, answer.text
        mission_id: str = answer.json()["id"]
        return mission_id


# axe-core (npm, frontend/node_modules) checks a page as a screen-reader user and the WCAG rules
# see it; every page the browser suite visits must be free of serious and critical
# violations.
AXE = REPO / "frontend" / "node_modules" / "axe-core" / "axe.min.js"
AXE_FAILS = ("serious", "critical")


def axe_violations(page: Page, *, include: str | None = None,
                   impacts: tuple[str, ...] = AXE_FAILS) -> list[dict[str, Any]]:
    """axe-core's violations of the page as shown now (or of the element `include` selects),
    of the given impacts. Injected through the DevTools protocol, which the app's CSP
    (`script-src 'self'`) does not govern; frames are not entered (viser's is sandboxed in an
    opaque origin and is viser's own page)."""
    if not AXE.is_file():
        pytest.fail(f"{AXE} is missing: run `npm ci` in frontend/ (axe-core is a dev dependency)")
    if not page.evaluate("() => typeof window.axe === 'object'"):
        page.evaluate(AXE.read_text(encoding="utf-8") + "\n;void 0")
    result: dict[str, Any] = page.evaluate(
        """async (include) => await window.axe.run(
               include ? document.querySelector(include) : document,
               { iframes: false, resultTypes: ["violations"] })""",
        include)
    return [v for v in result["violations"] if v.get("impact") in impacts]


def describe_violations(violations: list[dict[str, Any]]) -> str:
    lines = []
    for v in violations:
        targets = [" ".join(map(str, node.get("target", []))) for node in v.get("nodes", [])]
        lines.append(f"{v['impact']} {v['id']}: {v['help']} ({len(targets)} nodes: "
                     f"{', '.join(targets[:5])}{' ...' if len(targets) > 5 else ''})")
    return "\n".join(lines)


def expect_accessible(page: Page, where: str, *, include: str | None = None) -> None:
    """Fails, naming each rule and the elements that break it, when axe-core finds a serious or
    critical violation on the page (or in `include`). Call it once per page state worth
    checking: `expect_accessible(page, "review of v1")`."""
    found = axe_violations(page, include=include)
    assert not found, f"axe-core on {where}:\n{describe_violations(found)}"
