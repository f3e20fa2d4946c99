"""The shape of the backend's code: no module over 600 lines, no function over 60 lines
without a stated reason, one Turtle writer, and no import cycle between the packages and the
top-level modules. Each rule is also run on a planted example, so a check that stops seeing
anything fails too."""

from __future__ import annotations

import ast
import functools
from collections.abc import Iterator
from pathlib import Path

from tests.codebase.test_layering import _imports, _layer

ROOT = Path(__file__).resolve().parents[2] / "backend" / "countersign"

MAX_MODULE_LINES = 600
# Modules allowed to be longer, each with its reason (none today).
LONG_MODULES: dict[str, str] = {}

MAX_FUNCTION_LINES = 60
# A function over the limit states why in its docstring, in a sentence starting "Length:".
REASON = "Length:"
# Functions over the limit, each with the reason it is long: a declarative table or a hot
# loop. An entry must go when its function is split (the test says so).
LONG_FUNCTIONS: dict[str, str] = {
    "countersign/cli/orders.py:add_commands":
        "a declarative argparse table of the orders commands, one block per command",
    "countersign/rules/engine.py:compute":
        "one pass of the prioritised-extension algorithm over local arrays shared with its "
        "closure; split, the hot loop pays for attribute lookups",
}

# The one Turtle writer: escaping and document layout for every Turtle the code writes.
TURTLE_WRITER = "countersign/orders/turtle/syntax.py"


def _sources(root: Path) -> Iterator[tuple[str, Path]]:
    for path in sorted(root.rglob("*.py")):
        yield path.relative_to(root.parent).as_posix(), path


@functools.cache
def _tree(path: Path) -> ast.Module:
    return ast.parse(path.read_text(encoding="utf-8"))


def long_modules(root: Path = ROOT) -> dict[str, int]:
    found = {}
    for name, path in _sources(root):
        lines = len(path.read_text(encoding="utf-8").splitlines())
        if lines > MAX_MODULE_LINES:
            found[name] = lines
    return found


def _functions(tree: ast.AST, prefix: str = ""
               ) -> Iterator[tuple[str, ast.FunctionDef | ast.AsyncFunctionDef]]:
    for node in ast.iter_child_nodes(tree):
        if isinstance(node, ast.FunctionDef | ast.AsyncFunctionDef):
            yield prefix + node.name, node
            yield from _functions(node, f"{prefix}{node.name}.")
        elif isinstance(node, ast.ClassDef):
            yield from _functions(node, f"{prefix}{node.name}.")


def long_functions(root: Path = ROOT) -> dict[str, tuple[int, bool]]:
    """name -> (lines, whether its docstring gives the reason) of every function over the
    limit (from `def` to its last line)."""
    found = {}
    for name, path in _sources(root):
        tree = _tree(path)
        for qualified, node in _functions(tree):
            assert node.end_lineno is not None
            lines = node.end_lineno - node.lineno + 1
            if lines > MAX_FUNCTION_LINES:
                reasoned = REASON in (ast.get_docstring(node) or "")
                found[f"{name}:{qualified}"] = (lines, reasoned)
    return found


def _is_escape_table(node: ast.AST) -> bool:
    """A dict literal mapping '"' to '\\"' and a newline to '\\n': a Turtle (or JSON-like)
    string escape table."""
    if not isinstance(node, ast.Dict):
        return False
    pairs = {(k.value, v.value) for k, v in zip(node.keys, node.values, strict=True)
             if isinstance(k, ast.Constant) and isinstance(v, ast.Constant)}
    return ('"', '\\"') in pairs and ("\n", "\\n") in pairs


def _writes_prefix_lines(node: ast.AST) -> bool:
    if isinstance(node, ast.JoinedStr) and node.values:
        first = node.values[0]
        return isinstance(first, ast.Constant) and str(first.value).startswith("@prefix ")
    return (isinstance(node, ast.Constant) and isinstance(node.value, str)
            and node.value.startswith("@prefix "))


def turtle_writers(root: Path = ROOT) -> set[str]:
    """Modules holding a string escape table or writing `@prefix` lines."""
    found = set()
    for name, path in _sources(root):
        tree = _tree(path)
        if any(_is_escape_table(n) or _writes_prefix_lines(n) for n in ast.walk(tree)):
            found.add(name)
    return found


