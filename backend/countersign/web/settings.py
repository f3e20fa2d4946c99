"""Settings of the web app, read once from the environment."""

from __future__ import annotations

import os
from dataclasses import dataclass
from pathlib import Path

from platformdirs import user_data_dir

from .map_tiles import checked_template

FRONTEND_DIST = Path(__file__).resolve().parents[3] / "frontend" / "dist"


@dataclass(frozen=True)
class Settings:
    data_dir: Path
    database_url: str
    secure_cookies: bool = False
    max_body_bytes: int = 9 * 1024 * 1024
    frontend_dist: Path = FRONTEND_DIST
    # Processes that validate orders beside each server process (0: in the server's threads).
    # Two, so that one user's heavy validation leaves one for another's edit (validation_pool).
    validation_processes: int = 2
    # Map tiles under the plan view (map_tiles.py): a checked URL template, or None (offline).
    map_tiles: str | None = None
    map_tiles_attribution: str = ""

    @classmethod
    def from_environment(cls, data_dir: Path | None = None) -> Settings:
        chosen = data_dir or Path(
            os.environ.get("COUNTERSIGN_DATA_DIR") or user_data_dir("countersign", appauthor=False)
        )
        chosen = chosen.expanduser().resolve()
        url = os.environ.get("COUNTERSIGN_DATABASE_URL") or f"sqlite:///{chosen / 'countersign.db'}"
        secure = os.environ.get("COUNTERSIGN_SECURE_COOKIES", "").lower() in {"1", "true", "yes"}
        processes = os.environ.get("COUNTERSIGN_VALIDATION_PROCESSES", "2")
        if not processes.isdigit() or int(processes) > 64:
            raise ValueError("COUNTERSIGN_VALIDATION_PROCESSES must be a whole number from 0 "
                             f"to 64, not {processes!r}")
        tiles = os.environ.get("COUNTERSIGN_MAP_TILES", "").strip()
        attribution = os.environ.get("COUNTERSIGN_MAP_TILES_ATTRIBUTION", "").strip()[:200]
        return cls(data_dir=chosen, database_url=url, secure_cookies=secure,
                   validation_processes=int(processes),
                   map_tiles=checked_template(tiles) if tiles else None,
                   map_tiles_attribution=attribution)

    def __post_init__(self) -> None:
        if self.map_tiles is not None:
            checked_template(self.map_tiles)

    def prepare(self) -> None:
        self.data_dir.mkdir(parents=True, exist_ok=True, mode=0o700)
