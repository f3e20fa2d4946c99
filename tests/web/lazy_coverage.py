"""Schemathesis' coverage cases made when a fuzz test first runs, not when it is collected.

schemathesis (4.x) attaches each operation's coverage-phase cases to its test as Hypothesis
explicit examples while pytest collects the module: tens of thousands of cases, about 20 s of
CPU, paid by every process that collects tests/web/test_fuzz.py (each xdist worker, and
tests/codebase/test_node_ids.py's collection) although one worker runs those tests. Here the
same cases, made by schemathesis' own code from the same arguments, fill the test's example
list the first time Hypothesis reads it; tests/web/test_fuzz_lazy_coverage.py holds that the
cases and their order are those collection would have attached."""

from __future__ import annotations

from collections.abc import Callable, Iterator
from typing import Any, SupportsIndex

from schemathesis.generation.hypothesis import builder

EXAMPLES = "hypothesis_explicit_examples"
EAGER_ADD_COVERAGE: Callable[..., Callable[..., Any]] = builder.add_coverage


class _Holder:
    """Stands in for the test function while schemathesis attaches examples and marks to it."""


class LazyExamples(list[Any]):
    """A test's explicit examples: those attached at collection, then the coverage cases,
    made on first use (iteration, length, indexing: what Hypothesis does with the list)."""

    def __init__(self, attached: list[Any], make: Callable[[], list[Any]]) -> None:
        super().__init__(attached)
        self._make: Callable[[], list[Any]] | None = make

    @property
    def made(self) -> bool:
        return self._make is None

    def fill(self) -> None:
        if self._make is not None:
            make, self._make = self._make, None
            self.extend(make())

    def __iter__(self) -> Iterator[Any]:
        self.fill()
        return super().__iter__()

    def __reversed__(self) -> Iterator[Any]:
        self.fill()
        return super().__reversed__()

    def __len__(self) -> int:
        self.fill()
        return super().__len__()

    def __getitem__(self, index: Any) -> Any:
        self.fill()
        return super().__getitem__(index)

    def append(self, item: Any) -> None:
        self.fill()
        super().append(item)

    def index(self, value: Any, start: SupportsIndex = 0, stop: SupportsIndex = 2**63 - 1) -> int:
        self.fill()
        return super().index(value, start, stop)


def lazy_add_coverage(test: Callable[..., Any], *args: Any, **kwargs: Any) -> Callable[..., Any]:
    """builder.add_coverage's contract (the test, with its coverage cases as explicit examples
    after those already attached, and schemathesis' marks), the cases made on first use."""

    def make() -> list[Any]:
        holder = _Holder()
        EAGER_ADD_COVERAGE(holder, *args, **kwargs)
        unserializable = builder.UnserializablePayloadMark.get(holder)
        if unserializable is not None:  # the one mark add_coverage sets: read after the call
            builder.UnserializablePayloadMark.set(test, unserializable)
        return list(getattr(holder, EXAMPLES, ()))

    attached = list(getattr(test, EXAMPLES, ()))
    setattr(test, EXAMPLES, LazyExamples(attached, make))
    return test


def install() -> None:
    """From now on in this process, schemathesis' tests make their coverage cases lazily."""
    builder.add_coverage = lazy_add_coverage
