"""`countersign rules`: show contingency rules, their extension and the eq. 17 verdict."""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path
from typing import TYPE_CHECKING, Any, TextIO

from .. import strict_json

if TYPE_CHECKING:
    from ..orders.findings import Finding
    from ..rules import ActionVerdict, DefaultTheory, Extension

EXIT_OK, EXIT_FINDINGS, EXIT_UNREADABLE = 0, 1, 2

DESCRIPTION = """\
Show the contingency rules (a normal default theory, seed 004) of orders, a vehicle profile
or a theory file in plain English, check them against the seed's design patterns (RULES
findings), compute what the vehicle concludes from the given observations (the extension:
fired and blocked rules, goals, safety actions), and check a planned action with seed 004
equation (17): allowed, overridden by a do_safe action, or refused."""

EPILOG = """\
FILE is orders (JSON, AVCL, Turtle) carrying "rules", a JSON theory ({"rules": {...}} or the
rules object itself), 'example:NAME' for built-in orders, 'theory:NAME' for a built-in theory
({theories}) or '-' for standard input.

examples:
  countersign rules theory:transect \\
      --observe "localisation_precision_low,transect_done(t1)" --action transect_t2
  countersign rules example:search-and-sample-rules \\
      --observe "safety_sensor_failure(leak)" --action area_search
  countersign rules example:transect-survey --format json \\
      --observe gps_was_captured=false,usbl_was_captured=false

exit codes: 0 no error findings, 1 error findings (design errors in the rules),
2 unreadable input, unreadable rules or bad usage."""


class RulesUsageError(Exception):
    """Bad input the user can fix; exit code 2. Caught here rather than by cli.main, which may
    run as __main__ with its own copy of UsageError."""


def _usage_error(message: str) -> Exception:
    return RulesUsageError(message)


def _read_source(source: str) -> tuple[bytes, str]:
    from ..limits import MAX_INPUT_BYTES

    if source == "-":
        return sys.stdin.buffer.read(MAX_INPUT_BYTES + 1), "standard input"
    try:
        with Path(source).open("rb") as handle:
            return handle.read(MAX_INPUT_BYTES + 1), source
    except OSError as exc:
        raise _usage_error(f"cannot read {source}: {exc.strerror or exc}") from None


def load_rules(source: str) -> tuple[DefaultTheory, list[Finding], str]:
    """The theory named by `source`, its design findings and a label for output."""
    from ..limits import MAX_INPUT_BYTES, MIB
    from ..orders.examples import example_bytes
    from ..orders.reader import read_bytes
    from ..rules import design_findings, load_theory, parse_theory, theory_for

    if source.startswith("theory:"):
        try:
            theory = load_theory(source.removeprefix("theory:"))
        except KeyError as exc:
            raise _usage_error(str(exc.args[0])) from None
        return theory, design_findings(theory), source
    if source.startswith("example:"):
        try:
            data, name = example_bytes(source.removeprefix("example:")), source
        except KeyError as exc:
            raise _usage_error(str(exc.args[0])) from None
    else:
        data, name = _read_source(source)
    if len(data) > MAX_INPUT_BYTES:
        raise _usage_error(f"{name} is larger than the {MAX_INPUT_BYTES // MIB} MiB limit")
    parsed: Any = None
    if data.lstrip()[:1] == b"{":
        try:
            parsed = strict_json.loads(data)
        except strict_json.JsonPolicyError as exc:
            raise _usage_error(f"{name} is not valid JSON: {exc}") from None
    if isinstance(parsed, dict) and "format" not in parsed:
        body = parsed.get("rules", parsed) if set(parsed) <= {"rules"} else parsed
        theory = parse_theory(body, "rules" if "rules" in parsed else "$")
        return theory, design_findings(theory), name
    loaded = read_bytes(data, name)
    found = theory_for(loaded.orders)
    if found is None:
        raise _usage_error(f"{name}: the orders and their vehicle profile carry no rules")
    return found, design_findings(found, loaded.orders), name


