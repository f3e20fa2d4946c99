"""Every format orders can be written in, behind one function for the CLI and the API."""

from __future__ import annotations

import json
from collections.abc import Callable

from .canonical import orders_to_json
from .model import Orders


def _json(orders: Orders) -> str:
    return json.dumps(orders_to_json(orders), indent=2) + "\n"


def _dot(orders: Orders) -> str:
    from .dot import to_dot

    return to_dot(orders)


def _plain(orders: Orders) -> str:
    from .plain import plain_orders

    return plain_orders(orders).rstrip("\n") + "\n"


def _turtle(orders: Orders) -> str:
    from .turtle import write_turtle

    return write_turtle(orders)


def _nps_turtle(orders: Orders) -> str:
    from .turtle import write_nps_turtle

    return write_nps_turtle(orders)


def _avcl(orders: Orders) -> str:
    from .avcl_writer import write_avcl

    return write_avcl(orders)


# format name -> (writer, media type, file suffix)
WRITERS: dict[str, tuple[Callable[[Orders], str], str, str]] = {
    "json": (_json, "application/json", "json"),
    "dot": (_dot, "text/vnd.graphviz", "dot"),
    "plain": (_plain, "text/plain; charset=utf-8", "txt"),
    "turtle": (_turtle, "text/turtle", "ttl"),
    "nps-turtle": (_nps_turtle, "text/turtle", "nps.ttl"),
    "avcl": (_avcl, "application/xml", "xml"),
}


def write(orders: Orders, fmt: str) -> str:
    return WRITERS[fmt][0](orders)
