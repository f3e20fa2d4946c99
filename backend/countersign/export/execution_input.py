"""What a vehicle logs, turned into the NDJSON execution log the checker reads.

* IMC: a sequence of IMC messages as imcpy serialises them (e.g. a DUNE log's
  PlanControlState messages). While the plan is EXECUTING, each change of `man_id` ends the
  maneuver before it; `LogBookEntry` texts ManeuverIsDone / ManeuverFailed / ConstraintViolated
  (the export's transition conditions, raised by the vehicle's monitors) name the outcome, and
  EstimatedState gives depth_m and altitude_m samples.
* MOOS alog, as pLogger writes it: `TIME VAR SOURCE VALUE` lines of any variables; headers
  and the continuation lines of multi-line values are skipped and counted in a note.
  MODE = ACTIVE:<mode> (or MISSION_GOAL) enters a goal's helm mode (the innermost of
  ACTIVE:<refined goal>:<mode> for a goal inside a refinement), GOAL_OUTCOME and
  CONSTRAINT_VIOLATED name its outcome, NAV_DEPTH and NAV_ALTITUDE are samples.
Without a named outcome, the outcome is the one whose transition leads to the maneuver that
ran next; when several do, the first is taken and a note says so. Maneuvers are goals by their
id (IMC) or helm mode name (MOOS), as the exports name them."""

from __future__ import annotations

import json
import math
from collections.abc import Callable, Iterable
from dataclasses import dataclass, field
from datetime import UTC, datetime
from typing import Any

from ..orders.model import OUTCOMES, Orders
from ..verify.nesting import Nesting
from ..verify.refine import checked_form
from .moos import helm_modes

FORMATS = ("auto", "ndjson", "imc", "alog")
IMC_SYNC = b"\x54\xfe"  # 0xFE54, little endian: the first bytes of an IMC message
MAX_MESSAGES = 2_000_000
IMC_CHUNK = 1024
MAX_SAMPLES = 64  # per goal run: the extremes of each quantity are kept
MOOS_SAMPLES = {"NAV_DEPTH": "depth_m", "NAV_ALTITUDE": "altitude_m"}
MOOS_OUTCOMES = {"succeed": "succeed", "fail": "fail", "violate": "violate"}


class ExecutionInputError(ValueError):
    """Input that is not an execution log in the named format (the message says where)."""


@dataclass
class _Run:
    name: str
    start: float | None
    outcome: str | None = None
    # quantity -> ((lowest, order, sample), (highest, order, sample)): kept as they come, so
    # a long run does not hold every sample
    extremes: dict[str, list[tuple[float, int, dict[str, float]]]] = field(
        default_factory=dict)
    count: int = 0

    def add(self, values: dict[str, float]) -> None:
        self.count += 1
        for quantity, value in values.items():
            if not math.isfinite(value):
                continue
            entry = (value, self.count, values)
            low_high = self.extremes.setdefault(quantity, [entry, entry])
            if value < low_high[0][0]:
                low_high[0] = entry
            if value > low_high[1][0]:
                low_high[1] = entry

    def samples(self) -> list[dict[str, float]]:
        """The samples holding each quantity's lowest and highest value (bounds are what
        constraints state), in time order."""
        kept = {order: sample for pair in self.extremes.values() for _, order, sample in pair}
        return [kept[order] for order in sorted(kept)][:MAX_SAMPLES]


@dataclass(frozen=True)
class Converted:
    fmt: str
    ndjson: str
    notes: tuple[str, ...]


def _when(seconds: float | None, absolute: bool) -> str | None:
    if seconds is None or not math.isfinite(seconds):
        return None
    if not absolute:
        return f"{seconds:g}"
    try:
        moment = datetime.fromtimestamp(seconds, UTC)
    except (OverflowError, OSError, ValueError):
        raise ExecutionInputError(f"the vehicle's time {seconds:g} s since 1970 is not a date "
                                  "(years 1-9999)") from None
    return moment.isoformat().replace("+00:00", "Z")


