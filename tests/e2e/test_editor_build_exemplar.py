"""Acceptance: an operator builds the built-in exemplar in the graph editor.

In headless Chromium, with only mouse and keyboard (clicks, drags, typing into labelled
fields), the operator starts an empty mission and enters everything `search-and-sample`
contains: mission fields, quantities, the vehicle profile and its features, the areas with
their polygons and contexts, goals G1-G5 with behaviours, areas, requirements, envelopes,
parameters and costs, the constraints C1-C7 (text, expression, scope) and the norm. The wiring
plants a loop and an unreachable goal; the operator sees their findings on the right nodes and
edges, fixes them, reaches 75 paths, undoes and redoes, and exports JSON whose digest equals
the built-in exemplar's. The mission is built on a server of its own, so that the id
`search-and-sample` is free whatever other browser tests imported.
"""

from __future__ import annotations

import json
import re
import time
from collections.abc import Iterator
from pathlib import Path

import pytest
from playwright.sync_api import Browser, Locator, Page, expect

from .conftest import Server, _fresh_page, keep_failure_shot, running_server
from .test_editor import choose_next, drag_connect, edge, pick, select_node
from .test_roles import sign_in

EXAMPLE = "search-and-sample"


@pytest.fixture(scope="module")
def own_server(server: Server, tmp_path_factory: pytest.TempPathFactory) -> Iterator[Server]:
    """A second real server on a fresh data directory (the shared one may hold the exemplar)."""
    del server  # the shared server's checks (prerequisites) ran first
    data_dir = tmp_path_factory.mktemp("countersign-e2e-build")
    with running_server(data_dir, ["operator"]) as running:
        yield running


@pytest.fixture()
def own_page(browser: Browser, own_server: Server, request: pytest.FixtureRequest,
             tmp_path_factory: pytest.TempPathFactory) -> Iterator[Page]:
    with _fresh_page(browser, own_server, {"width": 1280, "height": 900},
                     accept_downloads=True) as opened:
        yield opened
        keep_failure_shot(opened, request, tmp_path_factory)


def exemplar() -> dict:
    from countersign.orders.examples import example_bytes

    data: dict = json.loads(example_bytes(EXAMPLE))
    return data


def digest_of(data: dict) -> str:
    from countersign.orders.canonical import digest
    from countersign.orders.reader import orders_from_data

    return digest(orders_from_data(data))


def panel(page: Page, name: str) -> None:
    tab = page.get_by_role("tab", name=name, exact=True)
    tab.click()
    expect(tab).to_have_attribute("aria-selected", "true")


def commit(field: Locator, text: str) -> None:
    """Types into a field that commits on Enter (inputs) or when focus leaves (textareas)."""
    field.fill(text)
    field.press("Tab")


def fmt(value: float) -> str:
    return repr(value) if isinstance(value, float) else str(value)


def saved(page: Page) -> None:
    expect(page.get_by_test_id("save-state")).to_have_text("Saved")


