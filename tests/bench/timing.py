"""The benchmarks' clocks: the best of a few wall-clock runs, and CPU seconds of one run."""

from __future__ import annotations

import gc
import time
from collections.abc import Callable


def best_of(runs: int, action: Callable[[], object]) -> float:
    """The fastest of `runs` wall-clock runs (each after a collection), in seconds."""
    best = float("inf")
    for _ in range(runs):
        gc.collect()
        start = time.perf_counter()
        action()
        best = min(best, time.perf_counter() - start)
    return best


def cpu(action: Callable[[], object]) -> float:
    """CPU seconds of one run (on a shared machine wall time also measures the load)."""
    gc.collect()
    start = time.process_time()
    action()
    return time.process_time() - start