def hand_written_caches(root: Path = ROOT) -> set[str]:
    """Modules bounding a dict by hand (`move_to_end` or `popitem(last=False)`): one cache
    interface, cachetools', holds every bounded memory, so eviction is written once."""
    found = set()
    for name, path in _sources(root):
        for node in ast.walk(_tree(path)):
            if isinstance(node, ast.Attribute) and node.attr == "move_to_end":
                found.add(name)
            if isinstance(node, ast.Call) and isinstance(node.func, ast.Attribute) and \
                    node.func.attr == "popitem" and any(
                        k.arg == "last" for k in node.keywords):
                found.add(name)
    return found


def import_cycles(root: Path = ROOT) -> list[list[str]]:
    """Cycles among the packages and top-level modules of countersign (an import inside a
    function counts: it is a dependency all the same)."""
    edges: dict[str, set[str]] = {}
    for _, path in _sources(root):
        parts = path.relative_to(root.parent).with_suffix("").parts
        source = _layer(".".join(parts))
        for module, _line in _imports(path, root):
            target = _layer(module)
            if module.split(".")[0] == "countersign" and target and target != source:
                edges.setdefault(source, set()).add(target)
    cycles = []
    for start in sorted(edges):
        stack = [(start, [start])]
        while stack:
            node, path_so_far = stack.pop()
            for nxt in sorted(edges.get(node, ())):
                if nxt == start:  # each cycle once, from its least member
                    cycles.append([*path_so_far, start])
                elif nxt > start and nxt not in path_so_far:
                    stack.append((nxt, [*path_so_far, nxt]))
    return cycles


def test_no_module_over_the_limit() -> None:
    found = long_modules()
    assert {n: lines for n, lines in found.items() if n not in LONG_MODULES} == {}
    assert sorted(set(LONG_MODULES) - set(found)) == [], "remove stale LONG_MODULES entries"


def test_no_function_over_the_limit_without_a_reason() -> None:
    found = long_functions()
    unexplained = {n: lines for n, (lines, reasoned) in found.items()
                   if not reasoned and n not in LONG_FUNCTIONS}
    assert unexplained == {}, f"split them or give the reason ({REASON}) in the docstring"
    assert sorted(set(LONG_FUNCTIONS) - set(found)) == [], "remove stale LONG_FUNCTIONS entries"


def test_one_turtle_writer() -> None:
    assert turtle_writers() == {TURTLE_WRITER}


def test_bounded_memories_use_the_one_cache_interface() -> None:
    assert hand_written_caches() == set()


def test_no_import_cycle() -> None:
    assert import_cycles() == []


def test_the_checks_see_planted_examples(tmp_path: Path) -> None:
    package = tmp_path / "countersign"
    (package / "orders").mkdir(parents=True)
    (package / "orders" / "big.py").write_text("x = 1\n" * (MAX_MODULE_LINES + 1))
    body = "".join(f"    x{i} = {i}\n" for i in range(MAX_FUNCTION_LINES))
    (package / "orders" / "long.py").write_text(
        f"def quiet():\n{body}\n\nclass A:\n    def said(self):\n"
        f'        """{REASON} a table."""\n' + body.replace("    ", "        ")
    )
    (package / "orders" / "writer.py").write_text(
        "ESC = {'\"': '\\\\\"', '\\n': '\\\\n'}\n"
        "def head(p, ns):\n    return f'@prefix {p}: <{ns}> .'\n"
    )
    (package / "leaf.py").write_text("def load():\n    from .orders import big\n")
    (package / "orders" / "uses_leaf.py").write_text("from .. import leaf\n")
    (package / "orders" / "lru.py").write_text(
        "def put(d, k, v):\n    d[k] = v\n    d.move_to_end(k)\n    d.popitem(last=False)\n")
    assert long_modules(package) == {"countersign/orders/big.py": MAX_MODULE_LINES + 1}
    assert long_functions(package) == {
        "countersign/orders/long.py:quiet": (MAX_FUNCTION_LINES + 1, False),
        "countersign/orders/long.py:A.said": (MAX_FUNCTION_LINES + 2, True),
    }
    assert turtle_writers(package) == {"countersign/orders/writer.py"}
    assert import_cycles(package) == [["leaf", "orders", "leaf"]]
    assert hand_written_caches(package) == {"countersign/orders/lru.py"}
