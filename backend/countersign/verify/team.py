"""TEAM: can a team's meetings deadlock? Exact, on the product of the members' MEAs.

A joint execution moves one member through one of its goals at a time, except at a meeting:
a goal naming `meet: R` waits until every member whose orders name R stands at such a goal,
then all of them leave with one shared outcome (each to its own successor for it). Moves of
different members are independent, so interleavings that differ only in their order are one
joint execution (a Mazurkiewicz trace; it is fixed by what each member did). The check never
enumerates interleavings:

- each member's own moves between meetings are summarised once per node: the meetings and
  terminals ("stops") it can reach without meeting anyone, with the number of ways and the
  shortest way (dynamic programming over its DAG);
- the product is explored over stops only, firing at each joint position the enabled meeting
  with the smallest id. An enabled meeting stays enabled until it fires (its members can do
  nothing else), so this one schedule meets every joint execution exactly once, and counts
  over it (memoised per joint position, in reverse topological order) count joint executions.

A joint position in which nothing can move while some member has not ended is a deadlock:
that member waits at a meeting a partner can no longer reach (the partner ended, went past
it, or waits at another meeting first). TEAM names the meeting and the shortest joint path to
such a position. Joint path text: steps separated by ", ", a member's step `auv-1/G3 fail`,
a meeting's step `R1[auv-1/G4 auv-2/G3] succeed`, then ` -> ` and the members' final positions
in team order, `(auv-1/G4, auv-2/ABORT)`; `start` when no step precedes them.
"""

from __future__ import annotations

import itertools
from collections import Counter
from collections.abc import Iterator, Sequence
from dataclasses import dataclass, field
from typing import Any

from ..orders.findings import Finding, error, warning
from ..orders.model import OUTCOMES
from .graph import MissionGraph
from .paths import topological_order

# Bounds on the product, so a user cannot make the check run unbounded: beyond them TEAM is a
# warning that says the meetings were not checked, never a hang.
MAX_JOINT_POSITIONS = 100_000
MAX_JOINT_MOVES = 1_000_000
MAX_LOCAL_ENTRIES = 2_000_000

# A member's way from a node to one stop: (number of ways, shortest length, first outcome).
Way = tuple[int, int, int]
Position = tuple[int, ...]
Waiter = tuple[str, int]  # a meeting and the index of a member waiting at it


class TooLarge(Exception):
    """The product exceeds a bound; the message says which."""


@dataclass(frozen=True)
class TeamMemberGraph:
    vehicle: str
    graph: MissionGraph


@dataclass(frozen=True)
class JointCounts:
    """Joint executions (traces) by where each member ends; `waiting` only on deadlocks."""

    total: int
    deadlocked: int
    by_ends: tuple[tuple[tuple[str, ...], tuple[str | None, ...], int], ...]
    vehicles: tuple[str, ...]

    def key(self, ends: Sequence[str], waiting: Sequence[str | None]) -> str:
        parts = []
        for vehicle, end, meet in zip(self.vehicles, ends, waiting, strict=True):
            parts.append(f"{vehicle}:{end}" + (f" (waits at {meet})" if meet else ""))
        return " + ".join(parts)

    def by_key(self) -> dict[str, int]:
        return {self.key(ends, waiting): n for ends, waiting, n in self.by_ends}

    def to_json(self) -> dict[str, Any]:
        return {
            "count": self.total,
            "deadlocked": self.deadlocked,
            "by_ends": [
                {"ends": dict(zip(self.vehicles, ends, strict=True)),
                 **({"waiting": {v: m for v, m in zip(self.vehicles, waiting, strict=True)
                                 if m is not None}} if any(waiting) else {}),
                 "count": n}
                for ends, waiting, n in self.by_ends
            ],
        }


@dataclass(frozen=True)
class TeamCheck:
    findings: list[Finding]
    counts: JointCounts | None
    meetings: dict[str, tuple[str, ...]] = field(default_factory=dict)


@dataclass
class _Node:
    """What is known of one joint position once its successors are done."""

    counts: Counter[tuple[Position, Position]]  # (final position, waiting flags) -> ways
    # (meeting, member) -> (shortest length to a deadlock where that member waits at that
    # meeting, next move or None)
    best: dict[Waiter, tuple[int, tuple[int, Position] | None]]


