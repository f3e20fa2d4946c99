"""One entry point for every vehicle format, for the command line, the API and packages."""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

from ..orders.model import Orders
from .notes import VehicleExport
from .provenance import Provenance, provenance_of

FORMATS = ("imc", "moos")


def _exporter(fmt: str) -> Callable[[Orders, Provenance], VehicleExport]:
    # imcpy is a compiled binding: load it only when IMC is asked for.
    if fmt == "imc":
        from .imc import export_imc

        return export_imc
    if fmt == "moos":
        from .moos import export_moos

        return export_moos
    raise ValueError(f"unknown vehicle format {fmt!r}; choose one of {', '.join(FORMATS)}")


def export_vehicle(orders: Orders, fmt: str, *, version: int | None = None,
                   approval: dict[str, Any] | None = None) -> VehicleExport:
    """The orders in a vehicle format; raises ExportError when they cannot be a plan."""
    exporter = _exporter(fmt)
    return exporter(orders, provenance_of(orders, version=version, approval=approval))
