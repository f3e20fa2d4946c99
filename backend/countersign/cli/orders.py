"""The orders commands: validate, paths, run, export, explain, examples.

The verifier (networkx, rdflib, z3, pydantic) is imported inside each command, so that
`countersign --help` and the other commands do not pay for it.
"""

from __future__ import annotations

import argparse
import json
import sys
from typing import TYPE_CHECKING, Any, TextIO

from .common import (
    EXIT_FINDINGS,
    EXIT_OK,
    FILE_HELP,
    SOLVER_BUDGET_S,
    UsageError,
    budget_seconds,
    load_orders,
    loading,
    member_orders,
    non_negative,
)
from .export_vehicle import add_export_arguments
from .procedures import add_library_argument, with_library

if TYPE_CHECKING:
    from ..orders.reader import ReadResult
    from ..verify.report import Report

ANSWERS = {
    "s": "succeed", "succeed": "succeed", "success": "succeed",
    "f": "fail", "fail": "fail", "failure": "fail",
    "c": "violate", "constraint": "violate", "x": "violate", "violate": "violate",
}


def _print_report_text(report: Report, out: TextIO) -> None:
    out.write(f"Mission {report.mission}  {report.digest}\n")
    errors = sum(f.severity == "error" for f in report.findings)
    warnings = len(report.findings) - errors
    for finding in report.findings:
        subjects = ", ".join(finding.subjects)
        out.write(f"  {finding.severity:<7} {finding.code:<13} [{subjects}]\n")
        out.write(f"          {finding.message}\n")
    if report.team is not None:
        from ..verify.team_report import summary_lines as team_lines

        out.write("".join(f"{line}\n" for line in team_lines(report.team)))
    elif report.paths is None:
        out.write("Paths: not countable until the errors above are fixed.\n")
    else:
        parts = ", ".join(f"{n} to {t}" for t, n in report.paths.by_terminal.items())
        out.write(f"Paths: {report.paths.total} ({parts})\n")
    for quantity, worst in (report.costs or {}).items():
        limit = f" of budget {worst.budget:g}" if worst.budget is not None else ""
        out.write(f"Worst {quantity}: {worst.total:g}{limit}\n")
    if report.probabilities is not None:
        from ..verify.probability import summary_lines

        out.write("\n".join(summary_lines(report.probabilities)) + "\n")
    verdict = "OK" if report.ok else "NOT OK"
    out.write(f"{verdict}: {errors} error(s), {warnings} warning(s).\n")


def _print_explanation(report: Report, out: TextIO) -> None:
    explanation = report.explanation or {}
    out.write("\nWhy (facts the Mission Execution Ontology infers, with their rules):\n")
    for fact in explanation.get("facts", []):
        rule = f" [{fact['rule']}]" if fact.get("rule") else ""
        out.write(f"  {fact['subject']} {fact['property']} {fact['object']}{rule}\n")
    scope = explanation.get("constraint_scope") or {}
    if scope:
        out.write("Constraint scope after C3 (mission constraints apply to every goal):\n")
        for constraint, goals in scope.items():
            out.write(f"  {constraint}: {', '.join(goals)}\n")


def cmd_validate(args: argparse.Namespace) -> int:
    with loading(args):
        from ..verify.parts import NoParts
        from ..verify.report import validate

    loaded = with_library(load_orders(args.file, teams=True), args.procedures)
    if args.explain and loaded.orders.team is not None:
        raise UsageError("--explain shows the ontology's facts about one vehicle's orders; "
                         "give a member's orders (team[i].orders)")
    # One validation: parts kept for a later one of the same orders would never be read.
    report = validate(loaded.orders, loaded.findings, solver_budget_s=args.solver_budget,
                      parts=NoParts())
    if args.format == "json":
        json.dump(report.to_json(explain=args.explain), sys.stdout, indent=2)
        sys.stdout.write("\n")
    else:
        _print_report_text(report, sys.stdout)
        if args.explain:
            _print_explanation(report, sys.stdout)
    return EXIT_OK if report.ok else EXIT_FINDINGS


def _refuse_structural_errors(loaded: ReadResult, why: str) -> int | None:
    """Print the structural errors that stop a command (why: what cannot be done), if any."""
    from ..verify.structure import check_structure

    errors = [f for f in check_structure(loaded.orders) if f.severity == "error"]
    if not errors:
        return None
    sys.stderr.write(f"countersign: {why}:\n")
    for finding in errors[:10]:
        sys.stderr.write(f"  {finding.code}: {finding.message}\n")
    return EXIT_FINDINGS


