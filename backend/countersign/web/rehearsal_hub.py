"""The app's live rehearsals: one RehearsalManager per app process, who owns which rehearsal,
and the limits (per user and in total).

Live rehearsals are in-process state (a viser server on a loopback port per rehearsal), so
with several app replicas `/api/rehearsals/*` and `/rehearsal/*` need sticky routing to the
replica that started the rehearsal; finished records go to the database and are visible from
every replica."""

from __future__ import annotations

import threading
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING

from cachetools import LRUCache

from ..errors import Gone, TooMany, Unavailable
from ..orders.model import Chart, Orders
from ..store.missions import Conflict, NotFound
from .viewer_tickets import ViewerRegistry

if TYPE_CHECKING:
    from ..rehearse.manager import Rehearsal, RehearsalManager, RehearsalOptions
    from ..rehearse.record import RehearsalRecord

MAX_PER_USER = 3
MAX_TOTAL = 16
IDLE_TIMEOUT_S = 900
# When every slot is taken, a rehearsal nobody has watched or called for this long is stopped
# to make room (its owner can still stop it into a record); below it, the newcomer gets 503.
EVICT_IDLE_S = 120.0
ENDED_MEMORY = 2000  # ids of ended rehearsals remembered to answer 410 instead of 404


class TooManyForUser(TooMany):
    pass


class Busy(Unavailable):
    pass


@dataclass
class Live:
    rehearsal: Rehearsal
    user_id: int
    mission_id: str
    version: int | None
    source: str
    sockets: int = 0


