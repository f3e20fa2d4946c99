"""Every setting Countersign reads from the environment, in this one module (pydantic).

Each `COUNTERSIGN_*` variable is a field below, under its own name; nothing else in the package
reads the environment (tests/core/test_settings_place.py). The variables are read in groups,
each when its user needs it, as before: the server's when a server or command opens the
database (`Settings.from_environment`), the log key's when the log signer opens, the password
limit when the throttle is imported, the installation paths when a file is looked up, the
client's when the command line runs. A group with a bad value raises SettingsError naming the
variable and what is wrong; a group never fails for another group's variable.

A leaf module: it imports nothing of ours but other leaves, so that every layer (the command
line as well as the web app) takes its settings from here.

Each group is a plain pydantic model validated from the environment's variables, not a
pydantic-settings class: pydantic-settings imports asyncio, dotenv and its cloud providers,
about a tenth of a `countersign validate` process, which reads one path from here (the land
mask's cache). tests/core/test_settings_reading.py holds the two readings equal.
"""

from __future__ import annotations

import os
from pathlib import Path
from typing import Annotated, Any, TypeVar

from platformdirs import user_data_dir
from pydantic import (
    BaseModel,
    BeforeValidator,
    ConfigDict,
    Field,
    SecretStr,
    ValidationError,
    field_validator,
)

from .limits import MAX_BODY_BYTES
from .map_tiles import checked_template

FRONTEND_DIST = Path(__file__).resolve().parents[2] / "frontend" / "dist"
MAX_VALIDATION_PROCESSES = 64
DEFAULT_VALIDATION_PROCESSES = 2
DEFAULT_PASSWORD_CHECKS = 10
MAX_PASSWORD_CHECKS = 1000
MAX_ATTRIBUTION = 200
DEFAULT_SERVER = "http://127.0.0.1:8000"
LOG_KEY_DIR_VARIABLE = "COUNTERSIGN_LOG_KEY_DIR"
LEGACY_LOG_KEY_VARIABLE = "COUNTERSIGN_LOG_KEY"


class SettingsError(ValueError):
    """An environment variable holds an unusable value; the message names it and says why."""


def _blank_is_none(value: Any) -> Any:
    """An empty (or blank) variable means the variable is not set."""
    return None if isinstance(value, str) and not value.strip() else value


def _whole_number(name: str, low: int, high: int,
                  blank: int | None = None) -> BeforeValidator:
    """A whole number from low to high, written in digits; `blank` is what an empty value
    means (None: an empty value is refused like any other)."""

    def check(value: Any) -> Any:
        if not isinstance(value, str):
            return value
        if blank is not None:  # this variable always allowed spaces around its number
            if not value.strip():
                return blank
            value = value.strip()
        if not value.isdigit() or not low <= int(value) <= high:
            raise ValueError(f"{name} must be a whole number from {low} to {high}, "
                             f"not {value!r}")
        return int(value)

    return BeforeValidator(check)


def _yes(value: Any) -> Any:
    """1, true or yes (any case) mean on; anything else, off (as this variable always read)."""
    return value.lower() in {"1", "true", "yes"} if isinstance(value, str) else value


def _tiles(value: Any) -> Any:
    if isinstance(value, str):
        value = value.strip()
        return checked_template(value) if value else None
    return value


def _attribution(value: Any) -> Any:
    return value.strip()[:MAX_ATTRIBUTION] if isinstance(value, str) else value


OptionalPath = Annotated[Path | None, BeforeValidator(_blank_is_none)]


class _Environment(BaseModel):
    """A group of variables, each field under its variable's exact name (validation_alias,
    case-sensitive); an unset variable is the field's default, validated too."""

    # Built when first read: a command reads one group of the five.
    model_config = ConfigDict(frozen=True, extra="ignore", validate_default=True,
                              defer_build=True)


class ServerEnvironment(_Environment):
    data_dir: OptionalPath = Field(None, validation_alias="COUNTERSIGN_DATA_DIR")
    database_url: str = Field("", validation_alias="COUNTERSIGN_DATABASE_URL")
    secure_cookies: Annotated[bool, BeforeValidator(_yes)] = Field(
        False, validation_alias="COUNTERSIGN_SECURE_COOKIES")
    validation_processes: Annotated[int, _whole_number(
        "COUNTERSIGN_VALIDATION_PROCESSES", 0, MAX_VALIDATION_PROCESSES)] = Field(
        DEFAULT_VALIDATION_PROCESSES, validation_alias="COUNTERSIGN_VALIDATION_PROCESSES")
    map_tiles: Annotated[str | None, BeforeValidator(_tiles)] = Field(
        None, validation_alias="COUNTERSIGN_MAP_TILES")
    map_tiles_attribution: Annotated[str, BeforeValidator(_attribution)] = Field(
        "", validation_alias="COUNTERSIGN_MAP_TILES_ATTRIBUTION")