class _Sequencer:
    """Turns 'maneuver X began at t' events into goal runs with outcomes."""

    def __init__(self, orders: Orders, goal_of: dict[str, str], absolute: bool) -> None:
        self.orders, self.goal_of, self.absolute = orders, goal_of, absolute
        self.goals = orders.goal_index()
        self.terminals = {t.id for t in orders.effective_terminals}
        self.current: _Run | None = None
        self.lines: list[str] = []
        self.notes: list[str] = []

    def _outcome(self, run: _Run, following: str | None) -> str:
        if run.outcome is not None:
            return run.outcome
        goal = self.goals.get(self.goal_of.get(run.name, run.name))
        if goal is None:
            return "succeed"
        nxt = self.goal_of.get(following, following) if following is not None else None
        leading = [o for o in OUTCOMES if goal.successors(o)[0] == nxt]
        if len(leading) > 1:
            self.notes.append(f"{goal.id} -> {nxt} is the transition of {', '.join(leading)}; "
                              f"no outcome was logged, so {leading[0]} was taken")
        if not leading and nxt is not None:
            self.notes.append(f"{goal.id} -> {nxt} is no transition of the orders; no outcome "
                              "was logged, so succeed was taken")
        return leading[0] if leading else "succeed"

    def _close(self, following: str | None, at: float | None) -> None:
        run = self.current
        if run is None:
            return
        name = self.goal_of.get(run.name, run.name)
        if name in self.terminals:
            return
        line: dict[str, Any] = {"goal": name, "outcome": self._outcome(run, following)}
        start, time = _when(run.start, self.absolute), _when(at, self.absolute)
        if start is not None:
            line["start"] = start
        if time is not None:
            line["time"] = time
        if run.extremes:
            line["samples"] = run.samples()
        self.lines.append(json.dumps(line, sort_keys=True))

    def enter(self, name: str, at: float | None) -> None:
        if self.current is not None and self.current.name == name:
            return
        self._close(name, at)
        self.current = _Run(name, at)

    def outcome(self, outcome: str) -> None:
        if self.current is not None:
            self.current.outcome = outcome

    def sample(self, values: dict[str, float]) -> None:
        if self.current is not None:
            self.current.add(values)

    def stop(self, at: float | None, outcome: str | None = None) -> None:
        if self.current is not None and outcome is not None and \
                self.current.outcome is None:
            self.current.outcome = outcome
        self._close(None, at)
        self.current = None

    def result(self, fmt: str) -> Converted:
        if self.current is not None:
            self.stop(None)
        if not self.lines:
            raise ExecutionInputError(f"the {fmt} input shows no goal being run")
        return Converted(fmt, "".join(line + "\n" for line in self.lines), tuple(self.notes))


# --- IMC -------------------------------------------------------------------------------


def _imc_messages(data: bytes) -> Iterable[Any]:
    """Messages of an IMC byte stream. imcpy's parser keeps a partial message between calls,
    so it is fed small chunks: slicing the whole rest of the input for every message would
    copy it quadratically."""
    import imcpy

    parser, count = imcpy.Parser(), 0
    for base in range(0, len(data), IMC_CHUNK):
        chunk, offset = data[base:base + IMC_CHUNK], 0
        while offset < len(chunk):
            message, used = parser.parse(chunk[offset:] if offset else chunk)
            if used <= 0:
                break
            offset += used
            if message is not None:
                count += 1
                if count > MAX_MESSAGES:
                    raise ExecutionInputError(f"more than {MAX_MESSAGES:,} IMC messages")
                yield message


def from_imc(orders: Orders, data: bytes) -> Converted:
    import imcpy

    from .imc import OUTCOME_OF

    executing = imcpy.PlanControlState.StateEnum.EXECUTING
    sequencer = _Sequencer(orders, {}, absolute=True)
    plans: set[str] = set()
    seen = 0
    for message in _imc_messages(data):
        seen += 1
        name = message.msg_name
        if name == "PlanControlState":
            if message.state == executing and message.man_id:
                plans.add(message.plan_id)
                sequencer.enter(str(message.man_id), message.timestamp)
            elif sequencer.current is not None:
                last = message.last_outcome
                outcome = {imcpy.PlanControlState.LastPlanOutcomeEnum.SUCCESS: None,
                           imcpy.PlanControlState.LastPlanOutcomeEnum.FAILURE: "fail"}.get(last)
                sequencer.stop(message.timestamp, outcome)
        elif name == "LogBookEntry" and str(message.text) in OUTCOME_OF:
            sequencer.outcome(OUTCOME_OF[str(message.text)])
        elif name == "EstimatedState":
            values = {"depth_m": float(message.depth)}
            if message.alt >= 0:
                values["altitude_m"] = float(message.alt)
            sequencer.sample(values)
    if not seen:
        raise ExecutionInputError("no IMC message found (not an imcpy-serialised sequence)")
    others = sorted(p for p in plans if not p.startswith(f"{orders.id}@"))
    if others:
        sequencer.notes.append(f"the vehicle ran plan {others[0][:80]!r}, not one of mission "
                               f"{orders.id}")
    return sequencer.result("imc")


# --- MOOS alog -------------------------------------------------------------------------


