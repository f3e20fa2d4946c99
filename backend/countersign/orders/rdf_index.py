"""Turtle read into an in-memory index of triples.

rdflib's own Turtle parser and memory store cost about 30 s for the 290,000 statements of a
10,000-goal mission. Oxigraph's parser (pyoxigraph, Rust) reads them in about a second; the
orders reader then needs only a few lookups by subject and by predicate, which two dictionaries
answer. Terms are rdflib's (URIRef, BNode, Literal), converted once per distinct term, so the
reader and its callers keep one term model. Literals keep rdflib's conventions: a plain string
has no datatype, a language string has no datatype.
"""

from __future__ import annotations

import contextlib
import gc
import re
from collections.abc import Iterable, Iterator
from typing import Final

import pyoxigraph as ox
from rdflib import BNode, Literal, URIRef
from rdflib.namespace import XSD
from rdflib.term import Node

Triple = tuple[Node, Node, Node]
_XSD_STRING: Final = str(XSD.string)
# Relative IRIs in an upload resolve against this (rdflib resolves against the working
# directory, which says nothing about the document either).
INPUT_BASE: Final = "https://input.countersign.invalid/"


class TurtleSyntaxError(ValueError):
    """Turtle that does not parse: `line` is 1-based when the parser reported it."""

    def __init__(self, reason: str, line: int | None) -> None:
        super().__init__(reason)
        self.reason = reason
        self.line = line


class TripleIndex:
    """The part of rdflib's Graph API the orders readers use, indexed by subject and by
    predicate. Statement order is the document's; a repeated statement is kept once. Both
    indexes grow with each statement added, so reading a document builds them in one pass."""

    def __init__(self, triples: Iterable[Triple] = ()) -> None:
        self._spo: dict[Node, dict[Node, dict[Node, None]]] = {}
        self._pso: dict[Node, list[tuple[Node, Node]]] | None = {}
        self._count = 0
        for triple in triples:
            self.add(triple)

    # -- changes

    def add(self, triple: Triple) -> None:
        s, p, o = triple
        by_predicate = self._spo.get(s)
        if by_predicate is None:
            by_predicate = self._spo[s] = {}
        objects = by_predicate.get(p)
        if objects is None:
            by_predicate[p] = {o: None}
        elif o in objects:
            return
        else:
            objects[o] = None
        self._count += 1
        pso = self._pso
        if pso is not None:
            pairs = pso.get(p)
            if pairs is None:
                pso[p] = [(s, o)]
            else:
                pairs.append((s, o))

    def remove(self, triple: Triple) -> None:
        s, p, o = triple
        objects = self._spo.get(s, {}).get(p)
        if objects is None or o not in objects:
            return
        del objects[o]
        self._count -= 1
        self._pso = None  # rebuilt on next use (removals are rare: NPS names renamed)

    def _by_predicate(self) -> dict[Node, list[tuple[Node, Node]]]:
        if self._pso is None:
            pso: dict[Node, list[tuple[Node, Node]]] = {}
            for s, by_predicate in self._spo.items():
                for p, objects in by_predicate.items():
                    pairs = pso.get(p)
                    if pairs is None:
                        pairs = pso[p] = []
                    pairs.extend((s, o) for o in objects)
            self._pso = pso
        return self._pso

    # -- lookups

    def __len__(self) -> int:
        return self._count

    def __iter__(self) -> Iterator[Triple]:
        for s, by_predicate in list(self._spo.items()):
            for p, objects in list(by_predicate.items()):
                for o in list(objects):
                    yield s, p, o

    def __contains__(self, pattern: tuple[Node | None, Node | None, Node | None]) -> bool:
        return next(self.triples(pattern), None) is not None

    def triples(self, pattern: tuple[Node | None, Node | None, Node | None]) -> Iterator[Triple]:
        s, p, o = pattern
        if s is not None:
            by_predicate = self._spo.get(s, {})
            predicates = [p] if p is not None else list(by_predicate)
            for predicate in predicates:
                for obj in list(by_predicate.get(predicate, ())):
                    if o is None or obj == o:
                        yield s, predicate, obj
            return
        if p is not None:
            for subject, obj in list(self._by_predicate().get(p, ())):
                if o is None or obj == o:
                    yield subject, p, obj
            return
        for triple in self:
            if o is None or triple[2] == o:
                yield triple

    def properties(self, subject: Node) -> dict[Node, dict[Node, None]]:
        """Predicate -> objects of one subject (read only: the index's own dictionary)."""
        return self._spo.get(subject, _NO_PROPERTIES)

    def value(self, subject: Node, predicate: Node) -> Node | None:
        by_predicate = self._spo.get(subject)
        objects = by_predicate.get(predicate) if by_predicate is not None else None
        return next(iter(objects)) if objects else None

    def objects(self, subject: Node, predicate: Node) -> Iterator[Node]:
        return iter(list(self._spo.get(subject, {}).get(predicate, ())))

    def subjects(self, predicate: Node, obj: Node | None) -> Iterator[Node]:
        pairs = self._by_predicate().get(predicate, ())
        found = (s for s, o in pairs if obj is None or o == obj)
        return iter(list(dict.fromkeys(found)))

    def subject_objects(self, predicate: Node) -> Iterator[tuple[Node, Node]]:
        return iter(list(self._by_predicate().get(predicate, ())))

    def predicate_objects(self, subject: Node) -> Iterator[tuple[Node, Node]]:
        return iter([(p, o) for p, objects in self._spo.get(subject, {}).items()
                     for o in objects])


