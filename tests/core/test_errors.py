"""Domain errors carry no HTTP: one hierarchy in countersign.errors,
mapped to the status codes the API has always answered by web/problems.py. One name per error:
no two exception classes of the package share a name, none is an alias of another, and routes
raise domain errors for domain cases (HTTPException only for what is HTTP's own)."""

from __future__ import annotations

import ast
import builtins
from pathlib import Path

import pytest
from fastapi import FastAPI, HTTPException
from fastapi.testclient import TestClient

from countersign import errors
from countersign.store.accounts import AccountError, TooManyAttempts
from countersign.store.approvals import (
    BadDecision,
    BadKey,
    BadSignature,
    LogUnvouched,
    Refused,
    Stale,
)
from countersign.store.campaigns import CampaignNotThisVersion
from countersign.store.cosignatures import BadCosignature
from countersign.store.missions import BadDraft, Conflict, NotFound, PreconditionFailed
from countersign.store.reauth import PasswordRequired
from countersign.store.rehearsals import RecordNotThisVersion
from countersign.web import problems
from countersign.web.problems import status_of
from countersign.web.rehearsal_hub import Busy, TooManyForUser

# The status each error answered with before the hierarchy (their former `status` attributes).
FORMER_STATUS: list[tuple[errors.DomainError, int]] = [
    # The former MissionError (an alias of DomainError) of drafts, decisions and keys.
    (BadDraft("x"), 400), (BadDecision("x"), 400), (BadKey("x"), 400),
    (NotFound("x"), 404), (Conflict("x"), 409), (CampaignNotThisVersion("x"), 409),
    (PreconditionFailed("x", 3), 412), (Refused("x"), 403), (Stale("x"), 409),
    (BadSignature("x"), 400), (LogUnvouched("x"), 503), (PasswordRequired("x"), 403),
    (BadCosignature("x"), 400), (RecordNotThisVersion("x"), 409), (TooManyForUser("x"), 429),
    (Busy("x"), 503), (errors.Gone("x"), 410), (errors.Unprocessable("x"), 422),
    (AccountError("x"), 400), (TooManyAttempts("x"), 429),
]


@pytest.mark.parametrize(("error", "status"), FORMER_STATUS,
                         ids=[type(e).__name__ for e, _ in FORMER_STATUS])
def test_each_domain_error_maps_to_its_former_status(error: errors.DomainError,
                                                     status: int) -> None:
    assert status_of(error) == status


def _subclasses(cls: type) -> set[type]:
    found = set()
    for sub in cls.__subclasses__():
        found |= {sub} | _subclasses(sub)
    return found


def test_no_domain_error_carries_an_http_status() -> None:
    # Importing problems above imported every module that defines one.
    for cls in _subclasses(errors.DomainError) | {errors.DomainError}:
        assert "status" not in vars(cls), f"{cls.__qualname__} carries an HTTP status"


PACKAGE = Path(__file__).resolve().parents[2] / "backend" / "countersign"


def _exception_classes(root: Path) -> tuple[list[str], list[str]]:
    """(name, where) of every exception class the package defines, and every module-level
    alias of one (`Name = OtherError`)."""
    trees = {path: ast.parse(path.read_text(encoding="utf-8"))
             for path in sorted(root.rglob("*.py"))}
    known = {name for name in dir(builtins)
             if isinstance(getattr(builtins, name), type)
             and issubclass(getattr(builtins, name), BaseException)}
    # Library bases the package subclasses (FastAPI's HTTPException, its own errors' bases).
    known |= {"HTTPException", "ValidationError", "DomainError"}
    defined: dict[str, list[str]] = {}
    # Every class and its bases' names, read once: the fixed point below goes over them again
    # for each new exception class found (walking every tree each time cost seconds).
    classes = [(path, node.name, {ast.unparse(base).rsplit(".", 1)[-1] for base in node.bases})
               for path, tree in trees.items() for node in ast.walk(tree)
               if isinstance(node, ast.ClassDef)]
    grew = True
    while grew:  # a class is an exception when one of its bases is
        grew = False
        for _, name, bases in classes:
            if name not in known and not bases.isdisjoint(known):
                known.add(name)
                grew = True
    for path, name, _ in classes:
        if name in known:
            defined.setdefault(name, []).append(str(path.relative_to(root.parent)))
    aliases = []
    for path, tree in trees.items():
        where = str(path.relative_to(root.parent))
        for node in tree.body:
            if isinstance(node, ast.Assign) and isinstance(node.value, ast.Name) and \
                    node.value.id in known:
                aliases.append(f"{where}:{node.lineno} {ast.unparse(node)}")
    twice = [f"{name}: {', '.join(places)}" for name, places in sorted(defined.items())
             if len(places) > 1]
    return twice, aliases


