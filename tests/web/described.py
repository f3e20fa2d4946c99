"""Whether a response model describes a JSON value exactly (typed API).

A field typed `SchemaOf(Model)` passes the stored value through untouched, so the answer alone
cannot show that `Model` is right: a field the model forgets is still answered, and the
front end's generated type silently lacks it. Reading the value with the model and writing it
back must give the same JSON text: a forgotten field is dropped, a retyped one is rewritten
(an int read as a float gains ".0")."""

from __future__ import annotations

import json
from typing import Any

from pydantic import BaseModel, TypeAdapter


def _text(value: Any) -> str:
    return json.dumps(value, sort_keys=True, ensure_ascii=False)


def assert_described(model: type[BaseModel] | Any, value: Any) -> None:
    """`model` (a Pydantic model or a type such as list[Model]) reads `value` and writes back
    exactly it: no field dropped, none retyped, none added."""
    adapter: TypeAdapter[Any] = TypeAdapter(model)
    again = adapter.dump_python(adapter.validate_python(value), mode="json", by_alias=True,
                                 exclude_unset=True)
    name = model.__name__ if isinstance(model, type) else str(model)
    assert _text(again) == _text(value), (
        f"{name} does not describe the value exactly:\n  described {_text(again)[:2000]}\n"
        f"  value     {_text(value)[:2000]}")
