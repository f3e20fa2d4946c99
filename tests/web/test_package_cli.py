"""`countersign package` against a real server, then `countersign vehicle verify` offline."""

from __future__ import annotations

from pathlib import Path

import pytest

from countersign.cli import main

from .approval_helpers import MISSION, approve, new_version, register_key, submit
from .conftest import World


def test_package_downloads_and_verifies_offline(world: World, server: str, tmp_path: Path,
                                                capsys: pytest.CaptureFixture[str]) -> None:
    supervisor = world.client("supervisor")
    number = new_version(world)
    token = tmp_path / "token"
    token.write_text(world.tokens["auditor"])
    target = tmp_path / "p.tar"
    common = ["--server", server, "--token-file", str(token), "-o", str(target)]
    assert main(["package", MISSION, str(number), *common]) == 1  # not approved
    assert "no standing approval" in capsys.readouterr().err
    approve(world, supervisor, register_key(supervisor), submit(world, number))
    assert main(["package", MISSION, str(number), *common]) == 0
    log_key = world.client("auditor").get("/api/log/checkpoint").json()["public_key"]
    capsys.readouterr()
    assert main(["vehicle", "verify", str(target), "--log-key", log_key]) == 0
    assert capsys.readouterr().out.startswith(f"OK {MISSION} version {number}: approved")
