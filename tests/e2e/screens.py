"""Geometry helpers of the browser tests, and a check of a page's tables on the screens the
suite looks at (1024x768 and 1280x800): each table inside its card and the window, nothing
scrolling the page sideways, axe-core clean, and a screenshot per screen in the artifacts folder
for a person to look at."""

from __future__ import annotations

from pathlib import Path

import pytest
from playwright.sync_api import Locator, Page

from .conftest import SCREENS, expect_accessible

__all__ = ["SCREENS"]


def shot(page: Page, tmp_path_factory: pytest.TempPathFactory, name: str, *,
         full_page: bool = False) -> Path:
    """A screenshot `name.png` in the run's artifacts folder, for a person to look at."""
    shots = tmp_path_factory.getbasetemp() / "artifacts"
    shots.mkdir(exist_ok=True)
    path = shots / f"{name}.png"
    page.screenshot(path=str(path), full_page=full_page)
    print(f"screenshot: {path}")
    return path


def box(locator: Locator) -> dict[str, float]:
    found = locator.bounding_box()
    assert found is not None, f"{locator} is not rendered"
    return found


def inside(inner: dict[str, float], outer: dict[str, float], what: str) -> None:
    assert inner["x"] >= outer["x"] - 1 and inner["y"] >= outer["y"] - 1, (what, inner, outer)
    assert inner["x"] + inner["width"] <= outer["x"] + outer["width"] + 1, (what, inner, outer)
    assert inner["y"] + inner["height"] <= outer["y"] + outer["height"] + 1, (what, inner, outer)


def no_page_scroll_sideways(page: Page) -> None:
    overflow = page.evaluate("() => document.documentElement.scrollWidth - window.innerWidth")
    assert overflow <= 0, f"the page scrolls sideways by {overflow} px"


def font_px(locator: Locator) -> float:
    return float(locator.evaluate("e => parseFloat(getComputedStyle(e).fontSize)"))


def tables_fit_each_screen(page: Page, tmp_path_factory: pytest.TempPathFactory, name: str,
                           tables: list[tuple[Locator, Locator]], *,
                           include: str | None = None) -> None:
    """For each (table, card) at each screen: the table's box inside the card's and the
    window's; then a screenshot `name-WxH.png` and axe-core on the page (or `include`). The
    window is left at the size it had."""
    before = page.viewport_size
    for width, height in SCREENS:
        page.set_viewport_size({"width": width, "height": height})
        for table, card in tables:
            table.scroll_into_view_if_needed()
            where = f"{name}: {table} at {width}x{height}"
            inside(box(table), box(card), f"{where}, inside its card")
            table_box = box(table)
            assert table_box["x"] >= 0 and table_box["x"] + table_box["width"] <= width, (
                where, table_box)
        no_page_scroll_sideways(page)
        tables[0][0].scroll_into_view_if_needed()
        shot(page, tmp_path_factory, f"{name}-{width}x{height}")
        expect_accessible(page, f"{name} at {width}x{height}", include=include)
    if before is not None:
        page.set_viewport_size(before)