class _Product:
    def __init__(self, members: Sequence[TeamMemberGraph]) -> None:
        self.members = members
        self.meet_of: list[dict[int, str]] = []
        for member in members:
            graph = member.graph
            self.meet_of.append({n: g.meet for n, g in enumerate(graph.goals)
                                 if g.meet is not None})
        self.participants: dict[str, tuple[int, ...]] = {}
        for index, meets in enumerate(self.meet_of):
            for meet in sorted(set(meets.values())):
                self.participants[meet] = (*self.participants.get(meet, ()), index)
        self.order = sorted(self.participants)
        self.ways = [self._ways(m.graph, meets) for m, meets in zip(members, self.meet_of,
                                                                     strict=True)]
        self.memo: dict[Position, _Node] = {}
        self.moves = 0

    def _ways(self, graph: MissionGraph, meets: dict[int, str]) -> dict[int, dict[int, Way]]:
        """Per node, the stops (meeting goals, terminals) reachable without meeting anyone."""
        order = topological_order(graph)
        assert order is not None
        ways: dict[int, dict[int, Way]] = {
            graph.goal_count + t: {graph.goal_count + t: (1, 0, -1)}
            for t in range(len(graph.terminals))
        }
        entries = 0
        for node in order:  # successors first
            if node in meets:
                ways[node] = {node: (1, 0, -1)}
                continue
            table: dict[int, Way] = {}
            for k, target in enumerate(graph.succ[node]):
                for stop, (count, length, _) in ways[target].items():
                    old = table.get(stop)
                    if old is None:
                        table[stop] = (count, length + 1, k)
                    else:
                        better = length + 1 < old[1]
                        table[stop] = (old[0] + count, length + 1 if better else old[1],
                                       k if better else old[2])
            entries += len(table)
            if entries > MAX_LOCAL_ENTRIES:
                raise TooLarge(f"more than {MAX_LOCAL_ENTRIES:,} (goal, next meeting) pairs")
            ways[node] = table
        return ways

    def enabled(self, position: Position) -> str | None:
        """The meeting that fires next here (the smallest id among those assembled)."""
        for meet in self.order:
            if all(self.meet_of[i].get(position[i]) == meet for i in self.participants[meet]):
                return meet
        return None

    def spread(self, position: Position, movers: Sequence[tuple[int, int]],
               ) -> Iterator[tuple[Position, int, int]]:
        """Joint positions after the given members leave for the given nodes and run on to
        their next stops: (position, number of ways, added length)."""
        choices = [list(self.ways[i][node].items()) for i, node in movers]
        for combo in itertools.product(*choices):
            new = list(position)
            ways, length = 1, 0
            for (i, _), (stop, (count, steps, _)) in zip(movers, combo, strict=True):
                new[i] = stop
                ways *= count
                length += steps
            self.moves += 1
            if self.moves > MAX_JOINT_MOVES:
                raise TooLarge(f"more than {MAX_JOINT_MOVES:,} joint moves")
            yield tuple(new), ways, length

    def after(self, position: Position, meet: str, k: int) -> list[tuple[int, int]]:
        return [(i, self.members[i].graph.succ[position[i]][k])
                for i in self.participants[meet]]

    def solve(self, start: Position) -> _Node:
        """Counts and shortest deadlocks from `start`, memoised, without recursion."""
        stack: list[Position] = [start]
        while stack:
            position = stack[-1]
            if position in self.memo:
                stack.pop()
                continue
            meet = self.enabled(position)
            if meet is None:
                self.memo[position] = self._final(position)
                stack.pop()
                continue
            pending = [nxt for k in range(3)
                       for nxt, _, _ in self.spread(position, self.after(position, meet, k))
                       if nxt not in self.memo]
            if pending:
                stack.extend(pending)
                if len(self.memo) + len(stack) > MAX_JOINT_POSITIONS * 4:
                    raise TooLarge(f"more than {MAX_JOINT_POSITIONS:,} joint positions")
                continue
            self.memo[position] = self._combine(position, meet)
            if len(self.memo) > MAX_JOINT_POSITIONS:
                raise TooLarge(f"more than {MAX_JOINT_POSITIONS:,} joint positions")
            stack.pop()
        return self.memo[start]

    def _final(self, position: Position) -> _Node:
        waiting = tuple(1 if position[i] in self.meet_of[i] else 0
                        for i in range(len(position)))
        best: dict[Waiter, tuple[int, tuple[int, Position] | None]] = {
            (self.meet_of[i][position[i]], i): (0, None)
            for i in range(len(position)) if waiting[i]}
        return _Node(Counter({(position, waiting): 1}), best)

    def _combine(self, position: Position, meet: str) -> _Node:
        counts: Counter[tuple[Position, Position]] = Counter()
        best: dict[Waiter, tuple[int, tuple[int, Position] | None]] = {}
        for k in range(3):
            for nxt, ways, length in self.spread(position, self.after(position, meet, k)):
                node = self.memo[nxt]
                for key, n in node.counts.items():
                    counts[key] += ways * n
                for m, (rest, _) in node.best.items():
                    total = 1 + length + rest
                    if m not in best or total < best[m][0]:
                        best[m] = (total, (k, nxt))
        return _Node(counts, best)