def test_one_name_per_error() -> None:
    twice, aliases = _exception_classes(PACKAGE)
    assert twice == [] and aliases == []


def test_the_name_check_sees_a_second_class_and_an_alias(tmp_path: Path) -> None:
    (tmp_path / "countersign" / "store").mkdir(parents=True)
    (tmp_path / "countersign" / "errors.py").write_text(
        "class DomainError(Exception): ...\nclass Refused(DomainError): ...\n")
    (tmp_path / "countersign" / "store" / "a.py").write_text(
        "from ..errors import DomainError, Refused as R\nclass Refused(R): ...\n"
        "MissionError = DomainError\n")
    assert _exception_classes(tmp_path / "countersign") == (
        ["Refused: countersign/errors.py, countersign/store/a.py"],
        ["countersign/store/a.py:3 MissionError = DomainError"])


# What routes may still raise as HTTPException: HTTP's own cases, no domain kind answers them.
HTTP_ONLY = {
    401: "authentication: the problem carries WWW-Authenticate (routes/auth.py sign-in)",
    412: "an If-Match header that is no ETag of this API (the domain's 412 carries a revision)",
    413: "a body too large for the route",
    428: "a request without the If-Match header it needs",
}


def http_exceptions(root: Path) -> list[str]:
    found = []
    for path in sorted(root.rglob("*.py")):
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            if isinstance(node, ast.Call) and ast.unparse(node.func) == "HTTPException":
                status = node.args[0] if node.args else None
                if not (isinstance(status, ast.Constant) and status.value in HTTP_ONLY):
                    found.append(f"{path.relative_to(root)}:{node.lineno} "
                                 f"HTTPException({ast.unparse(status) if status else ''})")
    return found


def test_routes_raise_domain_errors_for_domain_cases(tmp_path: Path) -> None:
    assert http_exceptions(PACKAGE / "web" / "routes") == []
    (tmp_path / "r.py").write_text("def f():\n    raise HTTPException(404, 'no user 3')\n"
                                   "def g():\n    raise HTTPException(428, 'send If-Match')\n")
    assert http_exceptions(tmp_path) == ["r.py:2 HTTPException(404)"]


@pytest.mark.parametrize(("status", "kind"), [
    (400, errors.Invalid), (404, errors.NotFound), (409, errors.Conflict),
    (422, errors.Unprocessable)])
def test_a_domain_error_answers_the_bytes_its_http_exception_did(
        status: int, kind: type[errors.DomainError]) -> None:
    app = FastAPI()
    problems.install(app)
    detail = "the chart's id 'a' differs from 'b'"

    @app.get("/http")
    def as_http() -> None:
        raise HTTPException(status, detail)

    @app.get("/domain")
    def as_domain() -> None:
        raise kind(detail)

    client = TestClient(app)
    before, after = client.get("/http"), client.get("/domain")
    assert before.status_code == after.status_code == status
    assert after.content == before.content.replace(b"/http", b"/domain")
    assert dict(after.headers) == {**before.headers,
                                   "content-length": str(len(after.content))}