def cmd_paths(args: argparse.Namespace) -> int:
    from ..verify.paths import count_paths, iter_path_lines, iter_paths, trace_text
    from ..verify.refine import checked_form

    loaded = with_library(load_orders(args.file), args.procedures)
    # Refined goals run as their refinements: the paths are those of the flat mission.
    orders, graph = checked_form(loaded.orders)
    counts = count_paths(graph)
    if counts is None:
        refused = _refuse_structural_errors(
            loaded, f"the paths of {args.file} cannot be enumerated")
        return refused if refused is not None else EXIT_FINDINGS
    out = sys.stdout
    from ..orders.model import declares_probabilities
    from ..verify.probability import path_probability_bounds

    # Each path's probability (or its bounds) when the orders declare outcome probabilities.
    bounds = (path_probability_bounds(orders, graph)
              if declares_probabilities(orders) else None)
    if args.format == "trace":
        for path in iter_paths(graph, counts, args.offset, args.limit):
            out.write(trace_text(graph, path) + "\n")
    else:
        for line in iter_path_lines(graph, counts, args.offset, args.limit, bounds):
            out.write(line + "\n")
    out.flush()
    return EXIT_OK


def _ask(prompt_echo: bool, indent: str = "") -> str | None:
    """One answer from the operator: the outcome, or None at end of input. `indent`: the
    goal's depth inside refinements, as its Commence line has it."""
    from ..verify.paths import ANSWER, QUESTION

    while True:
        sys.stdout.write(f"{indent}{QUESTION} ")
        sys.stdout.flush()
        line = sys.stdin.readline()
        if not line:
            sys.stdout.write("\n")
            return None
        answer = ANSWERS.get(line.strip().lower().rstrip("."))
        if answer is not None:
            if prompt_echo:
                sys.stdout.write(f"{ANSWER[answer]}.\n")
            return answer
        if prompt_echo:
            sys.stdout.write(f"{line.strip()}\n")
        sys.stdout.write(
            "Please answer s (the goal succeeded), f (it failed) or c (it ended with an "
            "imminent constraint violation).\n"
        )


def cmd_run(args: argparse.Namespace) -> int:
    from ..verify.paths import (
        END_LINE,
        INDENT,
        commence_line,
        nested_answer,
        nested_commence,
    )
    from ..verify.refine import checked_form

    loaded = with_library(load_orders(args.file), args.procedures)
    refused = _refuse_structural_errors(loaded, "these orders cannot be executed until fixed")
    if refused is not None:
        return refused
    _, graph = checked_form(loaded.orders)
    if graph.start is None:
        sys.stderr.write("countersign: these orders cannot be executed until their "
                         "refinements are fixed (countersign validate says how)\n")
        return EXIT_FINDINGS
    echo = not sys.stdin.isatty()
    sys.stdout.write("?- execute_mission.\n")
    node = graph.start
    inside: list[str] = []  # refined goals begun and not ended
    while not graph.is_terminal(node):
        goal = graph.goals[node]
        if graph.nesting is None:
            sys.stdout.write(commence_line(goal.label) + "\n")
        else:
            lines = nested_commence(graph.nesting, inside, goal.id, goal.label)
            sys.stdout.write("".join(line + "\n" for line in lines))
        depth = len(graph.nesting.parents.get(goal.id, ())) if graph.nesting else 0
        answer = _ask(echo, INDENT * depth)
        if answer is None:
            sys.stdout.write(f"Mission execution stopped: no outcome given for {goal.id}.\n")
            return EXIT_FINDINGS
        if graph.nesting is not None:
            # The refinements this outcome ends answer for their refined goals.
            lines = nested_answer(graph.nesting, inside, goal.id, answer)[1:]
            sys.stdout.write("".join(line + "\n" for line in lines))
        k = ("succeed", "fail", "violate").index(answer)
        if graph.succ[node][k] < 0:
            sys.stderr.write(f"countersign: {goal.id} has no way on after {answer}\n")
            return EXIT_FINDINGS
        node = graph.succ[node][k]
    sys.stdout.write(END_LINE[graph.terminal(node).kind] + "\n")
    return EXIT_OK


def cmd_export(args: argparse.Namespace) -> int:
    from ..rules.plain_orders import write_for_supervisor

    # A team is one vehicle's files per member (--member); plain and json also write the team.
    vehicle_format = args.format in ("imc", "moos", "avcl")
    teams = vehicle_format or args.member is not None or args.format in ("plain", "json")
    loaded = with_library(load_orders(args.file, teams=teams), args.procedures)
    orders = loaded.orders
    if vehicle_format or args.member is not None:
        orders = member_orders(orders, args.member, what=f"--format {args.format}")
    if args.format in ("imc", "moos"):
        from .export_vehicle import write_vehicle_export

        return write_vehicle_export(loaded.orders, args)
    if args.format == "avcl":
        from ..export.avcl import export_avcl
        from ..export.team import select_member
        from .export_vehicle import print_notes

        export = export_avcl(orders, select_member(loaded.orders, args.member))
        sys.stdout.write(export.primary.content.decode("utf-8"))
        print_notes(export)
        return EXIT_OK
    sys.stdout.write(write_for_supervisor(orders, args.format))
    return EXIT_OK


