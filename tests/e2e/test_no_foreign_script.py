"""First "must hold": no script runs that the app did not ship.

Script-bearing strings (`<img onerror>`, `<iframe srcdoc>`, `<script>`, `<svg onload>`, markdown
links and images, `javascript:` URLs) are put in every user-controlled field, through the API:
the orders' goal, terminal, constraint, norm, area, quantity and vehicle texts, mission titles
and descriptions, rejection, revocation and key-revocation reasons, key names and display names
(a username with markup is refused outright). Then a supervisor with a key registered in the
browser opens every page (missions, the mission's tabs, the reviews, keys, audit and record
pages, activity, the plan view with a hostile chart, the printable approval documents, the
vehicle registry, a live rehearsal with its sandboxed viser viewer, the replay), an operator the
editors and an admin the users page. On every page and in every frame:

- a canary global (`window.__pwned`, trapped by an init script so that even a write on a page
  already left is seen) stays unset, and no element carries an injected handler or
  `javascript:` URL;
- the console shows no Content Security Policy or Trusted Types report: either the app's own
  code is blocked by its CSP (`require-trusted-types-for 'script'; trusted-types 'none'`) or a
  string became markup and only the CSP stopped it; both fail.

Afterwards the API shows no decision, API token or signing key beyond those the test made.
The test runs on its own server so that the hostile strings reach no other test."""

from __future__ import annotations

import json
import re
import sqlite3
from collections.abc import Iterator
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import httpx
import pytest
from playwright.sync_api import Browser, BrowserContext, Frame, Page, expect

from countersign.approvals import dsse

from .conftest import PASSWORD, PATIENCE_MS, ROLES, Server, api_login, running_server
from .test_roles import sign_in

MISSION = "xss-mission"
DECIDER = "decider"
DECIDER_PASSWORD = "xss-dcd-Qz9-long-pass-7"
PAYLOADS = (
    '<img src=x onerror="window.__pwned=1">',
    '<iframe srcdoc="<script>parent.__pwned=1</script>"></iframe>',
    "<script>window.__pwned=1</script>",
    '"><svg onload="window.__pwned=1">',
    "[x](javascript:window.__pwned=1)",
    "![x](javascript:window.__pwned=1)",
    "javascript:window.__pwned=1",
)
ALL = " ".join(PAYLOADS)

# Runs first in every frame: a write to the canary is reported at once, whichever page did it.
TRAP = """(() => {
  let value;
  Object.defineProperty(window, "__pwned", {
    configurable: false,
    get() { return value; },
    set(v) {
      value = v;
      try { window.__reportPwned(String(location.href)); } catch (e) { /* no binding */ }
    },
  });
})();"""

# Injected markup that the CSP or the browser did not run is still a string that became markup.
SCAN = """() => {
  const bad = [];
  const urlAttributes = ["href", "src", "action", "formaction", "xlink:href", "data", "poster",
                         "srcdoc"];
  const walk = (root) => {
    for (const el of root.querySelectorAll("*")) {
      for (const attr of el.attributes) {
        const name = attr.name.toLowerCase();
        const value = attr.value.replace(/[\\s\\u0000-\\u001f]/g, "").toLowerCase();
        if ((name.startsWith("on") && value.includes("__pwned")) ||
            (urlAttributes.includes(name) &&
             (value.startsWith("javascript:") || value.includes("__pwned")))) {
          bad.push(`<${el.tagName.toLowerCase()} ${attr.name}="${attr.value}">`);
        }
      }
      if (el.tagName === "SCRIPT" && (el.textContent || "").includes("__pwned")) {
        bad.push(`<script>${el.textContent}</script>`);
      }
      if (el.shadowRoot) walk(el.shadowRoot);
    }
  };
  walk(document);
  return { pwned: window.__pwned !== undefined, bad: bad.slice(0, 10) };
}"""

BLOCKED = re.compile(r"Trusted Type|TrustedHTML|TrustedScript|Content Security Policy", re.I)


def hostile(label: str) -> str:
    return f"{label} {ALL}"


@dataclass
class Findings:
    """What every page and frame reported; empty when no foreign script ran."""

    pwned: list[str] = field(default_factory=list)
    blocked: list[str] = field(default_factory=list)
    errors: list[str] = field(default_factory=list)
    dialogs: list[str] = field(default_factory=list)
    markup: list[str] = field(default_factory=list)
    pages: list[str] = field(default_factory=list)

    def problems(self) -> list[str]:
        return ([f"canary set on {p}" for p in self.pwned]
                + [f"CSP/Trusted Types report: {b}" for b in self.blocked]
                + self.errors + [f"dialog opened: {d}" for d in self.dialogs] + self.markup)


