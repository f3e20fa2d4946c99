"""Where the server's log signer keeps its key: its own directory, never the database."""

from __future__ import annotations

import os
from pathlib import Path

from ..approvals.signer import LegacyKey, LogSigner
from ..store.db import Database
from ..store.log_adoption import adopt_pre_receipt_log
from .settings import Settings

LOG_KEY_DIR_ENV = "COUNTERSIGN_LOG_KEY_DIR"
# Where the log key lived before the signer had its own directory (imported on upgrade).
LEGACY_KEY_ENV = "COUNTERSIGN_LOG_KEY"
LEGACY_KEY_FILE = "log-signing-key.pem"


def signer_directory(settings: Settings) -> Path:
    """COUNTERSIGN_LOG_KEY_DIR, or `log-signer/` in the data directory."""
    chosen = os.environ.get(LOG_KEY_DIR_ENV)
    return Path(chosen) if chosen else settings.data_dir / "log-signer"


def legacy_key(settings: Settings) -> LegacyKey | None:
    """The log key of an older deployment: the PEM in COUNTERSIGN_LOG_KEY, or the key file
    it made in the data directory."""
    pem = os.environ.get(LEGACY_KEY_ENV)
    if pem:
        return LegacyKey(pem.encode(), LEGACY_KEY_ENV)
    path = settings.data_dir / LEGACY_KEY_FILE
    try:
        return LegacyKey(path.read_bytes(), str(path), path)
    except FileNotFoundError:
        return None


def open_log_signer(settings: Settings, database: Database | None = None) -> LogSigner:
    """The signer (its key created on first use, or imported from an older deployment);
    SignerError on a key file others may read. With the database, a log appended before
    receipts existed is adopted when that is safe (store/log_adoption.py)."""
    signer = LogSigner(signer_directory(settings), legacy_key(settings))
    if database is not None:
        database.log_signer = signer
        adopt_pre_receipt_log(database, signer)
    return signer