def cmd_explain(args: argparse.Namespace) -> int:
    from ..verify.logic import UnknownIds, explain_goal_set, format_goal_set

    loaded = load_orders(args.file)
    goals = [g for g in args.goals.split(",") if g] if args.goals else None
    constraints = [c for c in args.constraints.split(",") if c] if args.constraints else None
    try:
        result = explain_goal_set(loaded.orders, goals, constraints)
    except UnknownIds as exc:
        raise UsageError(str(exc)) from None
    if args.format == "json":
        sys.stdout.write(json.dumps(result.to_json(), indent=2) + "\n")
    else:
        sys.stdout.write(format_goal_set(result).rstrip("\n") + "\n")
    return EXIT_OK if result.consistent is True else EXIT_FINDINGS


def cmd_examples(args: argparse.Namespace) -> int:
    from ..orders.examples import example_bytes, example_names, team_example_names

    if args.name is None:
        for name in example_names():
            sys.stdout.write(f"{name}\n")
        # One name a line, so scripts can loop over them; team orders are named *-team.
        for name in team_example_names():
            sys.stdout.write(f"{name}\n")
        return EXIT_OK
    try:
        sys.stdout.write(example_bytes(args.name).decode("utf-8"))
    except KeyError as exc:
        raise UsageError(str(exc.args[0])) from None
    return EXIT_OK


