"""Where the server's log signer keeps its key: its own directory, never the database."""

from __future__ import annotations

import os
from pathlib import Path

from ..approvals.signer import LogSigner
from .settings import Settings

LOG_KEY_DIR_ENV = "COUNTERSIGN_LOG_KEY_DIR"


def signer_directory(settings: Settings) -> Path:
    """COUNTERSIGN_LOG_KEY_DIR, or `log-signer/` in the data directory."""
    chosen = os.environ.get(LOG_KEY_DIR_ENV)
    return Path(chosen) if chosen else settings.data_dir / "log-signer"


def open_log_signer(settings: Settings) -> LogSigner:
    """The signer (its key created on first use); SignerError on a key file others may read."""
    return LogSigner(signer_directory(settings))
