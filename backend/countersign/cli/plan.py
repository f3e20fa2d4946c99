"""`countersign plan`: the survey planner of seed 001 (GRAVITAS) on the command line.

Registered by cli.py through `add_commands`. Exit codes: 0 a plan (or a checked plan that
holds), 1 no feasible plan, a plan that fails its check, or a timeout, 2 unreadable input or
bad usage (as every other command).
"""

from __future__ import annotations

import argparse
import json
import sys
import time
from collections.abc import Callable
from typing import TYPE_CHECKING, Any, TextIO

if TYPE_CHECKING:
    from ..plan.model import PlanProblem
    from ..plan.solver import Plan

EXIT_OK, EXIT_NO_PLAN, EXIT_UNREADABLE = 0, 1, 2

# plan.examples.EXAMPLES, named here so that help does not import the planner
# (tests/cli/test_cli_startup.py holds the two equal).
EXAMPLE_NAMES = ("gravitas", "gravitas-currency", "gravitas-level1", "gravitas-replan")

PROBLEM_HELP = (
    "planning problem JSON (countersign.plan/1); '-' reads standard input, "
    f"'example:NAME' a built-in example ({', '.join(EXAMPLE_NAMES)})"
)

DESCRIPTION = """\
Choose which survey areas to visit, in which order and (level 2) with which pass (entry and
exit point), so that the vehicle collects the most reward and then uses the least energy,
never more than its battery less its reserve, and always surveys every mandatory area.
The answer is exact (dynamic programming over every subset, order and pass) and comes with
draft orders (countersign.orders/1) that `countersign validate` accepts with no BUDGET finding:
one goal per area in plan order (succeed or fail go on, violate returns to recovery) and a
final recovery goal, with energy costs and the vehicle budget filled in.

Problem format (metres in a local frame):
  {"format": "countersign.plan/1", "level": 2, "start": [0, 0], "recovery": [8000, 0],
   "vehicle": {"transit_wh_per_m": 1.0, "battery_wh": 60000, "reserve_wh": 2000},
   "areas": [{"id": "LL", "title": "Lower left", "reward": 22807, "mandatory": false,
              "passes": [{"entry": [1000, 1000], "exit": [3000, 1000], "survey_wh": 13000}]}]}

Common currency (optional, seed 001 section 5.3): with
  "conversion": {"energy_wh": {"kind": "linear", "rate": 2.0}}
each Wh costs 2 reward units and the best plan maximises reward less converted energy
("value"); "kind": "exponential" with "rate" and "scale" costs scale * (exp(rate * Wh) - 1),
so the last Wh are dearer than the first. Try example:gravitas-currency.

When no plan is feasible, it prints a minimal set of mandatory areas that cannot be surveyed
together (drop any one and the rest fit). With --check PLAN it verifies a plan from another
source ({"order": [...], "passes": {...}}, e.g. a previous output) and explains the first
condition it breaks.
"""

EPILOG = """\
examples:
  countersign plan example:gravitas                  the three-area GRAVITAS survey
  countersign plan example:gravitas-replan           after a 62% rise in consumption
  countersign plan example:gravitas-currency         each Wh worth 2 reward units
  countersign plan survey.json --format json --orders-out draft.json
  countersign plan survey.json --check other-plan.json

exit codes: 0 plan found (or checked plan holds), 1 no feasible plan, the checked plan
fails, or the timeout passed, 2 unreadable input or bad usage.
"""


def _usage_error(message: str) -> Exception:
    from .common import UsageError

    return UsageError(message)


def _source_bytes(source: str) -> tuple[bytes, str]:
    from ..plan.model import read_path_bytes

    if source == "-":
        from ..limits import MAX_INPUT_BYTES

        return sys.stdin.buffer.read(MAX_INPUT_BYTES + 1), "standard input"
    return read_path_bytes(source), source


def load_problem(source: str) -> PlanProblem:
    from ..plan.examples import example_problem
    from ..plan.model import read_bytes

    if source.startswith("example:"):
        try:
            return example_problem(source.removeprefix("example:"))
        except KeyError as exc:
            raise _usage_error(str(exc.args[0])) from None
    data, name = _source_bytes(source)
    return read_bytes(data, name)


def _write_text(problem: PlanProblem, plan: Plan, out: TextIO) -> None:
    if not plan.feasible:
        out.write(f"No feasible plan: {plan.message}.\n")
        if plan.conflict:
            out.write(f"Minimal conflicting mandatory areas: {', '.join(plan.conflict)}\n")
        return
    areas = {area.id: area for area in problem.areas}
    out.write(
        f"Plan (level {problem.level}): reward {plan.reward:g}, energy {plan.energy_wh:,.1f} Wh "
        f"of {plan.limit_wh:,.1f} Wh\n"
    )
    for number, step in enumerate(plan.steps, start=1):
        area = areas[step.area]
        flag = " (mandatory)" if area.mandatory else ""
        name = area.passes[step.pass_index].title
        pass_name = f"pass {step.pass_index}" + (f" ({name})" if name else "")
        out.write(
            f"  {number}. {area.id} {area.title}{flag}: {pass_name}, transit "
            f"{step.leg_wh:,.1f} Wh + survey {step.survey_wh:,.1f} Wh, reward {area.reward:g}\n"
        )
    out.write(f"  then recovery: transit {plan.return_wh:,.1f} Wh\n")
    if problem.conversion:
        out.write(f"Value {plan.value:,.1f}: reward less energy in the common currency\n")
    skipped = [a.id for a in problem.areas if a.id not in plan.passes]
    if skipped:
        out.write(f"Not surveyed: {', '.join(skipped)}\n")
    seconds = plan.stats.get("seconds")
    if isinstance(seconds, float):
        out.write(f"Solved exactly over {plan.stats['states']:,} states in {seconds:.3f} s.\n")


