"""Viewer tickets stay out of the server's logs.

A live rehearsal's viewer opens `/rehearsal/{id}/t/{ticket}/` and its websocket on that path
(viewer_tickets.py): the ticket is a bearer secret for that socket while it lives. uvicorn's
access log (`uvicorn.access`, which gunicorn's uvicorn workers also write through) prints each
request's path, and its websocket lines go to `uvicorn.error`; whoever reads the logs could open
the viewer. The filter below replaces the ticket in every record of those loggers with
`[ticket]` before any handler formats it."""

from __future__ import annotations

import logging
import re
from collections.abc import Mapping
from typing import Any

# The viewer's ticket segment: after /rehearsal/<id>/t/ up to the next /, space, quote or ?.
_TICKET = re.compile(r"(/rehearsal/[^/\s\"?]+/t/)[^/\s\"?]+")
HIDDEN = "[ticket]"
LOGGERS = ("uvicorn.access", "uvicorn.error", "gunicorn.access", "gunicorn.error")


def scrub(value: Any) -> Any:
    return _TICKET.sub(rf"\g<1>{HIDDEN}", value) if isinstance(value, str) else value


class TicketFilter(logging.Filter):
    """Rewrites the record's message and arguments; never drops a record."""

    def filter(self, record: logging.LogRecord) -> bool:
        record.msg = scrub(record.msg)
        if isinstance(record.args, Mapping):
            record.args = {key: scrub(value) for key, value in record.args.items()}
        elif isinstance(record.args, tuple):
            record.args = tuple(scrub(value) for value in record.args)
        return True


def hide_tickets() -> None:
    """Install the filter on the server's loggers (idempotent: once per logger). Filters sit
    on the loggers themselves, which uvicorn's and gunicorn's logging setup leave in place
    while they replace handlers."""
    for name in LOGGERS:
        logger = logging.getLogger(name)
        if not any(isinstance(f, TicketFilter) for f in logger.filters):
            logger.addFilter(TicketFilter())
