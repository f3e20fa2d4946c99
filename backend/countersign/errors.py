"""The domain's errors: what was asked cannot be done, and the message says why.

One small hierarchy, free of HTTP: `web/problems.py` maps each kind to its status code and
RFC 9457 problem document, the command line to its exit code. It sits at the root of the
package, below every layer, so that store, rehearse and web raise the same kinds. Specific
errors (a stale statement, a bad cosignature) subclass a kind where they are raised.
"""

from __future__ import annotations


class DomainError(Exception):
    """A request that cannot be honoured as made (bad input the caller can fix)."""


class Invalid(DomainError):
    """The request is malformed or breaks a rule about its content."""


class Unprocessable(Invalid):
    """Well formed, but its content cannot be acted on (e.g. an unknown fault name)."""


class Forbidden(DomainError):
    """The caller may not do this (wrong role, own work, someone else's key, no password)."""


class NotFound(DomainError):
    """What the request names does not exist (or is not the caller's to see)."""


class Conflict(DomainError):
    """The request clashes with the current state (already decided, already used)."""


class PreconditionFailed(DomainError):
    """The request was made against a revision that is no longer the current one."""

    def __init__(self, message: str, current_revision: int) -> None:
        super().__init__(message)
        self.current_revision = current_revision


class Gone(DomainError):
    """What the request names existed once and has ended."""


class TooMany(DomainError):
    """The caller holds as many of these as one caller may."""


class Unavailable(DomainError):
    """The service cannot do this now (busy, or a dependency refuses); retrying may work."""
