"""Map tiles under the plan view, when an administrator configures a tile server.

The default is none: the plan view is drawn offline from the server's land mask. With
COUNTERSIGN_MAP_TILES set to a URL template such as `https://tiles.example.org/{z}/{x}/{y}.png`
the browser draws those (Web Mercator, 256-pixel) tiles beneath it, and the page's
Content-Security-Policy allows images from exactly that origin and no other.

The template is checked when the server starts: https (plain http only to this machine, for a
local tile server), a host, no credentials, no fragment, and the placeholders {z}, {x} and {y},
each once, with no other braces: anything else is refused with what is wrong."""

from __future__ import annotations

import re
from urllib.parse import urlsplit

PLACEHOLDERS = ("{z}", "{x}", "{y}")
LOOPBACK_HOSTS = {"localhost", "127.0.0.1", "::1"}
MAX_TEMPLATE = 500


def checked_template(template: str) -> str:
    """The template itself when it is usable; ValueError naming the problem otherwise."""
    problem = _problem(template)
    if problem is not None:
        raise ValueError(f"COUNTERSIGN_MAP_TILES {template[:80]!r}: {problem}")
    return template


def _problem(template: str) -> str | None:
    if len(template) > MAX_TEMPLATE:
        return f"longer than {MAX_TEMPLATE} characters"
    if any(ch.isspace() or ord(ch) < 32 for ch in template) or any(
            ch in template for ch in "\"'<>\\`"):
        return "contains spaces, quotes, angle brackets or control characters"
    missing = [p for p in PLACEHOLDERS if template.count(p) != 1]
    if missing:
        return f"needs each of {', '.join(PLACEHOLDERS)} exactly once ({', '.join(missing)})"
    rest = template
    for placeholder in PLACEHOLDERS:
        rest = rest.replace(placeholder, "0")
    if "{" in rest or "}" in rest:
        return "has braces other than {z}, {x} and {y}"
    try:
        parts = urlsplit(rest)
        host = parts.hostname
        parts.port  # noqa: B018 -- raises on a bad port
    except ValueError as exc:
        return f"is not a URL ({exc})"
    if parts.scheme not in ("https", "http") or not host:
        return "must be an https:// URL with a host"
    if parts.scheme == "http" and host not in LOOPBACK_HOSTS:
        return "must be https:// (plain http only for a tile server on this machine)"
    if parts.username is not None or parts.password is not None:
        return "must not carry a user name or password"
    if parts.fragment or "#" in rest:
        return "must not have a #fragment"
    if not re.fullmatch(r"[A-Za-z0-9.\-\[\]:]+", parts.netloc):
        return "has an unusual host"
    return None


def tile_origin(template: str) -> str:
    """scheme://host[:port] of the tiles, as a CSP source."""
    parts = urlsplit(template.replace("{z}", "0").replace("{x}", "0").replace("{y}", "0"))
    return f"{parts.scheme}://{parts.netloc}"
