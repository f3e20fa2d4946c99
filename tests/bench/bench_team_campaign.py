"""Benchmark of team campaigns: the cost of one team simulation (the two-vehicle exemplar)
beside one simulation of the single-vehicle exemplar, as a ratio (no wall-clock claim), and
the cost per member simulation, which the bound (simulations x members <= 10,000) assumes is
about one vehicle's.

Run: .venv/bin/python -m tests.bench.bench_team_campaign [-n 20]
"""

from __future__ import annotations

import argparse
import time

from countersign.campaigns.simulate import Mission, simulate
from countersign.campaigns.spec import CampaignSpec
from countersign.campaigns.team import TeamMission, simulate_team
from countersign.orders.examples import load_example

FAULTS = ["none", "nav_drift", "leak"]


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("-n", type=int, default=20)
    n = parser.parse_args().n
    single = Mission(load_example("search-and-sample"))
    team = TeamMission(load_example("search-and-sample-team"))
    one = CampaignSpec.build(simulations=n, faults=FAULTS, orders=single.orders)
    two = CampaignSpec.build(simulations=n, faults=FAULTS, orders=team.orders)
    start = time.perf_counter()
    for i in range(n):
        simulate(single, i, *one.simulation(i))
    single_s = time.perf_counter() - start
    start = time.perf_counter()
    for i in range(n):
        simulate_team(team, i, *two.simulation(i))
    team_s = time.perf_counter() - start
    members = len(team.vehicles)
    print(f"{n} simulations each, faults {', '.join(FAULTS)}")
    print(f"team simulation / vehicle simulation: {team_s / single_s:.2f}")
    print(f"per member simulation / vehicle simulation: {team_s / members / single_s:.2f}")


if __name__ == "__main__":
    main()
