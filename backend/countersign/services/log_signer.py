"""Where the server's log signer keeps its key: its own directory, never the database."""

from __future__ import annotations

from pathlib import Path

from ..approvals.signer import LegacyKey, LogSigner
from ..settings import LEGACY_LOG_KEY_VARIABLE as LEGACY_KEY_ENV
from ..settings import LOG_KEY_DIR_VARIABLE as LOG_KEY_DIR_ENV
from ..settings import LogKeyEnvironment, Settings, read
from ..store.db import Database
from ..store.log_adoption import adopt_pre_receipt_log

__all__ = ["LEGACY_KEY_ENV", "LEGACY_KEY_FILE", "LOG_KEY_DIR_ENV", "legacy_key",
           "open_log_signer", "signer_directory"]
# The key file of an older deployment in the data directory (imported on upgrade).
LEGACY_KEY_FILE = "log-signing-key.pem"


def signer_directory(settings: Settings) -> Path:
    """COUNTERSIGN_LOG_KEY_DIR, or `log-signer/` in the data directory."""
    chosen = read(LogKeyEnvironment).log_key_dir
    return chosen if chosen is not None else settings.data_dir / "log-signer"


def legacy_key(settings: Settings) -> LegacyKey | None:
    """The log key of an older deployment: the PEM in COUNTERSIGN_LOG_KEY, or the key file
    it made in the data directory."""
    pem = read(LogKeyEnvironment).legacy_log_key
    if pem is not None:
        return LegacyKey(pem.get_secret_value().encode(), LEGACY_KEY_ENV)
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
