"""The one Turtle writer: escaping, terms and the document's layout, for both outputs.

Our own Turtle (`text.py`) is rendered straight from the orders as text; the NPS view
(`nps.py`) is an rdflib graph, rendered by `serialize_turtle`. Both quote strings and IRIs
with the one escape table here and lay a document out the same way: `@prefix` lines, a blank
line, then one block per subject (`subject p o ;\\n    p o .`), blocks apart by a blank line.

rdflib's Turtle serializer spends most of its time computing prefixed names and nesting blank
nodes again for every term; on 10,000 goals it takes about 30 s. `serialize_turtle` makes one
pass: prefixes are looked up once per distinct IRI, statements are grouped by subject, and
blank nodes get short labels numbered by first use, so the output is stable for a stable graph.
It writes plain Turtle (subject; predicate object, ...) that any reader takes. (Oxigraph's
serializer writes other bytes - tabs, no blank lines - and the written bytes are pinned.)
"""

from __future__ import annotations

import re
from collections.abc import Iterable, Iterator
from typing import Any, Final, Protocol

from rdflib import BNode, Literal, URIRef
from rdflib.namespace import RDF, XSD
from rdflib.term import Node

# A local name safe in every Turtle reader: no dots, no escapes, no leading digit or dash.
LOCAL: Final = re.compile(r"[A-Za-z_][A-Za-z0-9_-]*")
DECIMAL: Final = re.compile(r"[+-]?[0-9]*\.[0-9]+")
_ESCAPES: Final = {"\\": "\\\\", '"': '\\"', "\n": "\\n", "\r": "\\r", "\t": "\\t",
                   "\b": "\\b", "\f": "\\f"}
_NEEDS_ESCAPE: Final = re.compile(r'[\\"\x00-\x1f\x7f]')
_IRI_UNSAFE: Final = re.compile(r'[\x00-\x20<>"{}|^`\\]')
_PLAIN_NUMBER: Final = {XSD.integer: re.compile(r"[+-]?[0-9]+"), XSD.decimal: DECIMAL}


def _escape_char(match: re.Match[str]) -> str:
    char = match.group(0)
    return _ESCAPES.get(char) or f"\\u{ord(char):04X}"


def quoted(text: str) -> str:
    """A string literal's quoted form."""
    if _NEEDS_ESCAPE.search(text) is None:
        return f'"{text}"'
    return '"' + _NEEDS_ESCAPE.sub(_escape_char, text) + '"'


def iri_ref(text: str) -> str:
    """An IRI in angle brackets, characters Turtle forbids there as \\u escapes."""
    if _IRI_UNSAFE.search(text):
        text = _IRI_UNSAFE.sub(lambda m: f"\\u{ord(m.group(0)):04X}", text)
    return f"<{text}>"


def document(prefixes: Iterable[tuple[str, str]],
             subjects: Iterable[tuple[str, Iterable[str]]]) -> str:
    """The document: `@prefix` lines, a blank line, then each subject's statements
    (`predicate object` texts) as one block, blocks separated by a blank line."""
    head = "".join(f"@prefix {prefix}: <{namespace}> .\n" for prefix, namespace in prefixes)
    blocks = (f"{subject} " + " ;\n    ".join(statements) + " .\n"
              for subject, statements in subjects)
    return head + "\n" + "\n".join(blocks)


class Statements(Protocol):
    """What `serialize_turtle` reads of a graph (rdflib's Graph has it)."""

    def namespaces(self) -> Iterator[tuple[str, Any]]: ...

    def __iter__(self) -> Iterator[tuple[Node, Node, Node]]: ...


class _Terms:
    def __init__(self, graph: Statements) -> None:
        # Longest namespace first, so that nested namespaces pick the most specific prefix.
        self.namespaces = sorted(((str(ns), prefix) for prefix, ns in graph.namespaces()),
                                 key=lambda item: -len(item[0]))
        self.used: set[str] = set()
        self._iris: dict[URIRef, str] = {}
        self._blanks: dict[BNode, str] = {}

    def iri(self, node: URIRef) -> str:
        found = self._iris.get(node)
        if found is None:
            found = self._iris[node] = self._name(str(node))
        return found

    def _name(self, text: str) -> str:
        if text == str(RDF.type):
            return "a"
        for namespace, prefix in self.namespaces:
            if text.startswith(namespace) and LOCAL.fullmatch(text[len(namespace):]):
                self.used.add(prefix)
                return f"{prefix}:{text[len(namespace):]}"
        return iri_ref(text)

    def term(self, node: Node) -> str:
        if isinstance(node, URIRef):
            return self.iri(node)
        if isinstance(node, BNode):
            label = self._blanks.get(node)
            if label is None:
                label = self._blanks[node] = f"_:b{len(self._blanks)}"
            return label
        if isinstance(node, Literal):
            return self.literal(node)
        raise TypeError(f"cannot write {type(node).__name__} as Turtle")

    def literal(self, node: Literal) -> str:
        lexical = str(node)
        datatype = node.datatype
        if datatype == XSD.boolean and lexical in ("true", "false"):
            return lexical
        pattern = _PLAIN_NUMBER.get(datatype) if datatype is not None else None
        if pattern is not None and pattern.fullmatch(lexical):
            return lexical
        text = quoted(lexical)
        if node.language:
            return f"{text}@{node.language}"
        if datatype is not None and datatype != XSD.string:
            return f"{text}^^{self.iri(datatype)}"
        return text


def serialize_turtle(graph: Statements) -> str:
    """The graph as Turtle, in time linear in its statements: named subjects first in IRI
    order, blank ones after in the graph's order; a subject's objects of one predicate are
    listed after it, comma-separated; only the prefixes used are declared."""
    terms = _Terms(graph)
    by_subject: dict[Node, list[tuple[Node, Node]]] = {}
    for s, p, o in graph:
        by_subject.setdefault(s, []).append((p, o))
    named = sorted((s for s in by_subject if isinstance(s, URIRef)), key=str)
    blank = [s for s in by_subject if not isinstance(s, URIRef)]
    blocks: list[tuple[str, list[str]]] = []
    for subject in (*named, *blank):
        predicate_of: dict[Node, list[str]] = {}
        for p, o in by_subject[subject]:
            predicate_of.setdefault(p, []).append(terms.term(o))
        lines = [f"{terms.term(p)} {', '.join(objects)}" for p, objects in predicate_of.items()]
        blocks.append((terms.term(subject), lines))
    prefixes = [(prefix, namespace)
                for namespace, prefix in sorted(terms.namespaces, key=lambda i: i[1])
                if prefix in terms.used]
    return document(prefixes, blocks)
