"""Canaries for the private third-party APIs we use, one adapter each:
rehearse/viser_adapter.py, verify/meo/owlrl_adapter.py, verify/z3_adapter.py. A library
release that renames or reshapes one fails here, naming it, before anything subtler breaks."""

from __future__ import annotations

import inspect
from collections.abc import Iterator
from typing import Any

import pytest

from countersign.rehearse import viser_adapter
from countersign.verify import z3_adapter


@pytest.fixture(scope="module")
def viser_server() -> Iterator[Any]:
    import viser

    server = viser.ViserServer(host="127.0.0.1", port=0, verbose=False)
    try:
        yield server
    finally:
        server.stop()


def test_viser_websocket_server_has_the_attributes_the_adapter_reaches(viser_server: Any) -> None:
    websock = viser_server._websock_server
    assert isinstance(websock._incoming_handlers, dict)
    assert isinstance(websock._live_connections, dict)
    assert isinstance(websock._client_state_from_id, dict)
    assert isinstance(websock._client_connect_cb, list)
    for method in ("register_handler", "unregister_handler", "disconnect_all_clients"):
        assert callable(getattr(websock, method)), method


def test_viser_share_messages_can_be_replaced(viser_server: Any) -> None:
    def drop(client_id: Any, message: Any) -> None:
        return None

    kinds = viser_adapter.share_message_types()
    assert [k.__name__ for k in kinds] == ["ShareUrlRequest", "ShareUrlDisconnect"]
    for kind in kinds:
        viser_adapter.replace_handler(viser_server, kind, drop)
        assert drop in viser_server._websock_server._incoming_handlers[kind]
    assert all(issubclass(k, viser_adapter.message_base()) for k in kinds)


def test_viser_connect_first_runs_before_viser_s_own(viser_server: Any) -> None:
    async def first(client: Any) -> None:
        return None

    viser_adapter.connect_first(viser_server, first)
    assert viser_server._websock_server._client_connect_cb[0] is first
    assert viser_adapter.connection_request_header(viser_server, -1, "X") is None


def test_viser_ships_its_built_client() -> None:
    assert b"<head>" in viser_adapter.client_index_path().read_bytes()


def test_owlrl_equality_hook_has_the_shape_we_override() -> None:
    import owlrl

    from countersign.verify.meo.owlrl_adapter import RoleSemantics

    hook = owlrl.OWLRL_Semantics._equality
    assert list(inspect.signature(hook).parameters) == ["self", "triple", "cycle_num"]
    assert issubclass(RoleSemantics, owlrl.OWLRL_Semantics)
    assert RoleSemantics._equality is not hook


def test_z3_raw_check_assumptions_answers_like_the_wrapper() -> None:
    import z3

    ctx = z3.Context()
    solver = z3.Solver(ctx=ctx)
    a, b = z3.Bool("a", ctx), z3.Bool("b", ctx)
    solver.add(z3.Implies(a, z3.Not(b)))
    assert z3_adapter.check_asts(z3, ctx, solver, [a.as_ast()]) == "sat"
    assert z3_adapter.check_asts(z3, ctx, solver, [a.as_ast(), b.as_ast()]) == "unsat"
    assert {str(x) for x in solver.unsat_core()} == {"a", "b"}
    assert z3_adapter.unsat_core_ids(z3, ctx, solver) == {x.get_id() for x in solver.unsat_core()}
    assert z3_adapter.check_asts(z3, ctx, solver, [a.as_ast()]) == "sat"
    assert str(solver.check(a, b)) == "unsat"


def test_z3_raw_disjunction_and_model_reading_answer_like_the_wrapper() -> None:
    import z3

    ctx = z3.Context()
    solver = z3.Solver(ctx=ctx)
    a, b, c = (z3.Bool(name, ctx) for name in "abc")
    solver.add(z3.Not(a), z3.Implies(b, c))
    z3_adapter.assert_any(z3, ctx, solver, [a, b])
    assert solver.check() == z3.sat
    model = solver.model()
    assert z3_adapter.true_in_model(z3, ctx, model, [a, b, c]) == [
        z3.is_true(model.eval(x, model_completion=True)) for x in (a, b, c)] == [False, True, True]


def test_z3_raw_bool_constant_is_the_wrappers_constant() -> None:
    import gc

    import z3

    ctx = z3.Context()
    ast, ident = z3_adapter.bool_constant(z3, ctx, "a:0")
    same = z3.Bool("a:0", ctx)
    assert ident == same.get_id() == z3.Z3_get_ast_id(ctx.ref(), ast)
    solver = z3.Solver(ctx=ctx)
    solver.push()
    solver.from_string("(declare-const |a:0| Bool)(assert (not |a:0|))")
    del same
    solver.pop()
    gc.collect()
    # Still alive after the assertion that named it was popped and the wrapper dropped it.
    assert z3_adapter.check_asts(z3, ctx, solver, [ast]) == "sat"
    solver.from_string("(assert (not |a:0|))")  # the solver keeps what it declared
    assert z3_adapter.check_asts(z3, ctx, solver, [ast]) == "unsat"
    assert z3_adapter.unsat_core_ids(z3, ctx, solver) == {ident}
