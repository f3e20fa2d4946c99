"""The app's long-lived services, built once by the app factory and handed to routes.

Routes receive this object through a FastAPI dependency (`web/deps.py`, `Services`) and pass
what a service function needs as explicit keyword arguments (`reports=`, `signer=`), instead
of finding it in a session's or a database's `info`."""

from __future__ import annotations

from dataclasses import dataclass

from ..approvals.signer import LogSigner
from ..store.db import Database
from ..store.report_service import ReportService


@dataclass(frozen=True)
class AppServices:
    """One app's services. `database` opens sessions (a short reader beside a writer);
    `reports` computes validation reports once per digest (with the app's pool of validation
    processes while it runs); `signer` holds the log key (outside the database) and signs
    receipts and checkpoints."""

    database: Database
    reports: ReportService
    signer: LogSigner

    @classmethod
    def of(cls, database: Database, signer: LogSigner) -> AppServices:
        """The services of an app on `database`. The database keeps the same report service
        and signer for the store's own use (the log receipt each appended event
        carries, the CLI's runs without an app), so both see one instance of each."""
        if database.log_signer is not signer:
            raise ValueError("the app's log signer must be the one its database appends with")
        return cls(database=database, reports=database.reports, signer=signer)