def cmd_plan(args: argparse.Namespace) -> int:
    from ..orders.canonical import orders_to_json
    from ..plan.check import check_plan, plan_from_data
    from ..plan.draft import orders_from_plan
    from ..plan.model import PlanReadError, json_from_bytes
    from ..plan.solver import PlanTimeout, PlanTooLarge, solve

    problem = load_problem(args.file)
    if args.check is not None:
        try:
            data, name = _source_bytes(args.check)
            order, passes = plan_from_data(json_from_bytes(data, name))
        except PlanReadError as exc:
            sys.stderr.write(f"countersign: cannot read the plan {args.check}:\n")
            for line in exc.summary().splitlines():
                sys.stderr.write(f"  {line}\n")
            return EXIT_UNREADABLE
        checked = check_plan(problem, order, passes)
        if args.format == "json":
            json.dump(checked.to_json(), sys.stdout, indent=2)
            sys.stdout.write("\n")
        else:
            verdict = "OK" if checked.ok else "NOT OK"
            sys.stdout.write(f"{verdict}: {checked.message}\n")
        return EXIT_OK if checked.ok else EXIT_NO_PLAN
    try:
        plan = solve(problem, timeout_s=args.timeout, progress=_progress_reporter())
    except PlanTooLarge as exc:
        raise _usage_error(str(exc)) from None
    except PlanTimeout as exc:
        sys.stderr.write(f"countersign: {exc}\n")
        return EXIT_NO_PLAN
    orders = orders_from_plan(problem, plan, args.id, args.title) if plan.feasible else None
    if orders is not None and args.orders_out:
        _write_orders(orders_to_json(orders), args.orders_out)
    if args.format == "json":
        result: dict[str, Any] = plan.to_json()
        if orders is not None:
            result["orders"] = orders_to_json(orders)
        json.dump(result, sys.stdout, indent=2)
        sys.stdout.write("\n")
    else:
        _write_text(problem, plan, sys.stdout)
        if args.orders_out and orders is not None:
            sys.stdout.write(f"Draft orders written to {args.orders_out}; check them with "
                             f"`countersign validate {args.orders_out}`.\n")
    return EXIT_OK if plan.feasible else EXIT_NO_PLAN


def _progress_reporter() -> Callable[[int, int], None] | None:
    """Progress on a terminal for solves that take more than a second."""
    if not sys.stderr.isatty():
        return None
    started = time.perf_counter()
    shown = [0.0]

    def report(done: int, total: int) -> None:
        now = time.perf_counter()
        if now - started < 1.0 or (now - shown[0] < 0.5 and done < total):
            return
        shown[0] = now
        end = "\n" if done >= total else ""
        sys.stderr.write(f"\rplanning: {100 * done // total}% of {total:,} subsets{end}")
        sys.stderr.flush()

    return report


def _write_orders(data: dict[str, Any], target: str) -> None:
    text = json.dumps(data, indent=2) + "\n"
    if target == "-":
        sys.stdout.write(text)
        return
    try:
        with open(target, "w", encoding="utf-8") as handle:
            handle.write(text)
    except OSError as exc:
        raise _usage_error(f"cannot write {target}: {exc.strerror}") from None


def _positive_seconds(text: str) -> float:
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"{text!r} is not a number of seconds") from None
    if not value > 0:
        raise argparse.ArgumentTypeError("must be more than 0 seconds")
    return value


def add_commands(commands: argparse._SubParsersAction) -> None:  # type: ignore[type-arg]
    """Register `plan` on the `countersign` command's subparsers."""
    plan_cmd = commands.add_parser(
        "plan",
        help="choose survey areas, order and passes under an energy budget; draft the orders",
        description=DESCRIPTION,
        epilog=EPILOG,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    plan_cmd.add_argument("file", metavar="PROBLEM", help=PROBLEM_HELP)
    plan_cmd.add_argument("--format", choices=["text", "json"], default="text",
                          help='json: {"reward", "energy_wh", "value", "order", "passes", '
                          '"orders", ...}')
    plan_cmd.add_argument("--check", metavar="PLAN", default=None,
                          help="verify this plan (JSON with order and passes) instead of planning")
    plan_cmd.add_argument("--orders-out", metavar="FILE", default=None,
                          help="also write the draft orders JSON to FILE ('-' for standard output)")
    plan_cmd.add_argument("--id", default="survey-plan", help="mission id of the draft orders")
    plan_cmd.add_argument("--title", default="Survey plan", help="title of the draft orders")
    plan_cmd.add_argument("--timeout", type=_positive_seconds, default=60.0,
                          help="give up after this many seconds (default 60)")
    plan_cmd.set_defaults(handler=cmd_plan)
