"""The built browser app's files: client-side routes fall back to index.html, and no path a
client sends (encoded dots, a NUL, a symlink) reaches a file outside the build or a 500."""

from __future__ import annotations

from pathlib import Path

import pytest
from fastapi.testclient import TestClient

from countersign.settings import Settings
from countersign.web.app import create_app

from .conftest import World

INDEX = "<!doctype html><title>app</title>"
SECRET = "not for the browser"


@pytest.fixture
def served(world: World, tmp_path: Path) -> TestClient:
    dist = tmp_path / "dist"
    (dist / "assets").mkdir(parents=True)
    (dist / "index.html").write_text(INDEX)
    (dist / "assets" / "app-1234.js").write_text("console.log(1)")
    (tmp_path / "secret.txt").write_text(SECRET)
    (dist / "outside.txt").symlink_to(tmp_path / "secret.txt")
    settings = Settings(data_dir=tmp_path / "data", database_url=str(world.database.engine.url),
                        frontend_dist=dist)
    return TestClient(create_app(settings, world.database), raise_server_exceptions=False)


@pytest.mark.parametrize("path", [
    "/%00", "/assets/%00.js", "/missions/a%00b", "/..%2fsecret.txt", "/%2e%2e/secret.txt",
    "/assets/..%2f..%2fsecret.txt", "/outside.txt", "/%2e%2e%2f%2e%2e%2fetc%2fpasswd",
])
def test_hostile_paths_get_the_app_never_another_file_or_a_500(served: TestClient,
                                                                path: str) -> None:
    response = served.get(path)
    assert response.status_code == 200, (path, response.status_code, response.text[:200])
    assert response.text == INDEX, path


def test_assets_and_client_routes_are_served(served: TestClient) -> None:
    asset = served.get("/assets/app-1234.js")
    assert asset.text == "console.log(1)" and "immutable" in asset.headers["cache-control"]
    assert served.get("/missions/search-and-sample?tab=versions").text == INDEX
    assert served.head("/").status_code == 200