def _write_text(
    label: str, theory: DefaultTheory, findings: list[Finding], observations: dict[str, bool],
    ext: Extension, verdict: ActionVerdict | None, out: TextIO,
) -> None:
    from ..rules import plain_rules

    out.write(f"Rules of {label} ({len(theory)}: {len(theory.defaults)} defaults, "
              f"{len(theory.facts) + len(theory.strict)} facts and strict rules)\n")
    for sentence in plain_rules(theory):
        out.write(f"  {sentence}\n")
    out.write(f"Design findings: {len(findings) or 'none'}\n")
    for finding in findings:
        out.write(f"  {finding.severity:<7} {finding.code} [{', '.join(finding.subjects)}]\n")
        out.write(f"          {finding.message}\n")
    shown = ", ".join(f"{k}={'true' if v else 'false'}" for k, v in observations.items())
    out.write(f"Observations: {shown or 'none'}\n")
    out.write("Extension:\n")
    out.write(f"  holds:   {', '.join(sorted(ext.literals)) or '-'}\n")
    out.write(f"  goals:   {', '.join(ext.goals) or '-'}\n")
    out.write(f"  do_safe: {', '.join(ext.safe_actions) or '-'}\n")
    out.write(f"  fired:   {', '.join(ext.fired) or '-'}\n")
    out.write(f"  blocked: {', '.join(ext.blocked) or '-'}\n")
    if ext.contradictions:
        out.write(f"  CONTRADICTORY observations about: {', '.join(ext.contradictions)}\n")
    if verdict is not None:
        decision = (
            "allowed" if verdict.allowed
            else f"overridden: do {verdict.action_to_take}" if verdict.action_to_take
            else "refused"
        )
        out.write(f"Planned action {verdict.planned}: {decision}\n  {verdict.explanation}\n")


def cmd_rules(args: argparse.Namespace) -> int:
    try:
        return _rules(args)
    except RulesUsageError as exc:
        sys.stderr.write(f"countersign: {exc}\n")
        return EXIT_UNREADABLE


def _rules(args: argparse.Namespace) -> int:
    from ..orders.reader import OrdersReadError
    from ..rules import (
        TheoryError,
        TheoryTooLarge,
        check_action,
        extension,
        parse_observations,
        plain_rules,
    )
    from ..rules.syntax import LiteralSyntaxError

    try:
        theory, findings, label = load_rules(args.file)
        observations = parse_observations(args.observe or "")
    except TheoryError as exc:
        sys.stderr.write(f"countersign: cannot read the rules of {args.file}:\n  {exc}\n")
        return EXIT_UNREADABLE
    except (LiteralSyntaxError, ValueError) as exc:
        if isinstance(exc, OrdersReadError):
            raise
        raise _usage_error(f"--observe: {exc}") from None
    try:
        ext = extension(theory, observations)
    except TheoryTooLarge as exc:
        sys.stderr.write(f"countersign: cannot reason with the rules of {args.file}:\n  {exc}\n")
        return EXIT_UNREADABLE
    verdict = None
    if args.action:
        try:
            verdict = check_action(theory, ext, args.action)
        except ValueError as exc:
            raise _usage_error(f"--action: {exc}") from None
    if args.format == "json":
        data = {
            "source": label,
            "rules": [
                {"id": rule.id, "kind": rule.kind, "default": rule.is_default,
                 "formula": rule.formula(), "plain": sentence}
                for rule, sentence in zip(theory.rules, plain_rules(theory), strict=True)
            ],
            "findings": [f.to_json() for f in findings],
            "observations": observations,
            "extension": ext.to_json(),
            "verdict": verdict.to_json() if verdict else None,
        }
        json.dump(data, sys.stdout, indent=2)
        sys.stdout.write("\n")
    else:
        _write_text(label, theory, findings, observations, ext, verdict, sys.stdout)
    return EXIT_FINDINGS if any(f.severity == "error" for f in findings) else EXIT_OK


class _TheoriesFormatter(argparse.RawDescriptionHelpFormatter):
    """Names the built-in theories only when help is shown (reading them imports the rules)."""

    def _format_text(self, text: str) -> str:
        if "{theories}" in text:
            from ..rules import theory_names

            text = text.replace("{theories}", ", ".join(theory_names()))
        return super()._format_text(text)


def add_commands(commands: argparse._SubParsersAction) -> None:  # type: ignore[type-arg]
    rules_cmd = commands.add_parser(
        "rules",
        help="contingency rules (seed 004): plain English, extension, eq. 17 action check",
        description=DESCRIPTION,
        epilog=EPILOG,
        formatter_class=_TheoriesFormatter,
    )
    rules_cmd.add_argument("file", metavar="FILE", help="orders or a rules file (see below)")
    rules_cmd.add_argument(
        "--observe", metavar="OBS",
        help="observations, comma separated: atom=true|false, or atom alone for true "
        "(e.g. gps_was_captured=false,usbl_was_captured=false,safety_sensor_failure(leak))",
    )
    rules_cmd.add_argument(
        "--action", metavar="ACTION", help="planned action to check with eq. 17 (e.g. transect_t2)"
    )
    rules_cmd.add_argument("--format", choices=["text", "json"], default="text")
    rules_cmd.set_defaults(handler=cmd_rules)
