"""Start-up of the command line as whole processes.

Targets: `countersign --help` under 0.3 s and `countersign validate` of the exemplar
(example:search-and-sample, seed 000 Figures 3-7) under 0.8 s wall (the goal is 0.3 s of
CPU), beside `python -c pass`.
Each figure is the median of 5 runs (--runs N): wall seconds and CPU seconds (user + system of
the child; on a shared, busy machine the wall figure includes waiting for a core, the CPU figure
does not).

The children run as an installed Countersign runs: with Python's bytecode cache (pip compiles
an installed package; an editable checkout writes `__pycache__` on its first run, the warm-up
here). PYTHONDONTWRITEBYTECODE in the caller's environment is dropped for them, since with it
every run would compile Countersign's 80-odd modules again (about 0.3 s of `validate` on a
quiet machine), which is not how it runs once installed.

With `--baseline DIR` (a `backend` folder of another commit, e.g. extracted with
`git archive COMMIT backend ontology | tar -x -C /tmp/base`) each command runs with that code
too, interleaved with this checkout's runs, so that both figures share the machine's load.

Run: .venv/bin/python -m tests.bench.bench_startup [--baseline /tmp/base/backend]
"""

from __future__ import annotations

import argparse
import os
import resource
import statistics
import subprocess
import sys
import time

RUNS = 5
COMMANDS: dict[str, list[str]] = {
    "python -c pass": [sys.executable, "-c", "pass"],
    "countersign --help": [sys.executable, "-m", "countersign.cli", "--help"],
    "countersign validate example:search-and-sample": [
        sys.executable, "-m", "countersign.cli", "validate", "example:search-and-sample"],
}
TARGETS = {"countersign --help": 0.3, "countersign validate example:search-and-sample": 0.8}
CPU_TARGETS = {"countersign validate example:search-and-sample": 0.3}
CACHED_ENV = {k: v for k, v in os.environ.items() if k != "PYTHONDONTWRITEBYTECODE"}


def _children_cpu() -> float:
    # getrusage counts in microseconds; os.times() in clock ticks (10 ms here), too coarse for
    # a difference of a few milliseconds between medians.
    usage = resource.getrusage(resource.RUSAGE_CHILDREN)
    return usage.ru_utime + usage.ru_stime


def _run_once(argv: list[str], env: dict[str, str] | None = None) -> tuple[float, float]:
    before = _children_cpu()
    start = time.perf_counter()
    subprocess.run(argv, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, check=False,
                   env=env if env is not None else CACHED_ENV)
    wall = time.perf_counter() - start
    return wall, _children_cpu() - before


def measure(argv: list[str], runs: int = RUNS,
            env: dict[str, str] | None = None) -> tuple[float, float]:
    """Median wall and CPU seconds over `runs` runs (one warm-up run first: .pyc files)."""
    _run_once(argv, env)
    samples = [_run_once(argv, env) for _ in range(runs)]
    return (statistics.median(s[0] for s in samples), statistics.median(s[1] for s in samples))


def _with_path(backend: str) -> dict[str, str]:
    return {**CACHED_ENV, "PYTHONPATH": backend}


def measure_side_by_side(argv: list[str], baseline: str,
                         runs: int = RUNS) -> tuple[tuple[float, float], tuple[float, float]]:
    """Medians (wall, CPU) of this checkout and of the baseline's code, runs interleaved."""
    ours, theirs = CACHED_ENV, _with_path(baseline)
    _run_once(argv, ours)
    _run_once(argv, theirs)
    pairs = [(_run_once(argv, ours), _run_once(argv, theirs)) for _ in range(runs)]

    def medians(samples: list[tuple[float, float]]) -> tuple[float, float]:
        return (statistics.median(s[0] for s in samples),
                statistics.median(s[1] for s in samples))

    return medians([p[0] for p in pairs]), medians([p[1] for p in pairs])


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--baseline", metavar="DIR",
                        help="a backend folder of other code to run beside this checkout's")
    parser.add_argument("--runs", type=int, default=RUNS, metavar="N",
                        help=f"runs of each command, the median shown (default {RUNS})")
    args = parser.parse_args()
    figures: dict[str, tuple[float, float]] = {}
    for label, argv in COMMANDS.items():
        if args.baseline and label != "python -c pass":
            figures[label], figures[f"  baseline: {label}"] = measure_side_by_side(
                argv, args.baseline, args.runs)
        else:
            figures[label] = measure(argv, args.runs)
    _, base_cpu = figures["python -c pass"]
    print(f"{'command':<60} {'wall s':>7} {'cpu s':>7} {'x pass (cpu)':>13} {'target':>7} "
          f"{'cpu target':>10}")
    for label, (wall, cpu) in figures.items():
        target, cpu_target = TARGETS.get(label), CPU_TARGETS.get(label)
        shown = f"{target:g}" if target is not None else "-"
        shown_cpu = f"{cpu_target:g}" if cpu_target is not None else "-"
        ratio = cpu / base_cpu if base_cpu > 0 else float("nan")
        print(f"{label:<60} {wall:7.3f} {cpu:7.3f} {ratio:13.1f} {shown:>7} {shown_cpu:>10}")
    for label, cpu_target in CPU_TARGETS.items():
        _, cpu = figures[label]
        verdict = "met" if cpu < cpu_target else "NOT met"
        line = f"{label}: {cpu:.3f} s CPU, goal < {cpu_target:g} s: {verdict}"
        if f"  baseline: {label}" in figures:
            _, base = figures[f"  baseline: {label}"]
            line += f"; baseline {base:.3f} s ({(cpu - base) / base:+.0%})"
        print(line)
    print(f"(median of {args.runs} runs each; load average {os.getloadavg()[0]:.1f})")


if __name__ == "__main__":
    main()
