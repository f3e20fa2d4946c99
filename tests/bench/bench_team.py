"""Benchmark of: TEAM on the product of the members' MEAs.

Run: .venv/bin/python -m tests.bench.bench_team

Teams of 2 and 3 members, each member a chain of "layers" of three goals (every outcome of a
layer's goals leads to the next layer, so paths grow as 3^goals) with a meeting every few
layers. Prints, per size, the joint executions counted, the joint positions the check
explored (over meetings and terminals only) and their ratio, and how the check's time grows
relative to the smallest size (ratios, not seconds to compare with another machine). Then two
independent pairs (a product that grows as the square of the meetings) up to the bound on
joint positions, where TEAM becomes a warning.
"""

from __future__ import annotations

import time
from typing import Any

from countersign.orders.model import OUTCOMES, Orders
from countersign.verify.graph import build_graph
from countersign.verify.team import TeamMemberGraph, check_team, joint_positions


def member(layers: int, every: int, skip: bool) -> dict[str, Any]:
    """A member: `layers` layers of 3 goals; a rendezvous (meeting M<k>) after every `every`
    layers; with `skip`, a violation in the last goal of a layer may skip to the end."""
    goals: list[dict[str, Any]] = []
    meeting = 0
    for layer in range(layers):
        ids = [f"L{layer}.{j}" for j in range(3)]
        after = f"L{layer + 1}.0" if layer + 1 < layers else "COMPLETE"
        if (layer + 1) % every == 0 and layer + 1 < layers:
            meet_id = f"M{meeting}"
            meeting += 1
            goals.append({"id": meet_id, "behavior": "rendezvous", "meet": meet_id,
                          "next": dict.fromkeys(OUTCOMES, after)})
            after = meet_id
        for j, gid in enumerate(ids):
            nxt = ids[j + 1] if j < 2 else after
            goals.append({"id": gid, "behavior": "transit",
                          "next": {"succeed": nxt, "fail": nxt,
                                   "violate": "ABORT" if skip and j == 2 else nxt}})
    return {"id": "m", "start": "L0.0", "goals": goals}


def magnitude(n: int) -> str:
    """A count too large for a float, as 10^k."""
    return f"10^{len(str(n)) - 1}" if n else "0"


def run(members: int, layers: int, every: int) -> tuple[float, int, int, int, int]:
    graphs = [TeamMemberGraph(f"v{i}", build_graph(Orders.model_validate(
        member(layers, every, skip=i == 1)))) for i in range(members)]
    started = time.perf_counter()
    result = check_team(graphs)
    elapsed = time.perf_counter() - started
    assert result.counts is not None
    positions = joint_positions(graphs)
    return (elapsed, result.counts.total, positions, len(result.findings),
            graphs[0].graph.goal_count)


def main() -> None:
    for members in (2, 3):
        base: float | None = None
        print(f"team of {members}: layers, goals/member, joint executions, positions, "
              "executions per position, findings, time vs smallest")
        for layers in (4, 16, 64, 256):
            elapsed, total, positions, findings, goals = run(members, layers, every=4)
            base = base or elapsed
            print(f"  {layers:>4} {goals:>5} {magnitude(total):>8} {positions:>6} "
                  f"{magnitude(total // positions):>8} {findings:>3} {elapsed / base:8.1f}x")
    print("two independent pairs: meetings each, joint positions, time vs smallest")
    first: float | None = None
    for meetings in (10, 30, 100, 320):
        elapsed, positions = pairs(meetings)
        first = first or elapsed
        shown = positions if positions is not None else "over the bound: TEAM warning"
        print(f"  {meetings:>4} {shown!s:>6} {elapsed / first:8.1f}x")


def pairs(meetings: int) -> tuple[float, int | None]:
    """Two independent pairs, each meeting `meetings` times; one of each pair may abort."""
    def chain(prefix: str, skip: bool) -> TeamMemberGraph:
        goals = []
        for i in range(meetings):
            after = f"X{i + 1}" if i + 1 < meetings else "COMPLETE"
            goals.append({"id": f"X{i}", "behavior": "rendezvous", "meet": f"{prefix}{i}",
                          "next": {"succeed": after, "fail": after,
                                   "violate": "ABORT" if skip else after}})
        orders = Orders.model_validate({"id": "m", "start": "X0", "goals": goals})
        return TeamMemberGraph(f"{prefix}{int(skip)}", build_graph(orders))

    graphs = [chain("R", False), chain("R", True), chain("S", False), chain("S", True)]
    started = time.perf_counter()
    result = check_team(graphs)
    return time.perf_counter() - started, (joint_positions(graphs) if result.counts else None)


if __name__ == "__main__":
    main()
