"""The command line starts light: heavy libraries load in the commands
that need them, so `import countersign.cli` and building its parser (what `--help` does) import
none of them. The figures are in tests/bench/bench_startup.py."""

from __future__ import annotations

import argparse
import contextlib
import gc
import io
import json
import subprocess
import sys

import pytest

from countersign.cli import GROUP_OF, GROUPS, build_parser
from countersign.cli import common as cli_common
from countersign.cli import plan as cli_plan
from countersign.cli import rehearse as cli_rehearse

HEAVY = ("z3", "rdflib", "networkx", "fastapi", "sqlalchemy", "pydantic", "viser", "owlrl",
         "numpy", "shapely", "pyproj", "pyoxigraph", "html5rdf", "uvicorn", "starlette",
         "gunicorn", "http.client", "urllib.request", "pint", "socket")


def _loaded_after(code: str) -> list[str]:
    report = f"print(json.dumps(sorted(set({HEAVY!r}) & set(sys.modules))))"
    probe = f"import json, sys\n{code}\n{report}"
    out = subprocess.run([sys.executable, "-c", probe], capture_output=True, text=True,
                         check=True, timeout=120).stdout
    loaded: list[str] = json.loads(out.strip().splitlines()[-1])
    return loaded


def test_importing_the_command_line_imports_no_heavy_library() -> None:
    assert _loaded_after("import countersign.cli") == []


def test_countersign_help_as_run_imports_no_heavy_library() -> None:
    # `countersign --help` itself, run as `python -m countersign.cli --help` runs it.
    code = ("import contextlib, io, runpy\nsys.argv = ['countersign', '--help']\n"
            "with contextlib.suppress(SystemExit), contextlib.redirect_stdout(io.StringIO()):\n"
            "    runpy.run_module('countersign.cli', run_name='__main__')\n")
    assert _loaded_after(code) == []


def test_building_every_parser_imports_no_heavy_library() -> None:
    # What `countersign --help` and `countersign COMMAND --help` need.
    code = ("import contextlib, io\nfrom countersign.cli import build_parser\n"
            "parser = build_parser()\n"
            "for name in ('rules', 'rehearse', 'plan', 'validate', 'serve', 'witness'):\n"
            "    with contextlib.suppress(SystemExit), contextlib.redirect_stdout(io.StringIO()):\n"
            "        parser.parse_args([name, '--help'])\n")
    assert _loaded_after(code) == []


def test_the_help_names_what_the_libraries_define() -> None:
    from countersign.plan.examples import EXAMPLES
    from countersign.rehearse.sim import FAULTS
    from countersign.rehearse.sources import SOURCES
    from countersign.verify.report import SOLVER_BUDGET_S

    assert cli_common.SOLVER_BUDGET_S == SOLVER_BUDGET_S
    assert tuple(sorted(EXAMPLES)) == cli_plan.EXAMPLE_NAMES
    assert cli_rehearse.FAULTS == FAULTS
    assert cli_rehearse.SOURCES == SOURCES


def test_the_rules_help_lists_the_built_in_theories() -> None:
    from countersign.rules import theory_names

    parser = build_parser()
    rules = next(a for a in parser._subparsers._group_actions  # type: ignore[union-attr]
                 ).choices["rules"]
    text = rules.format_help()
    assert "{theories}" not in text
    assert all(name in text for name in theory_names())


# What `countersign validate` of the exemplar has no use for: the MEO route (rdflib, owlrl,
# pyoxigraph: only --explain reasons over the graph), pint (its texts write their numbers in the
# units the conditions read), the rules engine (no rules), path properties and teams (none), the
# store and the server, pydantic-settings (the land mask's cache path is read with pydantic alone:
# settings.py), z3 (bounds propagation settles every unit of the exemplar). Each was once
# imported by every validation.
NOT_FOR_VALIDATE = ("rdflib", "owlrl", "pyoxigraph", "pint", "networkx", "sqlalchemy", "z3",
                    "pydantic_settings", "asyncio", "dotenv",
                    "fastapi", "numpy.ma", "countersign.verify.meo.reasoned",
                    "countersign.orders.turtle", "countersign.rules",
                    "countersign.verify.properties", "countersign.verify.team_report")


def _modules_after_cli(*argv: str) -> set[str]:
    """The modules loaded by `countersign ARGV` run as `python -m countersign.cli` runs it."""
    code = ("import contextlib, io, json, runpy, sys\n"
            f"sys.argv = ['countersign', *{list(argv)!r}]\n"
            "out = io.StringIO()\n"
            "with contextlib.suppress(SystemExit), contextlib.redirect_stdout(out):\n"
            "    runpy.run_module('countersign.cli', run_name='__main__')\n"
            "print(json.dumps([out.getvalue(), sorted(sys.modules)]))\n")
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                          check=True, timeout=300)
    output, modules = json.loads(done.stdout.strip().splitlines()[-1])
    assert "OK: 0 error(s)" in output  # the command ran and validated
    return set(modules)