def add_commands(commands: Any) -> None:
    validate_cmd = commands.add_parser(
        "validate",
        help="check orders: structure, paths, budget, contradictions, norms, properties, "
        "contingency rules",
        description="Check orders and count every path. Exit 0 no errors, 1 errors, "
        "2 unreadable input. The command line has no vehicle registry: orders must carry the "
        "profile of their target vehicle, or VEHICLE is reported (an error). When goals (or "
        "the vehicle, per behaviour) carry outcome probabilities `p`, it also prints the exact "
        "probability of each terminal and of any violation, the expected energy and time "
        "with quantiles, and min/max where probabilities are intervals or missing. "
        "Orders with a `team` (one member's orders per vehicle; goals with the same `meet` "
        "id are one meeting) are checked member by member, findings scoped `VEHICLE/ID`, "
        "then TEAM: a meeting where a member can wait for a partner that ended or went past "
        "it, named with the shortest joint path (`v1/G1 violate, v2/G1 violate -> (v1/G4, "
        "v2/ABORT)`); it prints each member's paths and costs and the joint executions by "
        "where each member ends (example:search-and-sample-team). "
        "A goal "
        "with `refines` (sub-orders whose terminals each `return` succeed, fail or violate) "
        "is carried out by them: each refinement is checked as orders, REFINE reports a "
        "terminal that returns no outcome or one the parent does not use and a loop without "
        "a time-out (`within` steps or duration_s, `on_timeout` fail or violate), and paths, "
        "budgets and probabilities are those of the flat, bounded unrolling.",
    )
    validate_cmd.add_argument("file", metavar="FILE", help=FILE_HELP)
    validate_cmd.add_argument("--format", choices=["text", "json"], default="text")
    validate_cmd.add_argument(
        "--explain", action="store_true",
        help="also show why: the facts the MEO infers (includes, canIdentify, hasCapability, "
        "performableBy, constraint scope after C3)",
    )
    validate_cmd.add_argument(
        "--solver-budget", type=budget_seconds, default=SOLVER_BUDGET_S, metavar="SECONDS",
        help=f"solver CPU time for the whole validation (default {SOLVER_BUDGET_S:g}, as the "
        "server allows; it stops at 4 times as much wall time in any case); what it leaves "
        "undecided is reported as a warning")
    add_library_argument(validate_cmd)
    validate_cmd.set_defaults(handler=cmd_validate)

    paths_cmd = commands.add_parser(
        "paths",
        help="enumerate every path lazily (succeed, fail, violate first)",
        description="Enumerate the paths from the start goal to a terminal, depth first in "
        "the order succeed, fail, violate. 'json' writes one JSON object per line (NDJSON): "
        '{"index", "goals", "outcomes", "terminal"} plus "probability" (a number, or [min, max]) '
        "when the orders carry outcome probabilities; 'trace' writes Figure 6 traces. The goals "
        "inside a refined goal read G1/G1.1 (G1/G1.1#k: the k-th goal commenced inside a "
        "refinement with a steps time-out; @Ts: after T seconds inside one with duration_s); "
        "a trace indents each refinement's lines under its goal's Commence line and then "
        "answers for that goal with the outcome its refinement returned.",
    )
    paths_cmd.add_argument("file", metavar="FILE", help=FILE_HELP)
    paths_cmd.add_argument("--limit", type=non_negative, default=None, help="at most N paths")
    paths_cmd.add_argument(
        "--offset", type=non_negative, default=0, help="skip the first N paths (instantly)"
    )
    paths_cmd.add_argument(
        "--format", choices=["json", "ndjson", "trace"], default="json",
        help="json/ndjson: one path per line; trace: execution traces",
    )
    add_library_argument(paths_cmd)
    paths_cmd.set_defaults(handler=cmd_paths)

    run_cmd = commands.add_parser(
        "run",
        help="execute the orders interactively (the MEE of seed 000 Figure 6)",
        description="Commence each goal and ask whether it succeeded (s), failed (f) or ended "
        "with an imminent constraint violation (c), until the mission completes or aborts. "
        "A refined goal commences its refinement's goals (indented); its own outcome is the "
        "one its refinement returns.",
    )
    run_cmd.add_argument("file", metavar="FILE", help=FILE_HELP)
    add_library_argument(run_cmd)
    run_cmd.set_defaults(handler=cmd_run)

    export_cmd = commands.add_parser(
        "export",
        help="write orders as plain language, JSON, DOT, Turtle, AVCL, or IMC/MOOS-IvP "
        "for a vehicle",
        description="Convert orders between formats: the plain-language orders a supervisor "
        "reads (seed 000 Figures 3 and 4; with a \"Contingency rules\" section, one sentence "
        "per rule, when the orders or their vehicle carry rules), orders JSON, a Graphviz DOT "
        "graph, MEO Turtle (lossless), an NPS MEO 3.0 Turtle view, or AVCL 3.1 XML (valid "
        "against the NPS AVCL.3.1.xsd); or for a vehicle: an IMC PlanSpecification (imc, "
        "binary) or MOOS-IvP helm behaviours plus uSimMarine lines (moos); a refined goal "
        "becomes the maneuvers of its goals, ids carrying the hierarchy (imc: G1/G1.2#2), or "
        "a helm mode holding its goals' modes (moos: ACTIVE:G1:G1_2_k2). Team orders: "
        "--member VEHICLE writes that member's files (any format; imc, moos and avcl need it); "
        "a meeting goal holds at its point and waits for every partner (moos: posts "
        "MEET_<id>_ARRIVED = <vehicle>, leaves after MEET_<id>_ALL = true; the .moos names what "
        "a pShare bridge carries; imc: custom meet, meet.partners). What AVCL or a "
        "vehicle format cannot carry is printed to standard error as notes (code, path, "
        "message).",
    )
    export_cmd.add_argument("file", metavar="FILE", help=FILE_HELP)
    export_cmd.add_argument(
        "--format",
        choices=["plain", "json", "dot", "turtle", "nps-turtle", "avcl", "imc", "moos"],
        default="plain",
    )
    add_export_arguments(export_cmd)
    add_library_argument(export_cmd)
    export_cmd.set_defaults(handler=cmd_export)

    explain_cmd = commands.add_parser(
        "explain",
        help="can these goals and constraints hold together? (minimal incompatible subset)",
        description="Check whether a set of goals and the constraints in their scope can hold "
        "together (z3). If not, print a minimal incompatible subset: removing any one of its "
        "members makes the rest consistent. Exit 0 consistent, 1 incompatible or undecided, "
        "2 unreadable input or unknown ids.",
    )
    explain_cmd.add_argument("file", metavar="FILE", help=FILE_HELP)
    explain_cmd.add_argument("--goals", default=None,
                             help="comma-separated goal ids (default: every goal)")
    explain_cmd.add_argument(
        "--constraints", default=None,
        help="comma-separated constraint ids (default: every constraint applying to the goals)",
    )
    explain_cmd.add_argument("--format", choices=["text", "json"], default="text")
    explain_cmd.set_defaults(handler=cmd_explain)

    examples_cmd = commands.add_parser(
        "examples", help="list the built-in example orders, or print one"
    )
    examples_cmd.add_argument("name", nargs="?", help="print this example's orders JSON")
    examples_cmd.set_defaults(handler=cmd_examples)