@pytest.fixture(scope="module")
def xss_server(browser: Browser, tmp_path_factory: pytest.TempPathFactory) -> Iterator[Server]:
    """A server of its own: the hostile strings reach no other test."""
    del browser  # launched (and checked) by the shared fixture
    with running_server(tmp_path_factory.mktemp("countersign-xss"), ROLES) as running:
        yield running


class Api:
    """One signed-in API client (cookie session, CSRF header)."""

    def __init__(self, server: Server, username: str, password: str) -> None:
        self.client = httpx.Client(base_url=server.url, timeout=60)
        login = api_login(self.client, username, password)
        assert login.status_code == 200, login.text
        self.client.headers["X-CSRF-Token"] = login.json()["csrf_token"]

    def call(self, method: str, path: str, expect_status: int = 200, **kwargs: Any) -> Any:
        answer = self.client.request(method, path, **kwargs)
        assert answer.status_code == expect_status, f"{method} {path}: {answer.text}"
        return answer.json() if answer.content else None

    def close(self) -> None:
        self.client.close()


def hostile_orders() -> dict[str, Any]:
    from countersign.orders.examples import example_bytes

    orders: dict[str, Any] = json.loads(example_bytes("search-and-sample"))
    orders["id"] = MISSION
    orders["title"] = hostile("Mission")
    orders["description"] = hostile("Description")
    for goal in orders["goals"]:
        goal["title"] = hostile(f"Goal {goal['id']}")
        goal["description"] = hostile(f"About {goal['id']}")
        if "partner" in goal.get("params", {}):
            goal["params"]["partner"] = hostile("partner")
    for terminal in orders["terminals"]:
        terminal["title"] = hostile(f"Terminal {terminal['id']}")
    for constraint in orders["constraints"]:
        constraint["text"] = hostile(f"Constraint {constraint['id']}")
    for norm in orders["norms"]:
        norm["text"] = hostile(f"Norm {norm['id']}")
    for area in orders["areas"]:
        area["title"] = hostile(f"Area {area['id']}")
        area["contexts"] = [*area["contexts"], PAYLOADS[0]]
    for name, quantity in orders["quantities"].items():
        quantity["title"] = hostile(f"Quantity {name}")
    for vehicle in orders["vehicles"]:
        vehicle["title"] = hostile("Vehicle")
        for feature in vehicle["features"]:
            feature["title"] = hostile(f"Feature {feature['id']}")
    return orders


@dataclass
class Made:
    """What the test itself created, to compare with what exists afterwards."""

    approvals: list[int]
    submissions: dict[int, int]  # version -> submission id


def sign_prepared(prepared: dict[str, Any], key: Any, key_id: str) -> str:
    payload = dsse.unb64(prepared["payload"], "payload")
    signature = key.sign(dsse.pae(dsse.PAYLOAD_TYPE, payload))
    return json.dumps({"payloadType": prepared["payloadType"], "payload": prepared["payload"],
                       "signatures": [{"keyid": key_id, "sig": dsse.b64(signature)}]})


