"""Request bodies parsed under the application's one JSON policy (`countersign.strict_json`).

FastAPI parses JSON bodies with `Request.json()`, i.e. Python's lenient `json.loads`: a
`1e999` in `PUT /api/vehicles` became infinity and was stored as `null`, and duplicate keys
silently kept the last value. Routes get a Request whose `json()` applies the policy; its
refusal is an HTTPException (FastAPI re-raises those from body parsing) carrying the path.
"""

from __future__ import annotations

from collections.abc import Callable, Coroutine
from typing import Any

from fastapi import HTTPException, Request, Response

from .. import strict_json


class BodyPolicyError(HTTPException):
    """A JSON body refused by the policy: a 422 problem naming the JSON path."""

    def __init__(self, error: strict_json.JsonPolicyError) -> None:
        super().__init__(422, "the request body is not acceptable JSON")
        self.errors = [{"path": error.path, "message": error.message}]


class StrictJsonRequest(Request):
    async def json(self) -> Any:
        if not hasattr(self, "_json"):
            try:
                self._json = strict_json.loads(await self.body())
            except strict_json.JsonPolicyError as exc:
                raise BodyPolicyError(exc) from None
        return self._json


Handler = Callable[[Request], Coroutine[Any, Any, Response]]


def strict_handler(handler: Handler) -> Handler:
    async def run(request: Request) -> Response:
        return await handler(StrictJsonRequest(request.scope, request.receive))

    return run
