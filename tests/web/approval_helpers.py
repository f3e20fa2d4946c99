"""Helpers for the approval tests: a supervisor's key, submissions, signing like a client."""

from __future__ import annotations

import json
from collections.abc import Iterator
from contextlib import contextmanager
from dataclasses import dataclass
from typing import Any

from cryptography.hazmat.primitives.asymmetric.ed25519 import Ed25519PrivateKey
from fastapi.testclient import TestClient
from sqlalchemy import event, text

from countersign.approvals import dsse
from countersign.store.db import Database

from .conftest import PASSWORD, World

MISSION = "search-and-sample"
TABLES = ("events", "log_entries", "approvals", "checkpoints", "submissions", "signing_keys")


@dataclass
class Signer:
    key: Ed25519PrivateKey
    key_id: str


def register_key(client: TestClient, name: str = "laptop") -> Signer:
    key = dsse.generate_key()
    response = client.post("/api/keys", json={"public_key": dsse.public_text(key), "name": name,
                                              "password": PASSWORD})
    assert response.status_code == 201, response.text
    return Signer(key, response.json()["key_id"])


def new_version(world: World, role: str = "operator") -> int:
    response = world.client(role).post(f"/api/missions/{MISSION}/versions")
    assert response.status_code == 201, response.text
    return int(response.json()["number"])


def submit(world: World, number: int, role: str = "operator") -> int:
    response = world.client(role).post(f"/api/missions/{MISSION}/versions/{number}/submit")
    assert response.status_code == 201, response.text
    return int(response.json()["id"])


def prepare(client: TestClient, submission: int, signer: Signer, decision: str = "approved",
            reason: str = "") -> dict[str, Any]:
    response = client.post(f"/api/submissions/{submission}/statement",
                           json={"decision": decision, "reason": reason,
                                 "key_id": signer.key_id})
    assert response.status_code == 200, response.text
    data: dict[str, Any] = response.json()
    return data


def envelope_for(payload: bytes, signer: Signer) -> str:
    return json.dumps(dsse.sign_envelope(payload, signer.key))


def sign_prepared(prepared: dict[str, Any], signer: Signer) -> str:
    """Sign exactly the PAE bytes the server handed out, as the browser does."""
    pae = dsse.unb64(prepared["pae"], "pae")
    payload = dsse.unb64(prepared["payload"], "payload")
    assert pae == dsse.pae(dsse.PAYLOAD_TYPE, payload)
    signature = signer.key.sign(pae)
    return json.dumps({"payloadType": prepared["payloadType"], "payload": prepared["payload"],
                       "signatures": [{"keyid": signer.key_id, "sig": dsse.b64(signature)}]})


def approve(world: World, client: TestClient, signer: Signer, submission: int,
            decision: str = "approved", reason: str = "") -> dict[str, Any]:
    envelope = sign_prepared(prepare(client, submission, signer, decision, reason), signer)
    response = client.post(f"/api/submissions/{submission}/decision",
                           json={"envelope": envelope, "password": PASSWORD})
    assert response.status_code == 201, response.text
    data: dict[str, Any] = response.json()
    return data


def counts(database: Database) -> dict[str, int]:
    with database.engine.connect() as connection:
        return {t: int(connection.execute(text(f"SELECT count(*) FROM {t}")).scalar_one())
                for t in TABLES}


def bypass_triggers(database: Database, table: str, sql: str, **params: Any) -> None:
    """Change a protected row directly, as an attacker with database access would."""
    with database.engine.begin() as connection:
        if connection.dialect.name == "postgresql":
            connection.execute(text(f"ALTER TABLE {table} DISABLE TRIGGER USER"))
            connection.execute(text(sql), params)
            connection.execute(text(f"ALTER TABLE {table} ENABLE TRIGGER USER"))
        else:
            connection.execute(text(f"DROP TRIGGER IF EXISTS {table}_no_update"))
            connection.execute(text(sql), params)


@contextmanager
def statements_run(world: World) -> Iterator[list[str]]:
    """The SQL statements the app runs inside the block, to count queries per request."""
    statements: list[str] = []

    def count(_conn: Any, _cursor: Any, statement: str, *_args: Any) -> None:
        statements.append(statement)

    event.listen(world.database.engine, "before_cursor_execute", count)
    try:
        yield statements
    finally:
        event.remove(world.database.engine, "before_cursor_execute", count)
