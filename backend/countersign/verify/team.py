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
  nothing else), so this one schedule meets every joint execution exactly once: the number of
  ways to reach each joint position, carried forward in topological order (multiplied by the
  members' own ways along each move), counts joint executions where the schedule stops, and
  the shortest length to each position gives the shortest joint path (a meeting is one step).

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
MAX_DEADLOCK_FINDINGS = 50  # each carries its joint path
MAX_LOCAL_ENTRIES = 500_000  # (node, next stop) pairs over all members: about 75 MB

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
    """Joint executions (traces) by where each member ends (a terminal, or None for a member
    left waiting), and the deadlocked ones by meeting and waiting member."""

    total: int
    deadlocked: int
    by_ends: tuple[tuple[tuple[str | None, ...], int], ...]
    # (meeting, vehicle waiting there, executions): one execution may leave several waiting.
    waiting: tuple[tuple[str, str, int], ...]
    vehicles: tuple[str, ...]

    def key(self, ends: Sequence[str | None]) -> str:
        return " + ".join(f"{vehicle}:{end or 'waiting'}"
                          for vehicle, end in zip(self.vehicles, ends, strict=True))

    def by_key(self) -> dict[str, int]:
        return {self.key(ends): n for ends, n in self.by_ends}

    def to_json(self) -> dict[str, Any]:
        return {
            "count": self.total,
            "deadlocked": self.deadlocked,
            "by_ends": [{"ends": dict(zip(self.vehicles, ends, strict=True)), "count": n}
                        for ends, n in self.by_ends],
            "waiting": [{"meeting": m, "vehicle": v, "count": n} for m, v, n in self.waiting],
        }


@dataclass(frozen=True)
class TeamCheck:
    findings: list[Finding]
    counts: JointCounts | None
    meetings: dict[str, tuple[str, ...]] = field(default_factory=dict)


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
        self.entries = 0
        self.ways = [self._ways(m.graph, meets) for m, meets in zip(members, self.meet_of,
                                                                     strict=True)]
        self.moves = 0

    def _ways(self, graph: MissionGraph, meets: dict[int, str]) -> dict[int, dict[int, Way]]:
        """Per node, the stops (meeting goals, terminals) reachable without meeting anyone."""
        order = topological_order(graph)
        assert order is not None
        ways: dict[int, dict[int, Way]] = {
            graph.goal_count + t: {graph.goal_count + t: (1, 0, -1)}
            for t in range(len(graph.terminals))
        }
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
            self.entries += len(table)
            if self.entries > MAX_LOCAL_ENTRIES:
                raise TooLarge(f"more than {MAX_LOCAL_ENTRIES:,} (goal, next meeting) pairs")
            ways[node] = table
        return ways

    def enabled(self, position: Position) -> str | None:
        """The meeting that fires next here (the smallest id among those assembled)."""
        # Only a meeting some member stands at can be assembled: look at those, not at all.
        here = sorted({meet for i, node in enumerate(position)
                       if (meet := self.meet_of[i].get(node)) is not None})
        for meet in here:
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
            yield tuple(new), ways, length

    def after(self, position: Position, meet: str, k: int) -> list[tuple[int, int]]:
        return [(i, self.members[i].graph.succ[position[i]][k])
                for i in self.participants[meet]]

    def moves_from(self, position: Position) -> Iterator[tuple[int, Position, int, int]]:
        """The scheduled meeting's moves: (outcome index, next position, ways, length)."""
        meet = self.enabled(position)
        if meet is None:
            return
        for k in range(3):
            for nxt, ways, length in self.spread(position, self.after(position, meet, k)):
                yield k, nxt, ways, length

    def explore(self, starts: Sequence[Position]) -> list[Position]:
        """Every joint position reachable from `starts`, parents before children."""
        done: dict[Position, None] = {}  # in post-order: children before parents
        stack: list[Position] = list(starts)
        while stack:
            position = stack[-1]
            if position in done:
                stack.pop()
                continue
            pending = []
            for _, nxt, _, _ in self.moves_from(position):
                self.moves += 1
                if self.moves > MAX_JOINT_MOVES:
                    raise TooLarge(f"more than {MAX_JOINT_MOVES:,} joint moves")
                if nxt not in done:
                    pending.append(nxt)
            if pending:
                stack.extend(pending)
                continue
            done[position] = None
            if len(done) > MAX_JOINT_POSITIONS:
                raise TooLarge(f"more than {MAX_JOINT_POSITIONS:,} joint positions")
            stack.pop()
        return list(reversed(done))


@dataclass
class _Forward:
    """Ways to reach each joint position from the start, the shortest length there and the
    move that reached it that way (None: reached by the members' first own moves)."""

    ways: dict[Position, int] = field(default_factory=dict)
    length: dict[Position, int] = field(default_factory=dict)
    parent: dict[Position, tuple[Position, int] | None] = field(default_factory=dict)

    def reach(self, position: Position, ways: int, length: int,
              parent: tuple[Position, int] | None) -> None:
        self.ways[position] = self.ways.get(position, 0) + ways
        if position not in self.length or length < self.length[position]:
            self.length[position] = length
            self.parent[position] = parent


def check_team(members: Sequence[TeamMemberGraph]) -> TeamCheck:
    """TEAM findings and joint counts of a team whose members' MEAs are all countable."""
    starts = [m.graph.start for m in members]
    assert members and all(s is not None for s in starts)
    begin = tuple(s for s in starts if s is not None)
    try:
        product = _Product(members)
        firsts = list(product.spread(begin, list(enumerate(begin))))
        if len(firsts) > MAX_JOINT_POSITIONS:
            raise TooLarge(f"more than {MAX_JOINT_POSITIONS:,} joint positions")
        order = product.explore([p for p, _, _ in firsts])
    except TooLarge as exc:
        return TeamCheck([warning(
            "TEAM", [m.vehicle for m in members],
            f"The team's meetings were not checked: the joint executions have {exc} "
            "(a deadlock cannot be ruled out).", undecided=True)], None)
    findings = _lonely_meetings(product)
    # Forward over the positions in topological order: ways multiply along each move and add
    # up where moves join, so every joint execution is counted once, as one path here.
    forward = _Forward()
    for position, ways, length in firsts:
        forward.reach(position, ways, length, None)
    finals: list[Position] = []
    for position in order:
        here_ways, here_length = forward.ways[position], forward.length[position]
        moved = False
        for k, nxt, ways, length in product.moves_from(position):
            moved = True
            forward.reach(nxt, here_ways * ways, here_length + 1 + length, (position, k))
        if not moved:
            finals.append(position)
    counts, best = _tally(product, forward, finals)
    # One finding per meeting and member left waiting there, in meeting then team order; a
    # path each, so their number is bounded and the rest are named in one more finding.
    waiters = sorted(best)
    for waiter in waiters[:MAX_DEADLOCK_FINDINGS]:
        findings.append(_deadlock(product, forward, waiter, begin, best[waiter]))
    if len(waiters) > MAX_DEADLOCK_FINDINGS:
        rest = waiters[MAX_DEADLOCK_FINDINGS:]
        findings.append(error(
            "TEAM", sorted({m for m, _ in rest}),
            f"{len(rest)} more meetings can leave a member waiting for ever: "
            + ", ".join(f"{m} ({members[i].vehicle})" for m, i in rest[:50])
            + (", ..." if len(rest) > 50 else "") + "."))
    return TeamCheck(findings, counts, {m: _names(product, m) for m in product.order})


def joint_positions(members: Sequence[TeamMemberGraph]) -> int:
    """How many joint positions (over meetings and terminals) the check explores: the size
    of the product it works on (tests/bench/bench_team.py prints it)."""
    product = _Product(members)
    begin = tuple(m.graph.start or 0 for m in members)
    return len(product.explore([p for p, _, _ in product.spread(begin, list(enumerate(begin)))]))


def _tally(product: _Product, forward: _Forward, finals: list[Position],
           ) -> tuple[JointCounts, dict[Waiter, Position]]:
    """Joint executions by ends and by waiting member; the nearest deadlock of each waiter."""
    by_ends: Counter[tuple[str | None, ...]] = Counter()
    waiting: Counter[Waiter] = Counter()
    best: dict[Waiter, Position] = {}
    deadlocked = 0
    for position in finals:  # in topological order: ties go to the first
        ways = forward.ways[position]
        ends = tuple(None if position[i] in product.meet_of[i] else _node_id(product, i, node)
                     for i, node in enumerate(position))
        by_ends[ends] += ways
        if any(end is None for end in ends):
            deadlocked += ways
        for i, node in enumerate(position):
            if ends[i] is None:
                waiter = (product.meet_of[i][node], i)
                waiting[waiter] += ways
                if waiter not in best or forward.length[position] < forward.length[
                        best[waiter]]:
                    best[waiter] = position
    vehicles = tuple(m.vehicle for m in product.members)
    rows = tuple(sorted(by_ends.items(), key=lambda row: (
        any(e is None for e in row[0]), [e or "" for e in row[0]])))
    counts = JointCounts(
        total=sum(by_ends.values()), deadlocked=deadlocked, by_ends=rows,
        waiting=tuple((m, vehicles[i], n) for (m, i), n in sorted(waiting.items())),
        vehicles=vehicles)
    return counts, best


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


def _deadlock(product: _Product, forward: _Forward, waiter: Waiter, begin: Position,
              position: Position) -> Finding:
    meet = waiter[0]
    steps, last_meeting = _joint_steps(product, forward, begin, position)
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
    shared = _parting(product, meet, steps, last_meeting, waiters, absent)
    return error(
        "TEAM", [meet, text],
        f"Meeting {meet} can deadlock: {who}, but {' and '.join(why)}, so it can no longer "
        f"come.{shared} Shortest joint path: {text}.",
        meeting=meet, joint_path=steps,
        waiting=[product.members[i].vehicle for i in waiters],
        absent=[product.members[j].vehicle for j in absent])


def _joint_steps(product: _Product, forward: _Forward, begin: Position, position: Position
                 ) -> tuple[list[dict[str, Any]], dict[int, int]]:
    """The shortest joint path from `begin` to `position` as steps (each member's own goals
    between meetings), and for each member the index of the last meeting step it took part in."""
    moves: list[tuple[Position, int, Position]] = []  # (from, outcome index, to)
    first = position
    while (parent := forward.parent[first]) is not None:
        moves.append((parent[0], parent[1], first))
        first = parent[0]
    steps: list[dict[str, Any]] = []
    for i, node in enumerate(begin):
        steps.extend(_local_steps(product, i, node, first[i]))
    last_meeting: dict[int, int] = {}
    for here, k, nxt in reversed(moves):
        fired = product.enabled(here)
        assert fired is not None
        steps.append({"meet": fired, "outcome": OUTCOMES[k],
                      "goals": {product.members[i].vehicle: _node_id(product, i, here[i])
                                for i in product.participants[fired]}})
        meeting_step = len(steps) - 1
        for i, node in product.after(here, fired, k):
            last_meeting[i] = meeting_step
            steps.extend(_local_steps(product, i, node, nxt[i]))
    return steps, last_meeting


def _parting(product: _Product, meet: str, steps: list[dict[str, Any]],
             last_meeting: dict[int, int], waiters: list[int], absent: list[int]) -> str:
    """The sentence naming the shared outcome after which a waiter and an absent member
    parted ways (empty when none did)."""
    for i in waiters:
        for j in absent:
            if i in last_meeting and last_meeting.get(j) == last_meeting[i]:
                step = steps[last_meeting[i]]
                return (f" After their shared outcome {step['meet']} {step['outcome']}, "
                        f"{product.members[i].vehicle} goes on to {meet} and "
                        f"{product.members[j].vehicle} does not.")
    return ""