def _alog_entry(line: str) -> tuple[float, str, str] | None:
    """(time, variable, value) of a `TIME VAR SOURCE [VALUE]` line; None for anything else:
    headers, blank lines, and the continuation lines of multi-line values (pLogger writes
    values such as DB_VARSUMMARY as they are), which MOOS's own alog reader also passes over."""
    parts = line.split(None, 3)
    if len(parts) < 3:
        return None
    try:
        at = float(parts[0])
    except ValueError:
        return None
    if not math.isfinite(at):
        return None
    return at, parts[1], parts[3].strip() if len(parts) == 4 else ""


def redelivered(latest: dict[str, tuple[float, str]], at: float, var: str,
                 value: str) -> bool:
    """Whether an entry repeats what the log has already shown of `var`. pLogger with
    WildCardLogging now and then writes the current value of every variable again with the
    time it was posted: MISSION_GOAL=G1 from the mission's start appearing after G2 began, or
    an outcome twice. A variable's entries older than its latest one, or that one again, are
    such repeats; every other entry becomes the latest."""
    seen = latest.get(var)
    if seen is not None and (at < seen[0] or (at, value) == seen):
        return True
    latest[var] = (at, value)
    return False


def from_alog(orders: Orders, text: str, nesting: Nesting | None = None) -> Converted:
    helm = helm_modes(orders, nesting)
    goal_of = {mode: item for item, mode in helm.name.items()}
    sequencer = _Sequencer(orders, goal_of, absolute=False)
    skipped, first_skipped, repeats = 0, 0, 0
    latest: dict[str, tuple[float, str]] = {}
    for number, line in enumerate(text.splitlines(), 1):
        if not line.strip() or line.startswith("%"):
            continue
        entry = _alog_entry(line)
        if entry is None:
            skipped += 1
            first_skipped = first_skipped or number
            continue
        at, var, value = entry
        if redelivered(latest, at, var, value):
            repeats += 1
        elif var == "MODE" and value.startswith("ACTIVE:"):
            # the innermost mode: ACTIVE:G1:G1_1_k1 runs goal G1/G1.1#1 inside G1
            sequencer.enter(value.rsplit(":", 1)[1], at)
        elif var == "MISSION_GOAL":
            sequencer.enter(value, at)
        elif var == "GOAL_OUTCOME" and value in MOOS_OUTCOMES:
            sequencer.outcome(MOOS_OUTCOMES[value])
        elif var == "CONSTRAINT_VIOLATED":
            sequencer.outcome("violate")
        elif var in MOOS_SAMPLES:
            try:
                sequencer.sample({MOOS_SAMPLES[var]: float(value)})
            except ValueError:
                continue
        elif var == "MISSION_RESULT" and value != "none":
            sequencer.stop(at)
    if repeats:
        sequencer.notes.append(f"{repeats:,} alog entries repeat a variable's earlier value "
                               "with its old time (pLogger's wildcard logging writes them); "
                               "skipped")
    if skipped:
        sequencer.notes.append(f"{skipped:,} alog line(s) are no TIME VAR SOURCE VALUE entry "
                               f"(the first: line {first_skipped}), e.g. the continuation of "
                               "a multi-line value; skipped")
        if not sequencer.lines and sequencer.current is None:
            raise ExecutionInputError(f"the alog input shows no goal being run; {skipped:,} "
                                      f"line(s) are no TIME VAR SOURCE VALUE entry (the first: "
                                      f"line {first_skipped})")
    return sequencer.result("alog")


# --- detection -------------------------------------------------------------------------


def detect(data: bytes) -> str:
    if data.startswith(IMC_SYNC):
        return "imc"
    head = data.lstrip()[:1]
    if head == b"{":
        return "ndjson"
    if head == b"%" or head[:1].isdigit():
        return "alog"
    raise ExecutionInputError("the input is none of: NDJSON execution log, IMC messages, "
                              "MOOS alog (choose the format)")


def to_execution_log(orders: Orders, data: bytes, fmt: str = "auto") -> Converted:
    """The NDJSON execution log of `data` in format `fmt` (auto: detected)."""
    # A refined mission runs as its flat automaton: the vehicle's logs name its flat goals.
    orders, graph = checked_form(orders)
    if fmt not in FORMATS:
        raise ExecutionInputError(f"unknown execution format {fmt!r}; one of "
                                  f"{', '.join(FORMATS)}")
    chosen = detect(data) if fmt == "auto" else fmt
    readers: dict[str, Callable[[], Converted]] = {
        "imc": lambda: from_imc(orders, data),
        "alog": lambda: from_alog(orders, _text(data), graph.nesting),
        "ndjson": lambda: Converted("ndjson", _text(data), ()),
    }
    return readers[chosen]()


def _text(data: bytes) -> str:
    try:
        return data.decode()
    except UnicodeDecodeError as exc:
        raise ExecutionInputError(f"the log is not UTF-8 text (byte {exc.start})") from None
