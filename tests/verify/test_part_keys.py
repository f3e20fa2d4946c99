"""Part keys (verify.parts) of an edit cost what it touches: each goal's view is hashed once
by the goal's JSON text, so a one-goal edit hashes one goal again; the keys still change
exactly when a field a part reads changes, and are the same from orders or their JSON."""

from __future__ import annotations

import copy

from countersign.orders.canonical import goal_texts, orders_to_json
from countersign.verify import parts

from ..bench.bench_meo import meo_mission


def test_a_one_goal_edit_hashes_that_goal_alone_and_changes_only_the_parts_that_read_it(
) -> None:
    data = orders_to_json(meo_mission(40, seed=3))
    first = parts.part_keys_of_json(data, goal_texts(data))
    edited = copy.deepcopy(data)
    edited["goals"][7]["cost"] = {"energy_wh": 123456}
    hashed: list[str] = []
    views = parts._views_of_goal

    def counted(goal: object, text: str) -> tuple[bytes, ...]:
        with parts._goal_views_lock:
            if text not in parts._goal_views:
                hashed.append(text)
        return views(goal, text)

    parts._views_of_goal = counted  # type: ignore[assignment]
    try:
        second = parts.part_keys_of_json(edited, goal_texts(edited))
    finally:
        parts._views_of_goal = views  # type: ignore[assignment]
    assert len(hashed) == 1 and '"energy_wh": 123456' in hashed[0]
    # Costs are read by the structural part (and the properties, keyed alike) only.
    assert (second.meo, second.logic) == (first.meo, first.logic)
    assert second.core != first.core and second.properties != first.properties
    edited["goals"][7]["title"] = "Renamed"
    third = parts.part_keys_of_json(edited)
    assert third.meo != second.meo and third.logic != second.logic


def test_keys_from_orders_equal_keys_from_their_json_and_tell_no_goals_from_none() -> None:
    orders = meo_mission(12, seed=1)
    data = orders_to_json(orders)
    assert parts.part_keys(orders) == parts.part_keys_of_json(data)
    described = copy.deepcopy(data)
    described["description"] = "only words"
    described["goals"][0]["description"] = "more words"
    assert parts.part_keys_of_json(described) == parts.part_keys_of_json(data)
    empty = {k: v for k, v in data.items() if k != "goals"}
    assert parts.part_keys_of_json({**empty, "goals": []}) != parts.part_keys_of_json(empty)