_NO_PROPERTIES: Final[dict[Node, dict[Node, None]]] = {}

_ECHAR: Final = {"t": "\t", "b": "\b", "n": "\n", "r": "\r", "f": "\f", '"': '"', "'": "'",
                 "\\": "\\"}
_ESCAPE: Final = re.compile(r"\\(?:u([0-9A-Fa-f]{4})|U([0-9A-Fa-f]{8})|(.))")


def _unescape(text: str) -> str:
    if "\\" not in text:
        return text

    def one(match: re.Match[str]) -> str:
        code = match.group(1) or match.group(2)
        if code is not None:
            return chr(int(code, 16))
        return _ECHAR.get(match.group(3), match.group(0))

    return _ESCAPE.sub(one, text)


_new_str: Final = str.__new__


class _Terms:
    """N-Triples terms to rdflib terms, each distinct term converted once. Literals keep
    rdflib's conventions: a plain string and a language string have no datatype."""

    def __init__(self) -> None:
        self.seen: dict[str, Node] = {}

    def node(self, token: str) -> Node:
        found = self.seen.get(token)
        if found is None:
            found = self.seen[token] = self._convert(token)
        return found

    def _convert(self, token: str) -> Node:
        first = token[0]
        # IRIs and blank node labels as Oxigraph wrote them are valid: the str constructor
        # skips the checks of rdflib's (a third of the conversions' cost; both classes hold
        # nothing but the text).
        if first == "<":
            return _new_str(URIRef, _unescape(token[1:-1]))
        if first == "_":
            return _new_str(BNode, token[2:])
        if first != '"':
            raise TurtleSyntaxError(f"unexpected term {token[:40]!r}", None)
        end = token.rindex('"')
        lexical = _unescape(token[1:end])
        suffix = token[end + 1:]
        if suffix.startswith("@"):
            return Literal(lexical, lang=suffix[1:])
        if suffix.startswith("^^<"):
            datatype = _unescape(suffix[3:-1])
            if datatype != _XSD_STRING:
                return Literal(lexical, datatype=URIRef(datatype))
        return Literal(lexical)


def parse_turtle(data: bytes) -> TripleIndex:
    """The statements of a Turtle document (default graph), or TurtleSyntaxError.

    Oxigraph parses the Turtle (prefixes, base, collections, nested blank nodes) and writes
    the statements back as N-Triples, one statement per line in a fixed form: subject and
    predicate hold no space, the object runs to the closing " .". Splitting those lines costs
    a fifth of reading Oxigraph's term objects one attribute at a time."""
    with paused_collection():
        return _parse_turtle(data)


@contextlib.contextmanager
def paused_collection() -> Iterator[None]:
    """The cyclic garbage collector paused while a document's statements are built: the
    hundreds of thousands of tuples and dictionaries made in one pass, none of them garbage,
    set off full collections that took as long as the parse itself."""
    enabled = gc.isenabled()
    gc.disable()
    try:
        yield
    finally:
        if enabled:
            gc.enable()


def _parse_turtle(data: bytes) -> TripleIndex:
    try:
        statements = ox.parse(data, format=ox.RdfFormat.TURTLE, base_iri=INPUT_BASE)
        lines = ox.serialize(statements, format=ox.RdfFormat.N_TRIPLES)
    except SyntaxError as exc:
        line = exc.lineno if isinstance(exc.lineno, int) else None
        reason = str(exc.msg or exc).split(": ", 1)[-1][:200]
        raise TurtleSyntaxError(reason, line) from None
    terms = _Terms()
    seen = terms.seen
    convert = terms.node
    index = TripleIndex()
    spo = index._spo
    pso: dict[Node, list[tuple[Node, Node]]] = {}
    count = 0
    # The index's add() inline (a call per statement is a third of the loop): most tokens
    # repeat, so the conversion runs only for a token not seen before. Only "\n" ends a
    # statement: str.splitlines() would also split at U+2028 or U+0085, which N-Triples
    # writes unescaped inside literals.
    for statement in (lines or b"").decode("utf-8").split("\n"):
        if not statement:
            continue
        subject, predicate, rest = statement.split(" ", 2)
        obj = rest[:-2]
        s = seen.get(subject)
        if s is None:
            s = convert(subject)
        p = seen.get(predicate)
        if p is None:
            p = convert(predicate)
        o = seen.get(obj)
        if o is None:
            o = convert(obj)
        by_predicate = spo.get(s)
        if by_predicate is None:
            spo[s] = {p: {o: None}}
        else:
            objects = by_predicate.get(p)
            if objects is None:
                by_predicate[p] = {o: None}
            elif o in objects:
                continue
            else:
                objects[o] = None
        count += 1
        pairs = pso.get(p)
        if pairs is None:
            pso[p] = [(s, o)]
        else:
            pairs.append((s, o))
    index._pso = pso
    index._count = count
    return index
