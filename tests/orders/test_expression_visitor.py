"""The expression visitor is exhaustive: every node kind of `tree.Expr` is dispatched by
`ExprVisitor.visit`, has an abstract method, and every interpreter of the language handles it.

The decisive check runs mypy: on copies of `tree.py` and `visit.py` it passes, and after a node
kind is added to the `Expr` union of the copy it fails at `visit.py`'s `assert_never`, so a kind
that is added but not dispatched cannot pass `mypy`. An interpreter that leaves a kind out cannot
be instantiated (mypy reports it too: "Cannot instantiate abstract class").
"""

from __future__ import annotations

import inspect
import re
import shutil
import typing
from pathlib import Path

import pytest
from mypy import api as mypy_api

import countersign.export.moos_condition
import countersign.orders.conditions
import countersign.rehearse.monitor
import countersign.verify.expressions
import countersign.verify.logic.formulas
from countersign.orders.expressions import ExprVisitor, children, parse, walk
from countersign.orders.expressions import tree as tree_module
from countersign.orders.expressions import visit as visit_module
from countersign.orders.expressions.tree import Expr

KINDS: tuple[type, ...] = typing.get_args(Expr)

# One text that holds every node kind.
EVERY_KIND = ("not (-depth_m + 2 * 3 >= 1 < 2) or behavior == 'x' and context('lane') "
              "implies true")


def _method(kind: type) -> str:
    return "visit_" + re.sub(r"(?<!^)(?=[A-Z])", "_", kind.__name__).lower()


def _answer(name: str) -> typing.Callable[[object, Expr], str]:
    return lambda self, node: name


def _interpreters() -> set[type]:
    found: set[type] = set()
    stack = list(ExprVisitor.__subclasses__())
    while stack:
        cls = stack.pop()
        found.add(cls)
        stack.extend(cls.__subclasses__())
    return found


def test_every_node_kind_has_one_abstract_method() -> None:
    assert len(KINDS) == 13
    assert ExprVisitor.__abstractmethods__ == frozenset(_method(kind) for kind in KINDS)


def test_the_text_holds_every_kind_and_visit_dispatches_each_to_its_method() -> None:
    nodes = list(walk(parse(EVERY_KIND)))
    assert {type(node) for node in nodes} == set(KINDS)

    # A visitor made here with one method per kind, each answering its own name.
    recorder = type("Recorder", (ExprVisitor,), {
        _method(kind): _answer(_method(kind)) for kind in KINDS})()
    for node in nodes:
        assert recorder.visit(node) == _method(type(node))


def test_every_interpreter_handles_every_kind() -> None:
    production = [cls for cls in _interpreters() if cls.__module__ != __name__]
    interpreters = {f"{cls.__module__}.{cls.__qualname__}" for cls in production}
    assert interpreters >= {
        "countersign.orders.expressions.visit._Children",
        "countersign.orders.expressions.words._Words",
        "countersign.orders.conditions._ConditionWords",
        "countersign.verify.expressions.evaluate._Evaluate",
        "countersign.verify.expressions.smt.Translator",
        "countersign.verify.expressions.types.TypeChecker",
        "countersign.rehearse.monitor._Compile",
        "countersign.export.moos_condition._Helm",
        "countersign.verify.logic.formulas._Condition",
        "countersign.verify.logic.formulas._Linear",
        "countersign.verify.logic.formulas._Strings",
    }, "an interpreter no longer uses ExprVisitor"
    for cls in production:
        assert not inspect.isabstract(cls), (
            f"{cls.__qualname__} leaves out {sorted(cls.__abstractmethods__)}")
    assert countersign.orders.conditions and countersign.rehearse.monitor  # imported for above
    assert countersign.export.moos_condition and countersign.verify.expressions
    assert countersign.verify.logic.formulas


def test_an_interpreter_that_leaves_a_kind_out_cannot_be_made() -> None:
    methods = {_method(kind): (lambda self, node: None) for kind in KINDS[1:]}
    partial = type("Partial", (ExprVisitor,), methods)
    with pytest.raises(TypeError, match=_method(KINDS[0])):
        partial()


def test_children_are_the_operands_in_order() -> None:
    expr = parse("a + b - c < d")
    assert [type(child).__name__ for child in children(expr)] == ["Sum", "Name"]
    assert [node.col for node in walk(expr)] == [1, 1, 1, 5, 9, 13]


def _mypy(package: Path) -> tuple[int, str]:
    stdout, stderr, status = mypy_api.run([
        "--strict", "--no-incremental", "--cache-dir", str(package.parent / ".mypy_cache"),
        "--python-version", "3.11", str(package),
    ])
    return status, stdout + stderr


def test_mypy_rejects_a_node_kind_that_visit_does_not_dispatch(tmp_path: Path) -> None:
    package = tmp_path / "exprcopy"
    package.mkdir()
    (package / "__init__.py").write_text("")
    shutil.copy(tree_module.__file__, package / "tree.py")
    shutil.copy(visit_module.__file__, package / "visit.py")

    status, output = _mypy(package)
    assert status == 0, output

    tree = (package / "tree.py").read_text()
    union = re.search(r"^Expr = .*?\n(?=\S|\Z)", tree, re.MULTILINE | re.DOTALL)
    assert union is not None
    (package / "tree.py").write_text(tree.replace(
        union.group(0),
        "@dataclass(frozen=True, slots=True)\nclass Power:\n    col: int\n\n\n"
        + union.group(0).rstrip("\n") + " | Power\n"))
    status, output = _mypy(package)
    assert status == 1, "mypy accepts a node kind that visit() does not dispatch"
    assert output.count("error:") == 1, output
    assert re.search(r"visit\.py:\d+: error: Argument 1 to \"assert_never\" has incompatible "
                     r"type \"Power\"", output), output
