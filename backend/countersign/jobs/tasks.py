"""The campaign task: simulate a range of indexes and store each result once.

Everything a job needs is in the database (the orders, the spec), so any worker can run any
job, and running one again (a retry after a worker was killed) skips the indexes already
stored; the unique (campaign, index) makes even two concurrent runs of one job store each
result once. The last job to store a result seals the record.
"""

from __future__ import annotations

import threading
from collections.abc import Callable
from typing import Any

from cachetools import LRUCache

from ..campaigns.simulate import Mission, simulate
from ..campaigns.spec import CampaignSpec
from ..campaigns.stats import FORMAT, summarize
from ..campaigns.team import TeamMission, simulate_team
from ..campaigns.team_stats import summarize_team
from ..orders.reader import orders_from_data
from ..store import campaigns as store
from ..store.db import Database

MISSIONS_KEPT = 4
_missions: LRUCache[tuple[str, str], Mission | TeamMission] = LRUCache(MISSIONS_KEPT)
_missions_lock = threading.Lock()


def _mission(digest: str, orders: dict[str, Any], campaign_id: str) -> Mission | TeamMission:
    key = (campaign_id, digest)
    with _missions_lock:
        found = _missions.get(key)
        if found is not None:
            return found
    read = orders_from_data(orders)
    mission = TeamMission(read) if read.team is not None else Mission(read)
    with _missions_lock:
        _missions[key] = mission
    return mission


def run_chunk(database: Database, campaign_id: str, start: int, stop: int, *,
              on_stored: Callable[[int], None] | None = None) -> int:
    """Simulate indexes [start, stop) not yet stored; stop early when the campaign is no
    longer active. Returns how many results this call stored."""
    with database.session(write=False) as db:
        row = store.get(db, campaign_id)
        if row.state not in store.ACTIVE_STATES:
            return 0
        orders, digest, spec_json = row.orders, row.orders_digest, row.spec
        done = store.done_indexes(db, campaign_id, start, stop)
    mission = _mission(digest, orders, campaign_id)
    spec = CampaignSpec.from_json(spec_json)
    with database.session() as db:
        store.mark_running(db, campaign_id)
    stored = 0
    for index in range(max(0, start), min(stop, spec.simulations)):
        if index in done:
            continue
        with database.session(write=False) as db:
            if store.state_of(db, campaign_id) not in store.ACTIVE_STATES:
                return stored  # cancelled
        seed, faults = spec.simulation(index)
        result = simulate_team(mission, index, seed, faults) \
            if isinstance(mission, TeamMission) else simulate(mission, index, seed, faults)
        with database.session() as db:
            if store.store_result(db, campaign_id, index, result):
                stored += 1
                if on_stored is not None:
                    on_stored(index)
    finish_if_complete(database, campaign_id)
    return stored


def finish_if_complete(database: Database, campaign_id: str) -> str | None:
    """Seal the campaign's record once every index has a result; its digest, or None."""
    with database.session(write=False) as db:
        row = store.get(db, campaign_id)
        if row.state not in store.ACTIVE_STATES or store.count_done(db, campaign_id) \
                < row.simulations:
            return None
        runs = store.results(db, campaign_id)
        orders, digest, spec_json = row.orders, row.orders_digest, row.spec
    mission = _mission(digest, orders, campaign_id)
    record = campaign_record(mission, digest, spec_json, runs)
    with database.session() as db:
        return store.seal(db, campaign_id, record)


def campaign_record(mission: Mission | TeamMission, orders_digest: str, spec: dict[str, Any],
                    runs: list[dict[str, Any]]) -> dict[str, Any]:
    orders = mission.orders
    if isinstance(mission, TeamMission):
        return {"format": FORMAT, "orders": {"id": orders.id, "digest": orders_digest},
                "spec": spec, "results": summarize_team(runs, mission)}
    results = summarize(
        runs, total_paths=mission.total_paths,
        terminals=[(t.id, t.kind) for t in orders.effective_terminals],
        goals=[g.id for g in orders.goals])
    return {"format": FORMAT, "orders": {"id": orders.id, "digest": orders_digest},
            "spec": spec, "results": results}


def missing_chunks(database: Database, campaign_id: str) -> list[tuple[int, int]]:
    """The spec's chunks that still lack a result (what a resumed campaign must run)."""
    with database.session(write=False) as db:
        row = store.get(db, campaign_id)
        spec = CampaignSpec.from_json(row.spec)
        done = store.done_indexes(db, campaign_id)
    return [(a, b) for a, b in spec.chunks() if any(i not in done for i in range(a, b))]
