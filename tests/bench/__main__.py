"""Run the benchmarks of tests/bench, each in a process of its own, and say which ran green.

Run: ./scripts/bench [NAME ...] [--full] [--timeout S]
     (or .venv/bin/python -m tests.bench; NAME is a module without its `bench_` prefix)

Every module prints its figures beside their goals and a baseline measured in the same run; this
runner only starts them one after another, so that one slow or failing module neither hides
the others nor shares their memory, and prints a last table: module, exit status, seconds.
By default each runs at the smaller sizes of QUICK in this file (the whole set in 17 to 24 min on
the shared 2-core machine); `--full` runs each at its own defaults, the sizes its issue names
(hours: `bench_api` alone runs two 35 s rounds per database). A module that exits non-zero,
or runs past --timeout, makes the runner exit 1.
"""

from __future__ import annotations

import argparse
import os
import subprocess
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]

# Module -> arguments of the quick run. The sizes keep every code path (servers, pools,
# baselines) but fewer rounds; the figures of record are the --full ones.
QUICK: dict[str, list[str]] = {
    "core": ["--paths", "100000", "--baseline-cap", "5"],
    "list": ["--missions", "5", "--readers", "20", "--seconds", "5"],
    "probability": [],
    "logic": ["--goals", "100", "--constraints", "25", "--norms", "10"],
    "logic_whole": ["--goals", "1000", "--constraints", "100"],
    "logic_scale": ["--goals", "2000", "--constraints", "200"],
    "incremental": ["--quick"],
    "scale": ["--quick"],
    "startup": [],
    "fail_fast": [],
    "turtle_depth": [],
    "export": [],
    "geo": ["--goals", "200", "--charts", "100"],
    "plan": ["--cap", "2", "--limit", "5"],
    "meo": ["--runs", "2", "--naive-max", "50"],
    "audit": ["--events", "1000", "--approvals", "20", "--rounds", "5"],
    "decisions": ["--rounds", "10"],
    "api": ["--clients", "20", "--seconds", "5", "--warmup", "2"],
    "fair": ["--seconds", "8"],
    "rss": ["--rounds", "2", "--heavy", "2"],
    "campaign": ["-n", "12"],
    "rehearsal": [],
    "rehearsal_sim": [],
}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__,
                                     formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("names", nargs="*", metavar="NAME", help=f"of {', '.join(QUICK)}")
    parser.add_argument("--full", action="store_true", help="each module at its own sizes")
    parser.add_argument("--timeout", type=float, default=1800.0, help="seconds per module")
    args = parser.parse_args()
    unknown = [name for name in args.names if name not in QUICK]
    if unknown:
        parser.error(f"unknown benchmark {', '.join(unknown)}; known: {', '.join(QUICK)}")
    # The modules measure this checkout's code, whatever an editable install points at.
    env = dict(os.environ)
    env["PYTHONPATH"] = os.pathsep.join(
        filter(None, [str(ROOT / "backend"), str(ROOT), env.get("PYTHONPATH")]))
    results: list[tuple[str, str, float]] = []
    for name in args.names or list(QUICK):
        command = [sys.executable, "-m", f"tests.bench.bench_{name}",
                   *([] if args.full else QUICK[name])]
        print(f"\n=== bench_{name}: {' '.join(command[1:])}", flush=True)
        start = time.perf_counter()
        try:
            status = str(subprocess.run(command, cwd=ROOT, env=env, check=False,
                                        timeout=args.timeout).returncode)
        except subprocess.TimeoutExpired:
            status = f"timeout {args.timeout:g} s"
        results.append((name, status, time.perf_counter() - start))
    print(f"\n{'benchmark':<16} {'exit':>14} {'seconds':>8}")
    for name, status, seconds in results:
        print(f"{name:<16} {status:>14} {seconds:>8.1f}")
    total = sum(seconds for _, _, seconds in results)
    failed = [name for name, status, _ in results if status != "0"]
    print(f"{len(results)} run in {total:.0f} s; "
          + (f"FAILED: {', '.join(failed)}" if failed else "all green"))
    sys.exit(1 if failed else 0)


if __name__ == "__main__":
    main()
