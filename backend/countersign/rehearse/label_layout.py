"""Where the rehearsal scene's text labels go so that they do not pile up.

viser draws a label as screen-facing text of a fixed size at a 3D point; labels at nearly the
same point (three outcome legs between the same two goals, an outcome marker beside an area's
title, the markers of a goal every run of a tour ends at) print on top of each other. The camera
looks down on the chart from the south, so two labels clash when their boxes on the chart's
plane (x east, y north) overlap, whatever their depth: the spacer keeps the boxes placed so far
and moves a new label north, a line at a time, until its box is clear. A box is as wide as its
text. Pure geometry, no viser: the scene asks it for positions.
"""

from __future__ import annotations

from dataclasses import dataclass

Point3 = tuple[float, float, float]

# Scene units (the chart is 12 units across, about 500 px in a laptop's view): one line of
# label text, and the width of one character of it.
LINE = 0.32
CHAR = 0.1
MAX_STEPS = 64


@dataclass(frozen=True)
class Placed:
    x: float
    y: float
    z: float
    width: float


def width_of(text: str) -> float:
    return CHAR * (len(text) + 2)


class LabelSpacer:
    """Positions for labels whose boxes on the chart do not overlap."""

    def __init__(self, limit: int = 2000) -> None:
        # A bound on the work per label (the scene caps its markers; this caps the search).
        self._limit = limit
        self._placed: list[Placed] = []

    def _clashes(self, x: float, y: float, width: float) -> bool:
        # A hair of tolerance: a label moved by exactly one line clears the one below it.
        return any(abs(y - p.y) < LINE - 1e-9 and abs(x - p.x) < (width + p.width) / 2 - 1e-9
                   for p in self._placed[-self._limit:])

    def place(self, at: Point3, text: str) -> Point3:
        """The nearest free position at or north of `at` for `text`, remembered as taken."""
        x, y, z = at
        width = width_of(text)
        for _ in range(MAX_STEPS):
            if not self._clashes(x, y, width):
                break
            y += LINE
        self._placed.append(Placed(x, y, z, width))
        return (x, y, z)

    def mark(self) -> int:
        """A point to rewind to (labels placed after it are forgotten by `rewind`)."""
        return len(self._placed)

    def rewind(self, mark: int) -> None:
        del self._placed[mark:]

    @property
    def placed(self) -> tuple[Placed, ...]:
        return tuple(self._placed)


def offset(label: Point3, anchor: Point3) -> Point3:
    """A label's position relative to the node it is attached to."""
    return (label[0] - anchor[0], label[1] - anchor[1], label[2] - anchor[2])