def check_team(members: Sequence[TeamMemberGraph]) -> TeamCheck:
    """TEAM findings and joint counts of a team whose members' MEAs are all countable."""
    product = _Product(members) if members else None
    assert product is not None
    findings = _lonely_meetings(product)
    starts = [m.graph.start for m in members]
    assert all(s is not None for s in starts)
    begin = tuple(s for s in starts if s is not None)
    movers = list(enumerate(begin))
    total: Counter[tuple[Position, Position]] = Counter()
    best: dict[Waiter, tuple[int, Position]] = {}
    try:
        for position, ways, length in product.spread(begin, movers):
            node = product.solve(position)
            for key, n in node.counts.items():
                total[key] += ways * n
            for waiter, (rest, _) in node.best.items():
                if waiter not in best or length + rest < best[waiter][0]:
                    best[waiter] = (length + rest, position)
    except TooLarge as exc:
        findings.append(warning(
            "TEAM", [m.vehicle for m in members],
            f"The team's meetings were not checked: the joint executions have {exc} "
            "(a deadlock cannot be ruled out).", undecided=True))
        return TeamCheck(findings, None, {m: _names(product, m) for m in product.order})
    # One finding per meeting and member left waiting there, in meeting then team order.
    for waiter in sorted(best):
        findings.append(_deadlock(product, waiter, begin, best[waiter][1]))
    return TeamCheck(findings, _joint_counts(product, total),
                     {m: _names(product, m) for m in product.order})


def _names(product: _Product, meet: str) -> tuple[str, ...]:
    return tuple(product.members[i].vehicle for i in product.participants[meet])


def _lonely_meetings(product: _Product) -> list[Finding]:
    findings = []
    for meet in product.order:
        (index, *others) = product.participants[meet]
        member = product.members[index]
        goals = [g.id for n, g in enumerate(member.graph.goals)
                 if product.meet_of[index].get(n) == meet]
        if not others:
            findings.append(error(
                "TEAM", [meet, *(f"{member.vehicle}/{g}" for g in goals)],
                f"Only {member.vehicle} names meeting {meet} ({', '.join(goals)}): no partner "
                "will come, so it would wait there for ever."))
    for index, member in enumerate(product.members):
        for node, meet in product.meet_of[index].items():
            goal = member.graph.goals[node]
            if goal.behavior != "rendezvous":
                findings.append(warning(
                    "TEAM", [meet, f"{member.vehicle}/{goal.id}"],
                    f"{member.vehicle}/{goal.id} names meeting {meet} but its behaviour is "
                    f"{goal.behavior or 'not given'}, not rendezvous."))
    return findings


def _node_id(product: _Product, index: int, node: int) -> str:
    return product.members[index].graph.node_id(node)


def _local_steps(product: _Product, index: int, node: int, stop: int) -> list[dict[str, str]]:
    graph = product.members[index].graph
    ways = product.ways[index]
    steps = []
    while node != stop:
        k = ways[node][stop][2]
        steps.append({"vehicle": product.members[index].vehicle,
                      "goal": graph.goal_ids[node], "outcome": OUTCOMES[k]})
        node = graph.succ[node][k]
    return steps