def make_hostile_world(server: Server) -> Made:
    """Every user-controlled field gets script-bearing text, through the API."""
    admin = Api(server, "admin", PASSWORD["admin"])
    operator = Api(server, "operator", PASSWORD["operator"])
    try:
        users = {u["username"]: u for u in admin.call("GET", "/api/users")}
        for index, role in enumerate(ROLES):
            admin.call("PATCH", f"/api/users/{users[role]['id']}",
                       json={"display_name": f"{role} {PAYLOADS[index % len(PAYLOADS)]} "
                                             f"{PAYLOADS[4]}"})
        # A username cannot carry markup at all: refused with a clear 4xx.
        refused = admin.client.post("/api/users", json={
            "username": PAYLOADS[0], "role": "operator", "password": DECIDER_PASSWORD})
        assert 400 <= refused.status_code < 500, refused.text
        assert "username" in refused.text
        admin.call("POST", "/api/users", 201, json={
            "username": DECIDER, "role": "supervisor", "password": DECIDER_PASSWORD,
            "admin_password": PASSWORD["admin"],
            "display_name": f"Decider {PAYLOADS[1]}"})

        # A chart whose title and kind the plan view and the 3D scene show.
        admin.call("POST", "/api/charts/import", json={"format": "geojson", "content": json.dumps(
            {"type": "FeatureCollection", "features": [{
                "type": "Feature", "id": "HOSTILE",
                "properties": {"title": hostile("Chart"), "kind": "keep_out"},
                "geometry": {"type": "Polygon", "coordinates": [[
                    [-121.99, 36.99], [-121.98, 36.99], [-121.98, 37.0], [-121.99, 37.0],
                    [-121.99, 36.99]]]}}]})})
        orders = hostile_orders()
        created = operator.call("POST", "/api/import", 201, content=json.dumps(orders),
                                headers={"Content-Type": "application/json"})
        assert created["id"] == MISSION
        submissions: dict[int, int] = {}

        def new_version(change: str | None) -> int:
            if change is not None:
                mission = operator.call("GET", f"/api/missions/{MISSION}")
                orders["goals"][0 if change == "v2" else 1]["title"] = hostile(f"Changed {change}")
                operator.call("PUT", f"/api/missions/{MISSION}/draft",
                              json={"orders": orders},
                              headers={"If-Match": f'"{mission["revision"]}"'})
            number = int(operator.call("POST", f"/api/missions/{MISSION}/versions", 201)["number"])
            submissions[number] = int(operator.call(
                "POST", f"/api/missions/{MISSION}/versions/{number}/submit", 201)["id"])
            return number

        decider = Api(server, DECIDER, DECIDER_PASSWORD)
        try:
            key = dsse.generate_key()
            key_id = decider.call("POST", "/api/keys", 201, json={
                "public_key": dsse.public_text(key), "name": hostile("key")[:100],
                "password": DECIDER_PASSWORD})["key_id"]

            def decide(submission: int, decision: str, reason: str) -> int:
                prepared = decider.call("POST", f"/api/submissions/{submission}/statement",
                                        json={"decision": decision, "reason": reason,
                                              "key_id": key_id})
                done = decider.call("POST", f"/api/submissions/{submission}/decision", 201,
                                    json={"envelope": sign_prepared(prepared, key, key_id),
                                          "password": DECIDER_PASSWORD})
                return int(done["id"])

            approvals = [decide(submissions[new_version(None)], "rejected",
                                hostile("Rejected because")[:2000])]
            approvals.append(decide(submissions[new_version("v2")], "approved", ""))
            prepared = decider.call("POST", f"/api/approvals/{approvals[1]}/statement",
                                    json={"reason": hostile("Revoked because"),
                                          "key_id": key_id})
            revoked = decider.call("POST", f"/api/approvals/{approvals[1]}/revoke", 201,
                                   json={"envelope": sign_prepared(prepared, key, key_id),
                                         "password": DECIDER_PASSWORD})
            approvals.append(int(revoked["id"]))
            decider.call("POST", f"/api/keys/{key_id}/revoke", json={
                "password": DECIDER_PASSWORD, "reason": hostile("Key revoked because")})
        finally:
            decider.close()
        new_version("v3")  # left submitted: the review page offers the supervisor a decision
        return Made(approvals=approvals, submissions=submissions)
    finally:
        admin.close()
        operator.close()


def tables(server: Server) -> dict[str, int]:
    connection = sqlite3.connect(server.data_dir / "countersign.db", timeout=30)
    try:
        return {t: int(connection.execute(f"SELECT count(*) FROM {t}").fetchone()[0])
                for t in ("approvals", "api_tokens", "signing_keys", "submissions")}
    finally:
        connection.close()


def api_state(server: Server) -> dict[str, Any]:
    """Decisions, keys and every account's API tokens as the API shows them."""
    state: dict[str, Any] = {}
    admin = Api(server, "admin", PASSWORD["admin"])
    try:
        state["approvals"] = sorted(a["id"] for a in
                                    admin.call("GET", "/api/approvals?limit=100")["items"])
        state["keys"] = sorted(k["key_id"] for k in admin.call("GET", "/api/keys"))
        state["submissions"] = sorted((s["id"], s["state"]) for s in
                                      admin.call("GET", f"/api/submissions?mission={MISSION}"))
    finally:
        admin.close()
    for username, password in [*((r, PASSWORD[r]) for r in ROLES), (DECIDER, DECIDER_PASSWORD)]:
        user = Api(server, username, password)
        try:
            state[f"tokens of {username}"] = user.call("GET", "/api/tokens")
        finally:
            user.close()
    return state


