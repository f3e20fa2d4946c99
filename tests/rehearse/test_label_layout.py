"""The rehearsal scene's labels do not pile up: the boxes of the labels the
spacer places (as wide as their text, a line high, on the chart's plane) never overlap."""

from __future__ import annotations

import itertools

from hypothesis import given
from hypothesis import strategies as st

from countersign.rehearse.label_layout import LINE, LabelSpacer, Placed, offset, width_of

coordinate = st.floats(min_value=-6, max_value=6, allow_nan=False)
label = st.tuples(coordinate, coordinate, st.floats(min_value=-1, max_value=1),
                  st.text(alphabet="abcdefg ", max_size=24))


def apart(a: Placed, b: Placed) -> bool:
    return (abs(a.y - b.y) >= LINE - 1e-9
            or abs(a.x - b.x) >= (a.width + b.width) / 2 - 1e-9)


def test_labels_at_one_point_are_stacked_a_line_apart() -> None:
    spacer = LabelSpacer()
    placed = [spacer.place((1.0, 2.0, 0.2), "G1: succeeded") for _ in range(5)]
    assert [round(p[1], 6) for p in placed] == [round(2.0 + k * LINE, 6) for k in range(5)]
    assert all(apart(a, b) for a, b in itertools.combinations(spacer.placed, 2))


def test_labels_far_apart_stay_where_they_were_asked() -> None:
    spacer = LabelSpacer()
    assert spacer.place((0.0, 0.0, 0.0), "Area A") == (0.0, 0.0, 0.0)
    far = width_of("Area A") + 0.01
    assert spacer.place((far, 0.0, 0.5), "Area B") == (far, 0.0, 0.5)


@given(st.lists(label, max_size=40))
def test_no_two_labels_overlap(labels: list[tuple[float, float, float, str]]) -> None:
    spacer = LabelSpacer()
    for x, y, z, text in labels:
        spacer.place((x, y, z), text)
    assert all(apart(a, b) for a, b in itertools.combinations(spacer.placed, 2))


def test_rewind_forgets_a_run_s_labels_and_offsets_are_relative() -> None:
    spacer = LabelSpacer()
    spacer.place((0.0, 0.0, 0.0), "x")
    mark = spacer.mark()
    spacer.place((0.0, 0.0, 0.0), "x")
    spacer.rewind(mark)
    assert spacer.place((0.0, 0.0, 0.0), "x")[1] == LINE
    assert offset((1.0, 2.0, 3.5), (1.0, 2.0, 3.0)) == (0.0, 0.0, 0.5)