def test_operator_builds_the_exemplar_by_mouse_and_keyboard(own_page: Page) -> None:
    page = own_page
    spec = exemplar()
    vehicle = spec["vehicles"][0]
    sign_in(page, "operator")
    page.get_by_role("link", name="Import", exact=True).click()
    page.get_by_label("Mission id").fill(EXAMPLE)
    page.get_by_label("Title", exact=True).fill(spec["title"])
    page.get_by_role("button", name="Create empty mission").click()
    expect(page.get_by_role("tab", name="Graph editor")).to_have_attribute("aria-selected", "true")
    expect(page.get_by_test_id("node-COMPLETE")).to_be_visible()

    # ---- Mission fields ----
    panel(page, "Mission")
    page.get_by_label("Mission description").fill(spec["description"])
    # The vehicle is not in the registry: its profile comes with these orders (below).
    pick(page, "Target vehicle", "", option="Other id")
    vehicle_field = page.get_by_label("Target vehicle (id)")
    vehicle_field.fill(spec["vehicle"])
    vehicle_field.press("Enter")
    saved(page)

    # ---- Quantities ----
    panel(page, "Quantities")
    for name, q in spec["quantities"].items():
        page.get_by_label("New quantity name").fill(name)
        page.get_by_role("button", name="Add quantity").click()
        expect(page.get_by_label(f"{name} title")).to_be_visible()
        page.get_by_label(f"{name} title").fill(q["title"])
        if "type" in q:
            page.get_by_label(f"{name} type").select_option(q["type"])
        if "unit" in q:
            page.get_by_label(f"{name} unit").fill(q["unit"])
        if "min" in q:
            page.get_by_label(f"{name} min", exact=True).fill(fmt(q["min"]))
    saved(page)

    # ---- Vehicle profile and features ----
    panel(page, "Vehicle")
    page.get_by_role("button", name="Add vehicle profile").click()
    expect(page.get_by_label("Vehicle id")).to_have_value(vehicle["id"])
    page.get_by_label("Vehicle title").fill(vehicle["title"])
    commit(page.get_by_label("Trusted behaviours (comma-separated)"),
           ", ".join(vehicle["behaviors"]))
    commit(page.get_by_label(re.compile("^Vehicle envelope")),
           "\n".join(f"{q} {lo} {hi}" for q, (lo, hi) in vehicle["envelope"].items()))
    page.get_by_label("Speed (m/s)").fill(fmt(vehicle["speed_mps"]))
    page.get_by_label("Power (W)").fill(fmt(vehicle["power_w"]))
    page.get_by_label("Energy budget (Wh)").fill(fmt(vehicle["budget"]["energy_wh"]))
    page.get_by_label("Time budget (s)").fill(fmt(vehicle["budget"]["duration_s"]))
    for feature in vehicle["features"]:
        page.get_by_role("button", name="Add feature").click()
        placeholder = "feature-1"  # the first free id (the previous one was renamed)
        id_field = page.get_by_label(f"Feature {placeholder} id")
        id_field.fill(feature["id"])
        id_field.press("Enter")
        fid = feature["id"]
        page.get_by_label(f"Feature {fid} title").fill(feature["title"])
        if feature["fulfills"]:
            commit(page.get_by_label(re.compile(rf"^Feature {fid} fulfils")),
                   ", ".join(feature["fulfills"]))
        if feature["measures"]:
            commit(page.get_by_label(re.compile(rf"^Feature {fid} measures")),
                   ", ".join(feature["measures"]))
    saved(page)

    # ---- Areas: id, title, contexts, polygon vertices (mouse adds rows, keyboard types) ----
    panel(page, "Areas")
    for area in spec["areas"]:
        page.get_by_role("button", name="Add area").click()
        id_field = page.get_by_label("Area id")
        expect(id_field).to_have_value(re.compile("^AREA"))
        id_field.fill(area["id"])
        id_field.press("Enter")
        expect(page.locator(".areas-panel legend")).to_contain_text(area["id"])
        page.get_by_label("Area title").fill(area["title"])
        commit(page.get_by_label("Context tags (comma-separated)"), ", ".join(area["contexts"]))
        for n, (lat, lon) in enumerate(area["polygon"], start=1):
            page.get_by_role("button", name="Add vertex").click()
            page.get_by_label(f"Vertex {n} latitude").fill(fmt(lat))
            page.get_by_label(f"Vertex {n} longitude").fill(fmt(lon))
        expect(page.get_by_test_id(f"plan-area-{area['id']}")).to_have_attribute(
            "data-vertices", str(len(area["polygon"])))
    expect(page.get_by_test_id("area-chart")).to_contain_text("shipping_lane")
    saved(page)

    # ---- Goals: add, then fill the inspector ----
    for number, goal in enumerate(spec["goals"], start=1):
        page.get_by_role("button", name="Add goal").click()
        expect(page.locator(".inspector legend").first).to_contain_text(f"G{number}")
        assert goal["id"] == f"G{number}"
        page.get_by_label("Title", exact=True).fill(goal["title"])
        pick(page, "Behaviour", goal["behavior"])
        page.get_by_label("Area", exact=True).select_option(goal["area"])
        commit(page.get_by_label("Requires (comma-separated)"), ", ".join(goal["requires"]))
        commit(page.get_by_label(re.compile("^Envelope")),
               "\n".join(f"{q} {lo} {hi}" for q, (lo, hi) in goal["envelope"].items()))
        if "params" in goal:
            commit(page.get_by_label(re.compile("^Parameters")),
                   "\n".join(f"{k} {v}" for k, v in goal["params"].items()))
        page.get_by_label("Energy (Wh)").fill(fmt(goal["cost"]["energy_wh"]))
        page.get_by_label("Duration (s)").fill(fmt(goal["cost"]["duration_s"]))
        expect(page.get_by_test_id(f"node-G{number}")).to_contain_text(goal["title"])
    saved(page)

    # ---- Constraints: text, expression (with completion), scope by clicking goals ----
    panel(page, "Constraints")
    for constraint in spec["constraints"]:
        cid = constraint["id"]
        page.get_by_test_id("add-constraint").click()
        page.get_by_label(f"{cid} text").fill(constraint["text"])
        expr = page.get_by_label(f"{cid} expression", exact=True)
        if cid == "C4":
            # Completion: type the start of a quantity, accept it with Tab, type on.
            expr.click()
            page.keyboard.type("lane_dis")
            listbox = page.get_by_role("listbox", name=f"Completions for {cid} expression")
            expect(listbox).to_be_visible()
            page.keyboard.press("Tab")
            expect(expr).to_have_value("lane_distance_m")
            page.keyboard.type(" >= 1000 or depth_m >= 20")
            expect(expr).to_have_value(constraint["expr"])
        else:
            # An inline parse error first, then the right text.
            expr.fill(constraint["expr"] + " >=")
            expect(page.get_by_test_id(f"c-{cid}-expr-error")).to_contain_text("Column")
            expr.fill(constraint["expr"])
        expect(page.get_by_test_id(f"c-{cid}-expr-error")).to_have_text("")
        if constraint["applies_to"] != "mission":
            page.get_by_label(f"{cid} applies to the whole mission").uncheck()
            for goal in constraint["applies_to"]:
                page.get_by_label(re.compile(rf"^{cid} applies to {goal}( |$)")).check()
    saved(page)

    # ---- Norms ----
    panel(page, "Norms")
    for norm in spec["norms"]:
        page.get_by_role("button", name="Add norm").click()
        nid = norm["id"]
        page.get_by_label(f"Norm {nid} context").fill(norm["context"])
        page.get_by_label(f"Norm {nid} kind").select_option("forbidden")
        page.get_by_label(f"Norm {nid} expression", exact=True).fill(norm["forbidden"])
        page.get_by_label(f"Norm {nid} text").fill(norm["text"])
    saved(page)

    # ---- Wiring: mouse drags and inspector selects, with a planted loop and orphan ----
    page.get_by_role("button", name="Auto layout").click()
    expect(page.get_by_test_id("editor-canvas")).to_have_attribute("data-ready", "true")
    saved(page)
    for source, outcome, target in [
        ("G1", "succeed", "G2"), ("G1", "fail", "G3"), ("G2", "succeed", "G3"),
        ("G3", "succeed", "G1"),  # planted loop
        ("G4", "succeed", "G5"), ("G5", "succeed", "COMPLETE"),
    ]:
        drag_connect(page, source, outcome, target)
        expect(edge(page, source, outcome, target)).to_have_count(1)
    for goal, outcome, target in [
        ("G1", "violate", "G5"),  # planted: G4 is then reachable from nowhere
        ("G2", "fail", "G5"), ("G2", "violate", "G5"),
        ("G3", "fail", "G1"), ("G3", "violate", "G1"),
        ("G4", "fail", "G5"), ("G4", "violate", "G5"),
        ("G5", "fail", "ABORT"), ("G5", "violate", "ABORT"),
    ]:
        choose_next(page, goal, outcome, target)
    saved(page)

    # The loop is marked on its goals and edges; the orphan on G4.
    expect(page.get_by_test_id("markers-G1")).to_contain_text("G7")
    expect(page.get_by_test_id("markers-G3")).to_contain_text("G7")
    expect(page.get_by_test_id("markers-G4")).to_contain_text("G10")
    expect(page.get_by_test_id("markers-G2")).to_contain_text("G7")  # G1 -> G2 -> G3 -> G1
    expect(page.get_by_test_id("markers-G5")).to_have_count(0)
    # A loop is drawn once, as a halo under its edges, not as a "G7" label on each.
    loop_edge = page.locator('.react-flow__edge[data-id="G3:succeed:G1"]')
    expect(loop_edge).to_have_class(re.compile("edge-loop"))
    expect(loop_edge.locator(".loop-halo")).to_have_count(1)
    expect(loop_edge).not_to_contain_text("G7")
    expect(page.locator('.react-flow__edge[data-id="G1:violate:G5"]')).not_to_have_class(re.compile("edge-loop"))
    expect(page.get_by_test_id("editor-verdict")).to_contain_text("Not valid")
    # The inspector field of the loop carries the finding; a finding selects its subject.
    select_node(page, "G3")
    expect(page.get_by_test_id("field-findings-G3")).to_contain_text("G7")
    page.get_by_test_id("editor-findings").get_by_role("button", name=re.compile("G10")).click()
    expect(page.locator(".inspector legend").first).to_contain_text("G4")

    # ---- Fix both with the inspector's selects (keyboard) ----
    for goal, outcome in [("G3", "succeed"), ("G3", "fail"), ("G3", "violate"), ("G1", "violate")]:
        choose_next(page, goal, outcome, "G4")
    expect(page.get_by_test_id("markers-G1")).to_have_count(0)
    started = time.monotonic()
    choose_next(page, "G2", "violate", "G4")
    expect(page.get_by_test_id("editor-verdict")).to_contain_text("75 paths")
    elapsed = (time.monotonic() - started) * 1000
    print(f"built exemplar: last edit -> 75 paths shown {elapsed:.0f} ms "
          f"(app: {page.get_by_test_id('check-time').inner_text().strip()})")
    expect(page.get_by_test_id("editor-verdict")).to_contain_text("Valid: 0 errors")
    expect(page.get_by_test_id("markers-G4")).to_have_count(0)
    saved(page)

    # ---- Undo and redo (canvas shortcuts) ----
    page.get_by_test_id("editor-canvas").focus()
    page.keyboard.press("Control+z")
    expect(edge(page, "G2", "violate", "G5")).to_have_count(1)
    expect(page.get_by_test_id("editor-verdict")).not_to_contain_text("75 paths")
    page.keyboard.press("Control+Shift+z")
    expect(edge(page, "G2", "violate", "G4")).to_have_count(1)
    expect(page.get_by_test_id("editor-verdict")).to_contain_text("75 paths")
    saved(page)

    # ---- Paths explorer: counts, the list, one path highlighted with its trace ----
    panel(page, "Path explorer")
    expect(page.get_by_test_id("paths-counts")).to_contain_text("75 paths")
    expect(page.get_by_test_id("paths-counts")).to_contain_text("25 to COMPLETE")
    page.get_by_role("button", name="List paths").click()
    first = page.get_by_role("option", name=re.compile(r"^Path 1: "))
    expect(first).to_be_visible()
    # Chosen from the keyboard (the list's own arrow keys), as an operator without a mouse would.
    page.get_by_test_id("editor-path-list").focus()
    page.keyboard.press("ArrowDown")
    expect(page.get_by_test_id("path-trace")).to_contain_text("Commence: Search Area A.")
    expect(page.get_by_test_id("highlight-note")).to_be_visible()
    expect(page.locator(".react-flow__edge.edge-on-path")).not_to_have_count(0)

    # ---- Export JSON and compare digests (positions are not in the orders) ----
    page.locator(".editor-toolbar summary", has_text="More").click()
    page.locator(".export-menu summary").click()
    with page.expect_download() as download:
        page.get_by_test_id("editor-export-json").click()
    exported = json.loads(Path(download.value.path()).read_text())
    assert "layout" not in exported
    built = digest_of(exported)
    expected = digest_of(spec)
    if built != expected:
        for key in spec:
            if json.dumps(spec[key], sort_keys=True) != json.dumps(exported.get(key),
                                                                   sort_keys=True):
                print(f"differs: {key}: {json.dumps(exported.get(key))[:400]}")
    assert built == expected
    print(f"exported digest {built} equals the built-in exemplar's")
