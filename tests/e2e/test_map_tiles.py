"""Map tiles under the plan view: with COUNTERSIGN_MAP_TILES the browser draws tiles
from that server, which the page's CSP allows; without it no tile is requested at all. The tile
server is a tiny HTTP server of this test on loopback, serving one PNG for every tile."""

from __future__ import annotations

import json
import struct
import threading
import urllib.request
import uuid
import zlib
from collections.abc import Iterator
from dataclasses import dataclass, field
from http.server import BaseHTTPRequestHandler, ThreadingHTTPServer

import pytest
from playwright.sync_api import Browser, expect

from .conftest import PASSWORD, PATIENCE_MS, Server, _api_import, running_server, submit_sign_in

PLAN = "Plan view: areas, charts and legs"


def _png() -> bytes:
    """A 1x1 blue PNG."""
    def chunk(kind: bytes, data: bytes) -> bytes:
        return (struct.pack(">I", len(data)) + kind + data
                + struct.pack(">I", zlib.crc32(kind + data)))
    header = struct.pack(">IIBBBBB", 1, 1, 8, 2, 0, 0, 0)
    return (b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", header)
            + chunk(b"IDAT", zlib.compress(b"\x00\x40\x80\xff")) + chunk(b"IEND", b""))


@dataclass
class TileServer:
    origin: str
    requests: list[str] = field(default_factory=list)


@pytest.fixture(scope="module")
def tile_server() -> Iterator[TileServer]:
    png = _png()
    seen: list[str] = []

    class Tiles(BaseHTTPRequestHandler):
        def do_GET(self) -> None:
            seen.append(self.path)
            self.send_response(200)
            self.send_header("Content-Type", "image/png")
            self.send_header("Content-Length", str(len(png)))
            self.end_headers()
            self.wfile.write(png)

        def log_message(self, *_args: object) -> None:
            pass

    httpd = ThreadingHTTPServer(("127.0.0.1", 0), Tiles)
    thread = threading.Thread(target=httpd.serve_forever, daemon=True)
    thread.start()
    try:
        yield TileServer(f"http://127.0.0.1:{httpd.server_address[1]}", seen)
    finally:
        httpd.shutdown()
        httpd.server_close()


@pytest.fixture(scope="module")
def tiled_server(tmp_path_factory: pytest.TempPathFactory, server: Server,
                 tile_server: TileServer) -> Iterator[Server]:
    data_dir = tmp_path_factory.mktemp("countersign-tiles-e2e")
    template = f"{tile_server.origin}/{{z}}/{{x}}/{{y}}.png"
    with running_server(data_dir, ["operator"], {"COUNTERSIGN_MAP_TILES": template}) as running:
        yield running


def _plan_requests(browser: Browser, server: Server) -> tuple[list[str], str | None]:
    """Every URL the browser asked for while showing the exemplar's plan view, and whether its
    map draws a tile layer ("on"/"off")."""
    from countersign.orders.examples import example_bytes

    orders = json.loads(example_bytes("search-and-sample"))
    orders["id"] = f"tiles-{uuid.uuid4().hex[:8]}"  # the shared server may hold the exemplar
    mission = _api_import(server, json.dumps(orders).encode(), "application/json")
    context = browser.new_context(base_url=server.url)
    context.set_default_timeout(PATIENCE_MS)
    page = context.new_page()
    asked: list[str] = []
    page.on("request", lambda request: asked.append(request.url))
    try:
        page.goto("/")
        submit_sign_in(page, "operator", PASSWORD["operator"])
        expect(page.get_by_test_id("current-role")).to_have_text("Operator")
        page.goto(f"/missions/{mission}?tab=plan")
        plan = page.get_by_role("region", name=PLAN)
        expect(plan).to_have_attribute("data-ready", "true")
        expect(plan.locator("[data-leg]").first).to_be_attached()
        page.wait_for_load_state("networkidle")
        return asked, plan.get_attribute("data-tiles")
    finally:
        context.close()


def test_configured_tiles_are_drawn_under_the_plan_view(
        browser: Browser, tiled_server: Server, tile_server: TileServer) -> None:
    with urllib.request.urlopen(tiled_server.url + "/") as answer:
        csp = answer.headers["Content-Security-Policy"]
    assert f"img-src 'self' data: {tile_server.origin};" in csp
    assert f"connect-src 'self' {tile_server.origin};" in csp
    asked, layer = _plan_requests(browser, tiled_server)
    tiles = [url for url in asked if url.startswith(tile_server.origin)]
    assert layer == "on" and len(tiles) > 0, (layer, tiles)
    assert all(url.endswith(".png") and len(url.split("/")) == 6 for url in tiles), tiles
    # The tile server answered them (the CSP let MapLibre's fetches through).
    assert len(tile_server.requests) > 0


def test_without_configured_tiles_none_is_requested(browser: Browser, server: Server) -> None:
    asked, layer = _plan_requests(browser, server)
    assert layer == "off"
    assert all(url.startswith(server.url) for url in asked), [
        url for url in asked if not url.startswith(server.url)]