def open_context(browser: Browser, server: Server, findings: Findings,
                 opened: list[BrowserContext]) -> Page:
    context = browser.new_context(base_url=server.url, viewport={"width": 1280, "height": 900})
    context.set_default_timeout(PATIENCE_MS)
    opened.append(context)
    context.expose_binding("__reportPwned",
                           lambda source, href: findings.pwned.append(str(href)))
    context.add_init_script(TRAP)
    page = context.new_page()
    page.on("console", lambda m: findings.blocked.append(f"{page.url}: {m.text}")
            if BLOCKED.search(m.text) else None)
    page.on("pageerror", lambda e: findings.errors.append(f"page error on {page.url}: {e}"))

    def dismiss(dialog: Any) -> None:
        findings.dialogs.append(f"{page.url}: {dialog.message}")
        dialog.dismiss()

    page.on("dialog", dismiss)
    return page


def check_frames(page: Page, findings: Findings, where: str) -> None:
    """The canary and the DOM of every frame of the page, now."""
    page.wait_for_timeout(300)  # let handlers of freshly drawn markup fire, if any
    findings.pages.append(where)
    for frame in page.frames:
        result = _scan(frame)
        if result is None:
            continue
        label = f"{where} (frame {frame.url[:120]})"
        if result["pwned"]:
            findings.pwned.append(label)
        findings.markup.extend(f"injected markup on {label}: {m}" for m in result["bad"])


def _scan(frame: Frame) -> dict[str, Any] | None:
    try:
        result: dict[str, Any] = frame.evaluate(SCAN)
    except Exception as exc:  # a frame detached while we looked: nothing left to check
        if frame.is_detached() or "detached" in str(exc) or "destroyed" in str(exc):
            return None
        raise
    return result


def self_test(page: Page, findings: Findings) -> None:
    """The detector itself: a write to the canary is reported by the trap and seen by the
    frame check (then the page is reloaded and the findings cleared)."""
    page.evaluate("() => { window.__pwned = 'self-test'; }")
    for _ in range(100):
        if findings.pwned:
            break
        page.wait_for_timeout(50)
    assert findings.pwned, "the canary trap did not report a write"
    scanned = _scan(page.main_frame)
    assert scanned is not None and scanned["pwned"], "the frame check did not see the canary"
    findings.pwned.clear()
    page.reload()
    expect(page.get_by_test_id("current-role")).to_be_visible()


def visit(page: Page, findings: Findings, path: str, ready: str | None = None) -> None:
    page.goto(path)
    try:
        expect(page.locator("main h1").first).to_be_visible(timeout=60_000)
        expect(page.locator("p.loading")).to_have_count(0, timeout=60_000)
        if ready:
            expect(page.locator(ready).first).to_be_visible(timeout=60_000)
    except AssertionError as exc:
        # A page the CSP broke draws nothing: say why, not only that it did not appear.
        raise AssertionError(f"{path} did not finish drawing: {exc}\nwhat the browser "
                             "reported:\n" + "\n".join(findings.problems())) from None
    check_frames(page, findings, path)


def register_browser_key(page: Page) -> None:
    page.goto("/keys")
    expect(page.get_by_role("heading", name="Signing keys", level=1)).to_be_visible()
    page.get_by_label("Key name").fill(hostile("browser key")[:100])
    page.get_by_label("Confirm your password").fill(PASSWORD["supervisor"])
    page.get_by_role("button", name="Create and register key").click()
    expect(page.get_by_role("status").filter(has_text="registered")).to_be_visible()
    expect(page.get_by_role("cell", name="yes (can sign here)")).to_be_visible()


def rehearse_and_replay(page: Page, findings: Findings) -> None:
    """A live rehearsal (viser's viewer in its sandboxed frame), one outcome, the record and
    its replay: the goal, area and terminal titles reach the 3D scene and its GUI."""
    page.goto(f"/missions/{MISSION}?tab=rehearse")
    page.get_by_test_id("rehearsal-speed").fill("5000")
    page.get_by_test_id("start-rehearsal").click()
    viewer = page.frame_locator('[data-testid="viser-frame"]')
    # Generous timeouts: a viser server and the simulation start on a loaded machine.
    expect(viewer.locator("canvas").first).to_be_visible(timeout=90_000)
    expect(page.get_by_test_id("rehearsal-state")).to_have_text("Waiting for the outcome",
                                                                 timeout=60_000)
    expect(page.get_by_test_id("current-goal")).to_contain_text("Changed v2")
    # The page holds the rehearsal's controls and the goal's title; viser's own
    # panel has none, so the title reaches viser only as scene labels, checked below.
    page.wait_for_timeout(1000)  # the scene's labels arrive
    check_frames(page, findings, "live rehearsal, first goal")
    page.get_by_test_id("outcome-succeed").click()
    expect(page.get_by_test_id("rehearsal-step")).to_have_text("1")
    page.wait_for_timeout(1000)
    check_frames(page, findings, "live rehearsal, second goal")
    page.get_by_test_id("stop-rehearsal").click()
    replay = page.get_by_test_id("rehearsal-records").get_by_role("link", name="Replay")
    expect(replay).to_have_count(1, timeout=60_000)
    check_frames(page, findings, "rehearsal records")
    href = replay.get_attribute("href")
    assert href and href.endswith("/replay.html")
    page.goto(href)
    expect(page.locator("canvas").first).to_be_visible(timeout=60_000)
    page.wait_for_timeout(1500)  # the recorded scene plays
    check_frames(page, findings, "replay")


