"""Benchmark of: vehicle exports of generated orders, against the structure check the
export runs first (measured in this same process, the baseline).

Run: .venv/bin/python -m tests.bench.bench_export
"""

from __future__ import annotations

from countersign.export.vehicle import export_vehicle
from countersign.verify.structure import check_structure

from .generated import random_dag
from .timing import best_of


def main() -> None:
    print(f"{'format':<6} {'goals':>6} {'bytes':>10} {'export s':>9} {'check s':>8} {'ratio':>6}")
    for fmt, sizes in (("imc", (50, 200)), ("moos", (100, 1_000, 10_000))):
        for goals in sizes:
            orders = random_dag(goals)
            runs = 3 if goals <= 1_000 else 1
            baseline = best_of(runs, lambda o=orders: check_structure(o))
            export = export_vehicle(orders, fmt)
            seconds = best_of(runs, lambda o=orders, f=fmt: export_vehicle(o, f))
            size = sum(len(f.content) for f in export.files)
            print(f"{fmt:<6} {goals:>6} {size:>10,} {seconds:>9.3f} {baseline:>8.3f} "
                  f"{seconds / baseline:>6.1f}x")


if __name__ == "__main__":
    main()
