"""What an export could not carry, named as finding-style notes instead of dropped silently."""

from __future__ import annotations

from dataclasses import dataclass, field


@dataclass(frozen=True)
class ExportNote:
    code: str
    # Where in the orders the uncarried part lives, as a JSON pointer (e.g. /constraints/2).
    path: str
    message: str

    def to_json(self) -> dict[str, str]:
        return {"code": self.code, "path": self.path, "message": self.message}

    def line(self) -> str:
        return f"note {self.code} {self.path}: {self.message}"


@dataclass(frozen=True)
class ExportFile:
    name: str
    media_type: str
    content: bytes


@dataclass(frozen=True)
class VehicleExport:
    format: str
    files: tuple[ExportFile, ...]
    notes: tuple[ExportNote, ...] = field(default_factory=tuple)

    @property
    def primary(self) -> ExportFile:
        return self.files[0]

    def file(self, name: str) -> ExportFile | None:
        return next((f for f in self.files if f.name == name), None)


class ExportError(ValueError):
    """Orders that cannot become a vehicle plan at all (e.g. structural errors)."""