class RehearsalHub:
    def __init__(self, *, per_user: int = MAX_PER_USER, total: int = MAX_TOTAL,
                 idle_timeout_s: float = IDLE_TIMEOUT_S,
                 evict_idle_s: float = EVICT_IDLE_S, viewer_controls: bool = False) -> None:
        self.per_user, self.total, self.idle_timeout_s = per_user, total, idle_timeout_s
        self.evict_idle_s = evict_idle_s
        # The page holds the one set of controls: viser's own GUI stays empty.
        # Tests of the viewer gate turn it on, so there is something a stray socket could click.
        self.viewer_controls = viewer_controls
        self.viewers = ViewerRegistry()
        self._manager: RehearsalManager | None = None
        self._lock = threading.RLock()
        self._live: dict[str, Live] = {}
        self._starting: dict[int, int] = {}
        self._stopping: set[str] = set()
        self._ended: LRUCache[str, str | None] = LRUCache(ENDED_MEMORY)

    @property
    def manager(self) -> RehearsalManager:
        """The manager, made on first use: an app that never rehearses starts no viser."""
        if self._manager is None:
            from ..rehearse.manager import RehearsalManager

            with self._lock:
                if self._manager is None:
                    self._manager = RehearsalManager(max_active=self.total,
                                                     idle_timeout_s=self.idle_timeout_s)
        return self._manager

    def start(self, orders: Orders, *, user_id: int, mission_id: str, version: int | None,
              options: RehearsalOptions, charts: Sequence[Chart] = (),
              paths: Mapping[str, int] | None = None) -> Live:
        with self._lock:
            self._prune()
            mine = sum(1 for live in self._live.values()
                       if live.user_id == user_id and live.rehearsal.state != "stopped")
            mine += self._starting.get(user_id, 0)
            if mine >= self.per_user:
                raise TooManyForUser(f"you have {mine} live rehearsals (at most "
                                     f"{self.per_user}); stop one first")
            running = sum(1 for live in self._live.values() if live.rehearsal.state != "stopped")
            if running + sum(self._starting.values()) >= self.total and self._evict_one():
                running -= 1
            if running + sum(self._starting.values()) >= self.total:
                raise Busy(f"the server runs {self.total} rehearsals already; try again later")
            self._starting[user_id] = self._starting.get(user_id, 0) + 1
        try:
            from ..rehearse.manager import RehearsalLimit

            try:
                rehearsal = self.manager.start(orders, owner=str(user_id), options=options,
                                               charts=charts, controls=self.viewer_controls,
                                               paths=paths)
            except RehearsalLimit as exc:
                raise Busy(str(exc) or "no rehearsal slot is free; try again later") from None
            live = Live(rehearsal, user_id, mission_id, version, options.source)
            with self._lock:
                self._live[rehearsal.id] = live
            return live
        finally:
            with self._lock:
                self._starting[user_id] -= 1
                if not self._starting[user_id]:
                    del self._starting[user_id]

    def get(self, rehearsal_id: str, *, user_id: int) -> Live:
        """The caller's rehearsal; NotFound for unknown ids and other users' rehearsals (whose
        existence is not revealed), Gone for ones stopped and recorded. A rehearsal that
        stopped itself (idle) is still here, state "stopped", until it is stopped and
        recorded through the API."""
        with self._lock:
            live = self._live.get(rehearsal_id)
            if live is not None and self.manager.get(rehearsal_id) is None:
                self._forget(rehearsal_id, None)
                live = None
            if live is None:
                if rehearsal_id in self._ended:
                    digest = self._ended[rehearsal_id]
                    raise Gone(f"the rehearsal {rehearsal_id} has ended"
                               + (f"; its record is {digest}" if digest else ""))
                raise NotFound(f"no live rehearsal {rehearsal_id!r}")
            if live.user_id != user_id:
                raise NotFound(f"no live rehearsal {rehearsal_id!r}")
            return live

    def stop(self, rehearsal_id: str, *, user_id: int) -> tuple[Live, RehearsalRecord]:
        """Stop the caller's rehearsal (its viser server and thread) and return its record.
        It stays known until `recorded()` confirms the record is stored, so that a failed
        store can be retried; a second stop meanwhile is a conflict."""
        with self._lock:
            live = self.get(rehearsal_id, user_id=user_id)
            if rehearsal_id in self._stopping:
                raise Conflict(f"the rehearsal {rehearsal_id} is being stopped")
            self._stopping.add(rehearsal_id)
        try:
            record = self.manager.stop(rehearsal_id)
        except BaseException:
            with self._lock:
                self._stopping.discard(rehearsal_id)
            raise
        return live, record

    def recorded(self, rehearsal_id: str, digest: str | None) -> None:
        """The record is stored (digest) or storing it failed (None): forget or retry."""
        with self._lock:
            self._stopping.discard(rehearsal_id)
            if digest is not None:
                self._forget(rehearsal_id, digest)

    def count(self) -> int:
        """Running rehearsals (not stopped)."""
        if self._manager is None:
            return 0
        with self._lock:
            self._prune()
            return sum(1 for live in self._live.values() if live.rehearsal.state != "stopped")

    def shutdown(self) -> None:
        with self._lock:
            for rehearsal_id in list(self._live):
                self._forget(rehearsal_id, None)
        if self._manager is not None:
            self._manager.shutdown()

    def _evict_one(self) -> bool:
        """Stop the rehearsal idle the longest, if it has been idle EVICT_IDLE_S (no API call,
        no viewer open); True when one was stopped."""
        idle = [(live.rehearsal.idle_for(), live) for live in self._live.values()
                if live.rehearsal.state != "stopped" and not live.sockets
                and not self.viewers.sockets(live.rehearsal.id)]
        idle = [pair for pair in idle if pair[0] >= self.evict_idle_s]
        if not idle:
            return False
        _, oldest = max(idle, key=lambda pair: pair[0])
        oldest.rehearsal.stop()  # stays known, state "stopped", until its owner records it
        return True

    def _prune(self) -> None:
        """Forget rehearsals the manager no longer knows (it keeps the last stopped ones)."""
        if self._manager is None:
            return
        for rehearsal_id in [k for k in self._live
                             if self._manager.get(k, touch=False) is None]:
            self._forget(rehearsal_id, None)

    def _forget(self, rehearsal_id: str, digest: str | None) -> None:
        self._live.pop(rehearsal_id, None)
        self._remember(rehearsal_id, digest)

    def _remember(self, rehearsal_id: str, digest: str | None) -> None:
        self._ended[rehearsal_id] = digest
