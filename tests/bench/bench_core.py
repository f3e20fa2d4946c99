"""Benchmarks of the core (structure, path counts, streaming, bad input).

Run: .venv/bin/python -m tests.bench.bench_core

Each figure is printed with a ratio against a baseline measured in this same process.
"""

from __future__ import annotations

import argparse
import functools
import subprocess
import sys
import time
import tracemalloc
from pathlib import Path

from countersign.orders.model import Orders
from countersign.orders.reader import read_file
from countersign.verify.budget import worst_paths
from countersign.verify.graph import build_graph
from countersign.verify.paths import count_paths, iter_path_lines
from countersign.verify.structure import check_structure

from .baseline import TimeUp, naive_ndjson, naive_paths
from .generated import layered_dag, random_dag
from .timing import best_of

REFERENCE = Path(__file__).resolve().parents[2].parent / "shared/reference/nps-ethical-control"



def analyse_file(path: Path) -> None:
    orders = read_file(path).orders
    graph = build_graph(orders)
    check_structure(orders, graph)
    count_paths(graph)


def analyse_orders(orders: Orders) -> None:
    graph = build_graph(orders)
    check_structure(orders, graph)
    count_paths(graph)
    worst_paths(orders, graph)


def bench_reference(baseline_cap_s: float) -> None:
    print("\n## Reference AVCL missions: full structural analysis + path counting")
    folder = REFERENCE / "missions/avcl"
    if not folder.is_dir():
        print(f"skipped: {folder} not found")
        return
    print(f"{'mission':<50} {'goals':>5} {'ours ms':>8} {'naive engine':>14} {'ratio':>8}")
    for path in sorted(folder.glob("*.xml")):
        ours_s = best_of(5, functools.partial(analyse_file, path))
        orders = read_file(path).orders
        start = time.perf_counter()
        try:
            count = sum(1 for _ in naive_paths(orders, start + baseline_cap_s))
            naive = f"{(time.perf_counter() - start) * 1000:9.1f} ms"
            ratio = f"{(time.perf_counter() - start) / ours_s:7.2f}x"
            del count
        except TimeUp:
            naive = f"> {baseline_cap_s:.0f} s (cut)"
            ratio = f"> {baseline_cap_s / ours_s:.0f}x"
        print(f"{path.name:<50} {len(orders.goals):>5} {ours_s * 1000:8.2f} {naive:>14} {ratio:>8}")


def bench_large_dag() -> None:
    print("\n## Generated ternary DAGs: counts, loops, reachability, worst-cost paths")
    print(f"{'goals':>6} {'paths (digits)':>15} {'analysis s':>11} {'vs 1,000':>9} "
          f"{'peak MiB':>9} {'bytes/goal':>11}")
    base_time = None
    for goals in (1_000, 2_500, 5_000, 10_000, 20_000):
        orders = random_dag(goals)

        seconds = best_of(3, functools.partial(analyse_orders, orders))
        base_time = base_time or seconds
        tracemalloc.start()
        graph = build_graph(orders)
        check_structure(orders, graph)
        counts = count_paths(graph)
        worst_paths(orders, graph)
        _, peak = tracemalloc.get_traced_memory()
        tracemalloc.stop()
        assert counts is not None
        digits = len(str(counts.total))
        print(f"{goals:>6} {digits:>15} {seconds:>11.3f} {seconds / base_time:>8.1f}x "
              f"{peak / 2**20:>9.1f} {peak / goals:>11.0f}")


def bench_streaming(paths: int) -> None:
    print(f"\n## Streaming {paths:,} paths to NDJSON")
    orders = layered_dag(40)
    graph = build_graph(orders)
    counts = count_paths(graph)
    assert counts is not None

    def ours(n: int) -> None:
        with open("/dev/null", "w") as sink:
            write = sink.write
            for line in iter_path_lines(graph, counts, 0, n):
                write(line)
                write("\n")

    ours_s = best_of(3, lambda: ours(paths))
    naive_s = best_of(1, lambda: naive_ndjson(orders, paths // 10)) * 10
    print(f"ours:     {paths / ours_s:12,.0f} paths/s")
    print(f"baseline: {paths / naive_s:12,.0f} paths/s (recursive, json.dumps per path)")
    print(f"ratio:    {naive_s / ours_s:12.1f}x")
    peaks = []
    for n in (paths // 10, paths):
        tracemalloc.start()
        ours(n)
        peaks.append(tracemalloc.get_traced_memory()[1])
        tracemalloc.stop()
    print(f"peak memory: {peaks[0] / 1024:.0f} KiB for {paths // 10:,} paths, "
          f"{peaks[1] / 1024:.0f} KiB for {paths:,} (ratio {peaks[1] / peaks[0]:.2f})")


def bench_bad_input(tmp: Path) -> None:
    print("\n## Bad input: time to a clear error (whole CLI process)")
    bomb = (b'<?xml version="1.0"?><!DOCTYPE l [<!ENTITY a "aaaaaaaaaa">'
            b'<!ENTITY b "&a;&a;&a;&a;&a;&a;&a;&a;&a;&a;"><!ENTITY c "&b;&b;&b;&b;&b;&b;&b;&b;">'
            b']><AVCL><body><GoalList><Goal id="G" title="&c;"/></GoalList></body></AVCL>')
    wide = '{"id":"w","goals":[{"id":"G1","next":{' + ",".join(
        f'"o{i}":"COMPLETE"' for i in range(10_000)) + "}}]}"
    cases = {
        "empty file": b"",
        "invalid JSON": b'{"id": ',
        "JSON array": b"[]",
        "XML bomb": bomb,
        "goal with 10,000 outcomes": wide.encode(),
        "odd id characters": b'{"id": "x", "goals": [{"id": "G\\u0000 <1>"}]}',
    }
    files = {}
    for name, data in cases.items():
        files[name] = tmp / f"{len(files)}.in"
        files[name].write_bytes(data)
    big = tmp / "big.json"
    with big.open("wb") as handle:
        handle.write(b'{"id": "x", "d": "' + b"x" * (50 * 2**20) + b'"}')
    files["50 MB file"] = big
    noop = best_of(3, lambda: subprocess.run([sys.executable, "-m", "countersign.cli",
                                              "--version"], capture_output=True, check=False))
    print(f"{'input':<28} {'exit':>4} {'seconds':>8} {'minus start-up':>15}")
    for name, path in files.items():
        start = time.perf_counter()
        result = subprocess.run([sys.executable, "-m", "countersign.cli", "validate", str(path)],
                                capture_output=True, check=False)
        seconds = time.perf_counter() - start
        print(f"{name:<28} {result.returncode:>4} {seconds:>8.3f} {seconds - noop:>15.3f}")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--paths", type=int, default=1_000_000)
    parser.add_argument("--baseline-cap", type=float, default=30.0,
                        help="seconds before the naive engine is cut off")
    args = parser.parse_args()
    import tempfile

    bench_reference(args.baseline_cap)
    bench_large_dag()
    bench_streaming(args.paths)
    with tempfile.TemporaryDirectory() as tmp:
        bench_bad_input(Path(tmp))


if __name__ == "__main__":
    main()
