"""Run an exported MOOS-IvP community with the real MOOS-IvP programs (../shared/tools/moos-ivp):
MOOSDB, uSimMarine, pMarinePID, pHelmIvP and pLogger under pAntler, on a port of its own,
outcomes posted with uPokeDB as the vehicle's monitors would post them."""

from __future__ import annotations

import os
import re
import signal
import subprocess
import time
from collections.abc import Callable, Iterator
from contextlib import contextmanager, suppress
from dataclasses import dataclass
from pathlib import Path

from countersign.export.execution_input import redelivered

from ..ports import free_port

SHARED = Path(__file__).resolve().parents[2].parent / "shared"
TOOLS = SHARED / "tools" / "moos-ivp"
# Simulated seconds per second: fast enough for dives of tens of metres, slow enough that
# the helm and simulator keep up on a loaded machine.
TIME_WARP = 10
# Generous: every wait polls the alog for a condition and returns as soon as it holds.
DEADLINE_S = 120.0
POLL_S = 0.2
# A post is re-sent only when the alog has not shown it for this long. pLogger writes the log
# asynchronously, and with WildCardLogging (~200 KB/s) it once lagged over 20 s under load: the
# outcome was posted twice and the second one read as another goal run.
RETRY_S = 45.0
# One uPokeDB run: it normally exits within a second; one stuck connecting is tried again.
POKE_S = 30.0


def tools_missing() -> str | None:
    if not (TOOLS / "bin" / "pHelmIvP").is_file():
        return f"the MOOS-IvP programs are not under {TOOLS}"
    return None


def _env() -> dict[str, str]:
    env = dict(os.environ)
    env["PATH"] = f"{TOOLS / 'bin'}{os.pathsep}{env.get('PATH', '')}"
    lib = env.get("LD_LIBRARY_PATH")
    env["LD_LIBRARY_PATH"] = str(TOOLS / "lib") + (f"{os.pathsep}{lib}" if lib else "")
    return env


@dataclass(frozen=True)
class Entry:
    time: float
    var: str
    source: str
    value: str


class Community:
    """One running community; `entries()` reads what its pLogger has written so far."""

    def __init__(self, folder: Path, moos: Path, process: subprocess.Popen[bytes],
                 output: Path) -> None:
        self.folder, self.moos, self.process, self.output = folder, moos, process, output
        self._read = 0  # bytes of the alog parsed so far: polls read only what is new
        self._entries: list[Entry] = []
        # pLogger's repeats of earlier values (WildCardLogging) are left out, as the
        # execution log conversion leaves them out: a stale MODE would read as a mode change
        self._latest: dict[str, tuple[float, str]] = {}

    @property
    def alog(self) -> Path:
        found = sorted(self.folder.rglob("*.alog"))
        return found[0] if found else self.folder / "missing.alog"

    def entries(self) -> list[Entry]:
        if not self.alog.is_file():
            return self._entries
        with self.alog.open("rb") as handle:
            handle.seek(self._read)
            data = handle.read()
        complete = data[:data.rfind(b"\n") + 1]
        self._read += len(complete)
        for line in complete.decode(errors="replace").splitlines():
            parts = line.split(None, 3)
            if len(parts) >= 3 and re.fullmatch(r"-?[0-9.]+", parts[0]):
                value = parts[3].strip() if len(parts) == 4 else ""
                if not redelivered(self._latest, float(parts[0]), parts[1], value):
                    self._entries.append(Entry(float(parts[0]), parts[1], parts[2], value))
        return self._entries

    def values(self, var: str) -> list[str]:
        return [e.value for e in self.entries() if e.var == var]

    def poke(self, var: str, value: str, landed: Callable[[], bool]) -> None:
        """Post var=value with uPokeDB until `landed()` shows the community got it: on a
        loaded machine uPokeDB now and then exits before its post reaches the MOOSDB. The
        retry interval is long, so a late first post is not followed by a second."""
        end = time.monotonic() + DEADLINE_S
        while time.monotonic() < end:
            # A uPokeDB that never reached the MOOSDB (a loaded machine) is killed by run();
            # what it may have posted is checked below, then it is tried again.
            with suppress(subprocess.TimeoutExpired):
                subprocess.run(["uPokeDB", str(self.moos), f"{var}={value}"], env=_env(),
                               cwd=self.folder, stdout=subprocess.DEVNULL,
                               stderr=subprocess.DEVNULL, check=True, timeout=POKE_S)
            retry = time.monotonic() + RETRY_S
            while time.monotonic() < retry:
                if landed():
                    return
                time.sleep(POLL_S)
        raise AssertionError(f"{var}={value} never reached the community")

    def poked(self, var: str) -> int:
        return sum(1 for e in self.entries() if e.var == var and e.source == "uPokeDB")

    def wait_for(self, what: str, holds: Callable[[], object]) -> None:
        """Poll until `holds()` is true; fail naming `what` and the helm's output."""
        end = time.monotonic() + DEADLINE_S
        while time.monotonic() < end:
            if holds():
                return
            if self.process.poll() is not None:
                break
            time.sleep(POLL_S)
        raise AssertionError(f"{what} did not happen; pAntler output ends:\n"
                             f"{self.output.read_text(errors='replace')[-3000:]}")


def prepare(moos: Path, port: int, warp: int = TIME_WARP) -> None:
    """The exported .moos, on its own port and in warped time."""
    text = moos.read_text()
    text, ports = re.subn(r"(?m)^ServerPort\s*=.*$", f"ServerPort = {port}", text)
    text, warps = re.subn(r"(?m)^MOOSTimeWarp\s*=.*$", f"MOOSTimeWarp = {warp}", text)
    assert ports == 1 and warps == 1, "the export's .moos names its port and time warp once"
    moos.write_text(text)


@contextmanager
def running(moos: Path) -> Iterator[Community]:
    """pAntler on `moos` in a session of its own; every process of it is ended on the way
    out, whatever happened."""
    prepare(moos, free_port())
    output = moos.parent / "antler.out"
    with output.open("wb") as sink:
        process = subprocess.Popen(["pAntler", moos.name], cwd=moos.parent, env=_env(),
                                   stdout=sink, stderr=subprocess.STDOUT,
                                   start_new_session=True)
    try:
        yield Community(moos.parent, moos, process, output)
    finally:
        _end(process)


def _session(sid: int) -> list[int]:
    """PIDs in session `sid`: pAntler gives each child a process group of its own, but they
    stay in its session even when orphaned."""
    pids = []
    for stat in Path("/proc").glob("[0-9]*/stat"):
        with suppress(OSError, ValueError, IndexError):
            # the fields after the command name (which may hold spaces), from the last ')'
            fields = stat.read_text().rsplit(")", 1)[1].split()
            if int(fields[3]) == sid and fields[0] != "Z":
                pids.append(int(stat.parent.name))
    return pids


def _end(process: subprocess.Popen[bytes]) -> None:
    """pAntler stops its children on SIGTERM once it has launched them all; whatever is left
    of its session after that is killed by PID."""
    with suppress(ProcessLookupError):
        process.terminate()
    with suppress(subprocess.TimeoutExpired):
        process.wait(timeout=10)
    end = time.monotonic() + 10
    while (left := _session(process.pid)) and time.monotonic() < end:
        for pid in left:
            with suppress(ProcessLookupError, PermissionError):
                os.kill(pid, signal.SIGKILL)
        time.sleep(0.2)
    with suppress(ProcessLookupError):
        process.kill()
    process.wait()
    assert not _session(process.pid), f"processes of pAntler {process.pid} outlived it"
