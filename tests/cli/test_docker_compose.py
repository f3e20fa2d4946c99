"""docker-compose.yml cannot be run here (no Docker engine), so its parts are checked for what
would break it: every `countersign` command it runs parses with the real command line, every
service that talks to PostgreSQL gets the same database URL, and campaigns have a worker."""

from __future__ import annotations

import re
from pathlib import Path
from typing import Any

import pytest
import yaml

from countersign.cli import build_parser

ROOT = Path(__file__).resolve().parents[2]


def _compose() -> dict[str, Any]:
    data: dict[str, Any] = yaml.safe_load((ROOT / "docker-compose.yml").read_text())
    return data


def _dockerfile_cmd() -> list[str]:
    line = next(x for x in (ROOT / "Dockerfile").read_text().splitlines() if x.startswith("CMD"))
    return re.findall(r'"([^"]*)"', line)


@pytest.mark.parametrize("service", ["app", "campaign-worker"])
def test_each_service_runs_a_command_the_cli_accepts(service: str) -> None:
    spec = _compose()["services"][service]
    command = spec.get("command") or _dockerfile_cmd()
    assert command[0] == "countersign"
    try:
        args = build_parser().parse_args(command[1:])
    except SystemExit as exc:  # argparse's way of refusing
        pytest.fail(f"{service}: `{' '.join(command)}` is refused by the CLI ({exc.code})")
    assert callable(args.handler)


def test_the_workers_share_the_apps_database_and_data() -> None:
    services = _compose()["services"]
    app, worker = services["app"], services["campaign-worker"]
    assert worker["environment"]["COUNTERSIGN_DATABASE_URL"] \
        == app["environment"]["COUNTERSIGN_DATABASE_URL"]
    assert worker["volumes"] == app["volumes"]
    assert worker["depends_on"]["db"]["condition"] == "service_healthy"