def joint_path_text(steps: Sequence[dict[str, Any]], ends: Sequence[str]) -> str:
    """The joint path's text (see the module's docstring)."""
    words = []
    for step in steps:
        if "meet" in step:
            at = " ".join(f"{v}/{g}" for v, g in step["goals"].items())
            words.append(f"{step['meet']}[{at}] {step['outcome']}")
        else:
            words.append(f"{step['vehicle']}/{step['goal']} {step['outcome']}")
    return f"{', '.join(words) or 'start'} -> ({', '.join(ends)})"


def _deadlock(product: _Product, waiter: Waiter, begin: Position, first: Position) -> Finding:
    meet = waiter[0]
    steps: list[dict[str, Any]] = []
    for i, node in enumerate(begin):
        steps.extend(_local_steps(product, i, node, first[i]))
    position = first
    last_meeting: dict[int, int] = {}
    while True:
        _, move = product.memo[position].best[waiter]
        if move is None:
            break
        k, nxt = move
        fired = product.enabled(position)
        assert fired is not None
        steps.append({"meet": fired, "outcome": OUTCOMES[k],
                      "goals": {product.members[i].vehicle: _node_id(product, i, position[i])
                                for i in product.participants[fired]}})
        for i, node in product.after(position, fired, k):
            last_meeting[i] = len(steps) - 1
            steps.extend(_local_steps(product, i, node, nxt[i]))
        position = nxt
    ends = [f"{m.vehicle}/{_node_id(product, i, position[i])}"
            for i, m in enumerate(product.members)]
    text = joint_path_text(steps, ends)
    # The member this finding is about first, then any other waiting there with it.
    waiters = [waiter[1], *(i for i in product.participants[meet] if i != waiter[1]
                            and product.meet_of[i].get(position[i]) == meet)]
    absent = [i for i in product.participants[meet] if i not in waiters]
    why = []
    for j in absent:
        graph = product.members[j].graph
        where = position[j]
        vehicle = product.members[j].vehicle
        if graph.is_terminal(where):
            why.append(f"{vehicle} has ended at {graph.node_id(where)} "
                       f"({graph.terminal(where).label})")
        else:
            why.append(f"{vehicle} waits at {graph.node_id(where)} for meeting "
                       f"{product.meet_of[j][where]} first")
    who = " and ".join(
        f"{product.members[i].vehicle} waits at {_node_id(product, i, position[i])} "
        f"({product.members[i].graph.goals[position[i]].label})" for i in waiters)
    shared = ""
    for i in waiters:
        for j in absent:
            if i in last_meeting and last_meeting.get(j) == last_meeting[i]:
                step = steps[last_meeting[i]]
                shared = (f" After their shared outcome {step['meet']} {step['outcome']}, "
                          f"{product.members[i].vehicle} goes on to {meet} and "
                          f"{product.members[j].vehicle} does not.")
                break
        if shared:
            break
    return error(
        "TEAM", [meet, text],
        f"Meeting {meet} can deadlock: {who}, but {' and '.join(why)}, so it can no longer "
        f"come.{shared} Shortest joint path: {text}.",
        meeting=meet, joint_path=steps,
        waiting=[product.members[i].vehicle for i in waiters],
        absent=[product.members[j].vehicle for j in absent])


def _joint_counts(product: _Product, total: Counter[tuple[Position, Position]]) -> JointCounts:
    grouped: Counter[tuple[tuple[str, ...], tuple[str | None, ...]]] = Counter()
    for (position, waiting), n in total.items():
        ends = tuple(_node_id(product, i, node) for i, node in enumerate(position))
        meets = tuple(product.meet_of[i][node] if waiting[i] else None
                      for i, node in enumerate(position))
        grouped[(ends, meets)] += n
    rows = tuple(sorted(((ends, meets, n) for (ends, meets), n in grouped.items()),
                        key=lambda row: (any(row[1]), row[0], [m or "" for m in row[1]])))
    return JointCounts(
        total=sum(grouped.values()),
        deadlocked=sum(n for _, meets, n in rows if any(meets)),
        by_ends=rows,
        vehicles=tuple(m.vehicle for m in product.members),
    )
