"""Points in time given as query parameters (`since`, `until`).

A time without a zone is ambiguous and could not be compared with the stored UTC times, and
one such as 9999-12-31T23:59:59-05:00 is past the last representable UTC instant: both were
500s. Each is now a 422 naming the parameter.
"""

from __future__ import annotations

from datetime import UTC, datetime
from typing import Annotated

from pydantic import AfterValidator


def _utc(value: datetime) -> datetime:
    if value.tzinfo is None or value.utcoffset() is None:
        raise ValueError("give a time zone, e.g. 2026-01-31T12:00:00Z")
    try:
        return value.astimezone(UTC)
    except OverflowError:
        raise ValueError("the time is outside the years 1 to 9999 in UTC") from None


Instant = Annotated[datetime, AfterValidator(_utc)]


def _utc_unless_zoned(value: datetime) -> datetime:
    # The event log's filters have always read a time without a zone as UTC.
    return _utc(value if value.tzinfo else value.replace(tzinfo=UTC))


UtcInstant = Annotated[datetime, AfterValidator(_utc_unless_zoned)]