def test_validating_the_exemplar_imports_only_what_it_needs() -> None:
    loaded = _modules_after_cli("validate", "example:search-and-sample")
    assert {"shapely", "countersign.verify.logic", "countersign.verify.meo.direct"} <= loaded
    assert sorted(m for m in loaded
                  if any(m == name or m.startswith(f"{name}.") for name in NOT_FOR_VALIDATE)) == []


def test_the_command_table_is_what_the_groups_add() -> None:
    def commands(parser: argparse.ArgumentParser) -> list[str]:
        action = next(a for a in parser._actions if isinstance(a, argparse._SubParsersAction))
        return list(action.choices)

    assert commands(build_parser()) == [c for group in GROUPS.values() for c in group]
    for group, names in GROUPS.items():
        assert tuple(commands(build_parser(group))) == names, group


def _parsed(parser: argparse.ArgumentParser, argv: list[str]) -> tuple[str, str, object]:
    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        try:
            result: object = vars(parser.parse_args(argv))
        except SystemExit as exc:
            result = exc.code
    return out.getvalue(), err.getvalue(), result


def test_a_group_parser_parses_its_commands_as_the_whole_parser() -> None:
    # Help, errors and parsed arguments alike, for every command.
    whole = build_parser()
    cases = [["validate", "x.json", "--format", "json"], ["validate"], ["validate", "x", "--nope"],
             ["export", "x.json", "--format", "moos"], ["plan", "--help"], ["users", "--help"],
             ["audit", "--help"], ["validate", "x", "extra", "--help"]]
    cases += [[command, "--help"] for names in GROUPS.values() for command in names]
    for argv in cases:
        assert _parsed(build_parser(GROUP_OF[argv[0]]), argv) == _parsed(whole, argv), argv


def test_validating_loads_only_its_command_group() -> None:
    loaded = _modules_after_cli("validate", "example:search-and-sample")
    groups = {m.removeprefix("countersign.cli.") for m in loaded
              if m.startswith("countersign.cli.")}
    # validate is of the orders group, which takes --library from the procedures group.
    assert groups & set(GROUPS) == {"orders", "procedures"}


def _freezes(monkeypatch: pytest.MonkeyPatch) -> list[int]:
    """Records each gc.freeze() call, and freezes nothing: a broken rule must not freeze the
    test process for every later test. Counting the permanent generation instead failed when
    an object an earlier test froze (an app's start freezes what it loaded) was freed."""
    calls: list[int] = []
    monkeypatch.setattr(gc, "freeze", lambda: calls.append(1))
    return calls


def test_the_program_ends_with_the_collector_frozen_and_a_call_does_not(
        monkeypatch: pytest.MonkeyPatch) -> None:
    # Frozen, the objects a command loaded are not walked by the collections at exit (a quarter
    # of a short command's CPU); a caller in the same process (these tests) keeps its collector.
    from countersign.cli import main

    freezes = _freezes(monkeypatch)
    with contextlib.redirect_stdout(io.StringIO()):
        assert main(["examples"]) == 0
    assert (freezes, gc.isenabled()) == ([], True)
    code = ("import contextlib, gc, io, runpy, sys\nsys.argv = ['countersign', 'examples']\n"
            "with contextlib.suppress(SystemExit), contextlib.redirect_stdout(io.StringIO()):\n"
            "    runpy.run_module('countersign.cli', run_name='__main__')\n"
            "print(gc.get_freeze_count())\n")
    frozen = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                            check=True, timeout=120).stdout.strip().splitlines()[-1]
    assert int(frozen) > 10_000


def test_validate_loads_its_modules_frozen_only_as_the_program(
        monkeypatch: pytest.MonkeyPatch) -> None:
    # As the program, validate's imports load without collections and are then frozen; called
    # in-process, its imports leave the collector as it was.
    from countersign.cli import main

    freezes = _freezes(monkeypatch)
    with contextlib.redirect_stdout(io.StringIO()):
        assert main(["validate", "example:search-and-sample"]) == 0
    assert (freezes, gc.isenabled()) == ([], True)
    code = ("import contextlib, gc, io, sys\nfrom countersign import cli\nfrozen = []\n"
            "real = cli.common.gc.freeze\n"
            "cli.common.gc.freeze = lambda: (frozen.append(sorted(sys.modules)), real())\n"
            "sys.argv = ['countersign', 'validate', 'example:search-and-sample']\n"
            "with contextlib.redirect_stdout(io.StringIO()):\n"
            "    cli.main()\n"
            "print(len(frozen), 'countersign.verify.report' in frozen[0], gc.isenabled())\n")
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                          check=True, timeout=300).stdout.strip().splitlines()[-1]
    # Frozen once the checks were loaded (and once more at the end), the collector back on.
    assert done == "2 True True"
