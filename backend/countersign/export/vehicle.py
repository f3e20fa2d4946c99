"""One entry point for every vehicle format, for the command line, the API and packages."""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

from ..orders.model import Orders
from .notes import VehicleExport
from .provenance import Provenance, provenance_of
from .team import Member, select_member

FORMATS = ("imc", "moos")


def _exporter(fmt: str) -> Callable[[Orders, Provenance, Member | None], VehicleExport]:
    # imcpy is a compiled binding: load it only when IMC is asked for.
    if fmt == "imc":
        from .imc import export_imc

        return export_imc
    if fmt == "moos":
        from .moos import export_moos

        return export_moos
    raise ValueError(f"unknown vehicle format {fmt!r}; choose one of {', '.join(FORMATS)}")


def export_vehicle(orders: Orders, fmt: str, *, version: int | None = None,
                   approval: dict[str, Any] | None = None,
                   member: str | None = None) -> VehicleExport:
    """The orders in a vehicle format; raises ExportError when they cannot be a plan. Team
    orders need `member`: that vehicle's files are written, from its own orders (whose digest
    the provenance names, as the team's approval names it) and its meetings."""
    exporter = _exporter(fmt)
    chosen = select_member(orders, member)
    own = orders if chosen is None else chosen.orders
    return exporter(own, provenance_of(own, version=version, approval=approval), chosen)
