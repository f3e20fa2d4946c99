"""Approved packages (`countersign.package/1`): the orders, their vehicle files (`export`) and
the approval's evidence (`approvals`) in one deterministic tar (`build`), checked offline on the
vehicle (`verify`) and unpacked only after it verifies (`unpack`).

It joins `export` and `approvals`, which may not import each other, so it sits one ring above
them (README, Development; tests/codebase/test_layering.py); the store, the web app and the command
line call in."""