def test_no_script_the_app_did_not_ship_runs(browser: Browser, xss_server: Server,
                                             tmp_path: Path) -> None:
    server = xss_server
    made = make_hostile_world(server)
    findings = Findings()
    opened: list[BrowserContext] = []
    try:
        supervisor = open_context(browser, server, findings, opened)
        sign_in(supervisor, "supervisor")
        self_test(supervisor, findings)
        register_browser_key(supervisor)
        before_api, before_rows = api_state(server), tables(server)
        assert len(before_api["approvals"]) == len(made.approvals)

        # The supervisor, who could sign here, opens every page.
        visit(supervisor, findings, "/missions", f'a[href="/missions/{MISSION}"]')
        for tab in ("orders", "findings", "paths", "plan", "versions", "rehearse"):
            visit(supervisor, findings, f"/missions/{MISSION}?tab={tab}")
        # The strings did reach the page, as text.
        expect(supervisor.locator("main h1")).to_contain_text(PAYLOADS[0])
        expect(supervisor.get_by_test_id("current-user")).to_contain_text(PAYLOADS[1])
        for number in sorted(made.submissions):
            visit(supervisor, findings, f"/missions/{MISSION}/versions/{number}/review",
                  '[data-testid="review-plain"]')
        expect(supervisor.get_by_role("button", name="Sign approval")).to_be_enabled()
        # The printable approval document of each version, its texts shown.
        for number in sorted(made.submissions):
            visit(supervisor, findings, f"/missions/{MISSION}/versions/{number}/document",
                  '[data-testid="approval-document"] h2')
        expect(supervisor.get_by_test_id("approval-document")).to_contain_text(PAYLOADS[0])
        visit(supervisor, findings, "/vehicles")
        visit(supervisor, findings, "/reviews")
        visit(supervisor, findings, "/keys")
        visit(supervisor, findings, f"/audit?mission={MISSION}")
        for approval in made.approvals:
            visit(supervisor, findings, f"/audit/{approval}")
            expect(supervisor.get_by_test_id("verification-verdict")).to_have_text(
                re.compile("passed|failed"), timeout=60_000)
            check_frames(supervisor, findings, f"/audit/{approval} verified")
        visit(supervisor, findings, "/events")
        visit(supervisor, findings, "/no-such-page")
        rehearse_and_replay(supervisor, findings)

        # The operator's editors, the admin's users page, the auditor's record page.
        operator = open_context(browser, server, findings, opened)
        sign_in(operator, "operator")
        visit(operator, findings, f"/missions/{MISSION}?tab=edit")
        visit(operator, findings, f"/missions/{MISSION}?tab=editor", ".react-flow__node")
        visit(operator, findings, f"/missions/{MISSION}/versions/3/review")
        visit(operator, findings, "/import")
        admin = open_context(browser, server, findings, opened)
        sign_in(admin, "admin")
        visit(admin, findings, "/users", "table")
        visit(admin, findings, "/events")
        auditor = open_context(browser, server, findings, opened)
        sign_in(auditor, "auditor")
        visit(auditor, findings, f"/audit/{made.approvals[-1]}")
        expect(auditor.get_by_test_id("verification-verdict")).to_have_text(
            re.compile("passed|failed"), timeout=60_000)
        check_frames(auditor, findings, "auditor's record page, verified")
    finally:
        for context in opened:
            context.close()

    problems = findings.problems()
    assert not problems, (f"{len(problems)} problems over {len(findings.pages)} pages:\n"
                          + "\n".join(problems))
    # Nothing was decided, minted or registered behind the test's back (the rehearsal record
    # the supervisor made is not a decision).
    after_rows = tables(server)
    assert after_rows == before_rows
    assert api_state(server) == before_api
