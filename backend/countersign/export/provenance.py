"""Which orders an export was written from: digest, version and (when signed) the approval."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

from ..orders.canonical import digest
from ..orders.model import Orders


@dataclass(frozen=True)
class Provenance:
    mission: str
    digest: str
    version: int | None = None
    # Approval facts as recorded: envelope digest, decision, supervisor, time (None: unsigned).
    approval: dict[str, Any] | None = None

    @property
    def plan_id(self) -> str:
        # IMC plan ids travel over acoustic links: short, but naming mission and version.
        tag = f"v{self.version}" if self.version is not None else self.digest[7:19]
        return f"{self.mission}@{tag}"

    def to_json(self) -> dict[str, Any]:
        return {"generator": "countersign", "mission": self.mission, "version": self.version,
                "orders_digest": self.digest, "approval": self.approval}


def provenance_of(orders: Orders, *, version: int | None = None,
                  approval: dict[str, Any] | None = None) -> Provenance:
    return Provenance(orders.id, digest(orders), version, approval)