class LogKeyEnvironment(_Environment):
    # The log signer's key directory (default: `log-signer/` in the data directory).
    log_key_dir: OptionalPath = Field(None, validation_alias=LOG_KEY_DIR_VARIABLE)
    # Where the log key lived before the signer had its own directory (imported on upgrade).
    legacy_log_key: Annotated[SecretStr | None, BeforeValidator(_blank_is_none)] = Field(
        None, validation_alias=LEGACY_LOG_KEY_VARIABLE)


class PasswordEnvironment(_Environment):
    # Password hashes per account and minute (the browser suite raises it for its few
    # shared accounts).
    checks_per_minute: Annotated[int, _whole_number(
        "COUNTERSIGN_PASSWORD_CHECKS_PER_MINUTE", 1, MAX_PASSWORD_CHECKS,
        blank=DEFAULT_PASSWORD_CHECKS)] = Field(
        DEFAULT_PASSWORD_CHECKS, validation_alias="COUNTERSIGN_PASSWORD_CHECKS_PER_MINUTE")


class InstallationEnvironment(_Environment):
    # The folder holding meo.ttl (the Docker image sets it; ontology_files.py).
    ontology_dir: OptionalPath = Field(None, validation_alias="COUNTERSIGN_ONTOLOGY_DIR")
    # The bit-packed land mask's cache file (verify/land_mask.py).
    land_mask_cache: OptionalPath = Field(None, validation_alias="COUNTERSIGN_LAND_MASK_CACHE")


class ClientEnvironment(_Environment):
    # The server the command line's client commands talk to, and their API token.
    server: str = Field(DEFAULT_SERVER, validation_alias="COUNTERSIGN_SERVER")
    token: Annotated[SecretStr | None, BeforeValidator(_blank_is_none)] = Field(
        None, validation_alias="COUNTERSIGN_TOKEN")
    # Any value: an internal error of the command line shows its trace.
    debug: bool = Field(False, validation_alias="COUNTERSIGN_DEBUG")

    @field_validator("debug", mode="before")
    @classmethod
    def _any_value(cls, value: Any) -> Any:
        return bool(value) if isinstance(value, str) else value


E = TypeVar("E", bound=_Environment)


def read(group: type[E]) -> E:
    """The group's variables from the environment; SettingsError naming each bad one."""
    try:
        return group.model_validate(dict(os.environ))
    except ValidationError as exc:
        raise SettingsError("; ".join(_explain(error) for error in exc.errors())) from None


def _explain(error: Any) -> str:
    where = ".".join(str(part) for part in error.get("loc", ()))
    cause = (error.get("ctx") or {}).get("error")
    if isinstance(cause, ValueError) and where in str(cause):
        return str(cause)
    return f"{where}: {cause or error.get('msg')}"


def password_checks_per_minute() -> int:
    return read(PasswordEnvironment).checks_per_minute


class Settings(BaseModel):
    """The server's settings. Built from the environment (`from_environment`) by the command
    line, or given whole (tests, scripts), in which case no variable is read."""

    model_config = ConfigDict(frozen=True, defer_build=True)  # the server's alone

    data_dir: Path
    database_url: str
    secure_cookies: bool = False
    max_body_bytes: int = MAX_BODY_BYTES
    frontend_dist: Path = FRONTEND_DIST
    # Processes that validate orders beside each server process (0: in the server's threads).
    # Two, so that one user's heavy validation leaves one for another's edit (validation_pool).
    validation_processes: int = Field(DEFAULT_VALIDATION_PROCESSES, ge=0,
                                      le=MAX_VALIDATION_PROCESSES)
    # Map tiles under the plan view (map_tiles.py): a checked URL template, or None (offline).
    map_tiles: str | None = None
    map_tiles_attribution: str = ""

    @field_validator("map_tiles")
    @classmethod
    def _checked_tiles(cls, value: str | None) -> str | None:
        return None if value is None else checked_template(value)

    @classmethod
    def from_environment(cls, data_dir: Path | None = None, *,
                         validation_processes: int | None = None) -> Settings:
        """COUNTERSIGN_DATA_DIR (or `data_dir`, or the per-user data directory),
        COUNTERSIGN_DATABASE_URL (or SQLite in the data directory) and the rest of
        ServerEnvironment; `validation_processes` overrides its variable."""
        env = read(ServerEnvironment)
        chosen = data_dir or env.data_dir or Path(user_data_dir("countersign",
                                                                 appauthor=False))
        chosen = chosen.expanduser().resolve()
        return cls(
            data_dir=chosen,
            database_url=env.database_url or f"sqlite:///{chosen / 'countersign.db'}",
            secure_cookies=env.secure_cookies,
            validation_processes=(env.validation_processes if validation_processes is None
                                  else validation_processes),
            map_tiles=env.map_tiles, map_tiles_attribution=env.map_tiles_attribution)

    def prepare(self) -> None:
        self.data_dir.mkdir(parents=True, exist_ok=True, mode=0o700)
