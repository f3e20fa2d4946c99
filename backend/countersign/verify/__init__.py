"""Every check on mission orders; `validate(orders)` runs them all and returns the report.

The report module pulls in numpy, shapely and pyproj (and z3 when there is logic to check), so
it is imported when `validate` or `Report` is first asked for, not whenever a light submodule
(expressions, structure) is.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:
    from .report import Report, validate

__all__ = ["Report", "validate"]


def __getattr__(name: str) -> Any:
    if name in __all__:
        from . import report

        return getattr(report, name)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
