"""The map tile template (COUNTERSIGN_MAP_TILES) is checked when the server starts, and the
page's CSP allows images from exactly the configured origin."""

from __future__ import annotations

from pathlib import Path

import pytest
from fastapi.testclient import TestClient

from countersign.map_tiles import checked_template, tile_origin
from countersign.settings import Settings
from countersign.web.app import create_app

GOOD = "https://tiles.example.org/osm/{z}/{x}/{y}.png"


@pytest.mark.parametrize("template", [
    GOOD, "https://tiles.example.org:8443/{z}/{y}/{x}.png?style=sea",
    "http://127.0.0.1:8080/{z}/{x}/{y}.png", "http://localhost/{z}/{x}/{y}"])
def test_usable_templates_are_kept(template: str) -> None:
    assert checked_template(template) == template


@pytest.mark.parametrize(("template", "problem"), [
    ("http://tiles.example.org/{z}/{x}/{y}.png", "must be https"),
    ("ftp://tiles.example.org/{z}/{x}/{y}.png", "https:// URL with a host"),
    ("javascript:alert(1)//{z}/{x}/{y}", "https:// URL with a host"),
    ("https:///{z}/{x}/{y}.png", "https:// URL with a host"),
    ("https://tiles.example.org/{z}/{x}.png", "{y}"),
    ("https://tiles.example.org/{z}/{x}/{y}/{z}.png", "{z}"),
    ("https://tiles.example.org/{s}/{z}/{x}/{y}.png", "braces other than"),
    ("https://user:secret@tiles.example.org/{z}/{x}/{y}.png", "user name or password"),
    ("https://tiles.example.org/{z}/{x}/{y}.png#top", "fragment"),
    ("https://tiles.example.org/{z}/{x}/{y}.png' 'unsafe-inline", "quotes"),
    ("https://tiles.example.org:99999/{z}/{x}/{y}.png", "not a URL"),
    ("https://tiles.example.org/" + "a" * 500 + "/{z}/{x}/{y}", "longer than"),
])
def test_unusable_templates_are_refused_naming_the_problem(template: str, problem: str) -> None:
    with pytest.raises(ValueError, match="COUNTERSIGN_MAP_TILES") as refused:
        checked_template(template)
    assert problem in str(refused.value)


def test_the_environment_setting_is_checked_at_start(monkeypatch: pytest.MonkeyPatch,
                                                     tmp_path: Path) -> None:
    monkeypatch.setenv("COUNTERSIGN_MAP_TILES", "http://tiles.example.org/{z}/{x}/{y}.png")
    with pytest.raises(ValueError, match="must be https"):
        Settings.from_environment(tmp_path)
    monkeypatch.setenv("COUNTERSIGN_MAP_TILES", GOOD)
    assert Settings.from_environment(tmp_path).map_tiles == GOOD
    monkeypatch.delenv("COUNTERSIGN_MAP_TILES")
    assert Settings.from_environment(tmp_path).map_tiles is None


def _csp_and_config(tmp_path: Path, tiles: str | None) -> tuple[str, object]:
    settings = Settings(data_dir=tmp_path, database_url=f"sqlite:///{tmp_path / 'db'}",
                        map_tiles=tiles)
    client = TestClient(create_app(settings))
    csp = client.get("/api/health").headers["Content-Security-Policy"]
    return csp, client.get("/api/client-config").status_code


def test_the_csp_allows_images_and_fetches_from_the_tile_origin_only(tmp_path: Path) -> None:
    csp, _ = _csp_and_config(tmp_path / "tiles", GOOD)
    assert tile_origin(GOOD) == "https://tiles.example.org"
    assert "img-src 'self' data: https://tiles.example.org;" in csp
    # MapLibre fetches tiles (fetch, then an ImageBitmap): the origin is allowed to connect too.
    assert "connect-src 'self' https://tiles.example.org;" in csp
    offline, status = _csp_and_config(tmp_path / "offline", None)
    assert "img-src 'self' data:;" in offline
    assert "connect-src" not in offline  # default-src 'self': the app's own origin only
    assert status == 401  # the setting is for signed-in users, as every other API route
