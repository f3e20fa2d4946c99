"""Tickets and sockets of the rehearsal viewer.

The viewer (viser's client at `/rehearsal/{id}/`) runs in an opaque origin (CSP `sandbox
allow-scripts`), so it sends no session cookie. The signed-in owner's `/rehearsal/{id}/`
mints a ticket and redirects the frame to `/rehearsal/{id}/t/{ticket}/`; viser's client opens
its websocket on that path. A ticket is

- per rehearsal and per credential: it opens that rehearsal's websocket and nothing else (no
  API route knows tickets);
- short-lived: new sockets only within `TICKET_TTL_S` of minting (an open one lives on while
  its session does);
- tied to the session or token that minted it: once that is signed out, revoked or expired, the
  ticket is void and every socket opened with it stops relaying.

Tickets and sockets are in-process state, like the live rehearsals they belong to."""

from __future__ import annotations

import asyncio
import hashlib
import secrets
import threading
import time
from dataclasses import dataclass, field

TICKET_TTL_S = 600.0
MAX_TICKETS = 4096
MAX_SOCKETS_PER_REHEARSAL = 4
MAX_SOCKETS_PER_USER = 8
SESSION_CHECK_S = 5.0  # how often an open socket checks that its session still exists


@dataclass(frozen=True)
class Credential:
    """What signed the viewer in: a session cookie or an API token (kept in memory only)."""

    cookie: str | None
    bearer: str | None

    @property
    def key(self) -> str:
        raw = f"c:{self.cookie}" if self.cookie else f"b:{self.bearer}"
        return hashlib.sha256(raw.encode()).hexdigest()


@dataclass
class Ticket:
    rehearsal_id: str
    user_id: int
    credential: Credential
    expires: float


@dataclass
class Socket:
    rehearsal_id: str
    user_id: int
    credential_key: str
    ended: asyncio.Event = field(default_factory=asyncio.Event)
    reason: str = ""


class SocketLimit(Exception):
    pass


class ViewerRegistry:
    def __init__(self, *, per_rehearsal: int = MAX_SOCKETS_PER_REHEARSAL,
                 per_user: int = MAX_SOCKETS_PER_USER, ttl_s: float = TICKET_TTL_S) -> None:
        self.per_rehearsal, self.per_user, self.ttl_s = per_rehearsal, per_user, ttl_s
        self._lock = threading.Lock()
        self._tickets: dict[str, Ticket] = {}
        self._sockets: list[tuple[Socket, asyncio.AbstractEventLoop]] = []

    def mint(self, rehearsal_id: str, user_id: int, credential: Credential) -> str:
        ticket = secrets.token_urlsafe(32)
        now = time.monotonic()
        with self._lock:
            for key in [k for k, t in self._tickets.items() if t.expires < now]:
                del self._tickets[key]
            while len(self._tickets) >= MAX_TICKETS:
                del self._tickets[next(iter(self._tickets))]
            self._tickets[_hash(ticket)] = Ticket(rehearsal_id, user_id, credential,
                                                  now + self.ttl_s)
        return ticket

    def redeem(self, rehearsal_id: str, ticket: str) -> Ticket | None:
        """The ticket, if it is live and for this rehearsal (its credential is checked by the
        caller). Not consumed: viser's client reconnects with the same URL."""
        with self._lock:
            found = self._tickets.get(_hash(ticket))
        if found is None or found.expires < time.monotonic():
            return None
        if not secrets.compare_digest(found.rehearsal_id, rehearsal_id):
            return None
        return found

    def open(self, rehearsal_id: str, user_id: int, credential_key: str) -> Socket:
        """Count a new socket against the caps; SocketLimit when one is reached."""
        with self._lock:
            self._sockets = [(s, loop) for s, loop in self._sockets if not s.ended.is_set()]
            live = [s for s, _ in self._sockets]
            if sum(1 for s in live if s.rehearsal_id == rehearsal_id) >= self.per_rehearsal:
                raise SocketLimit(f"the rehearsal has {self.per_rehearsal} viewers open "
                                  "already; close one first")
            if sum(1 for s in live if s.user_id == user_id) >= self.per_user:
                raise SocketLimit(f"you have {self.per_user} rehearsal viewers open already; "
                                  "close one first")
            socket = Socket(rehearsal_id, user_id, credential_key)
            self._sockets.append((socket, asyncio.get_running_loop()))
            return socket

    def close(self, socket: Socket) -> None:
        socket.ended.set()
        with self._lock:
            self._sockets = [(s, loop) for s, loop in self._sockets if s is not socket]

    def credential_ended(self, credential: Credential, reason: str = "signed out") -> int:
        """Void the credential's tickets and end its sockets (sign-out); how many sockets."""
        key = credential.key
        with self._lock:
            for ticket_key in [k for k, t in self._tickets.items()
                               if t.credential.key == key]:
                del self._tickets[ticket_key]
            mine = [(s, loop) for s, loop in self._sockets if s.credential_key == key]
        for socket, loop in mine:
            socket.reason = reason
            loop.call_soon_threadsafe(socket.ended.set)
        return len(mine)

    def sockets(self, rehearsal_id: str | None = None) -> int:
        with self._lock:
            return sum(1 for s, _ in self._sockets if not s.ended.is_set()
                       and (rehearsal_id is None or s.rehearsal_id == rehearsal_id))


def _hash(ticket: str) -> str:
    return hashlib.sha256(ticket.encode()).hexdigest()
