"""tools/verify_package.py, the standalone package verifier, loaded as a module from its file
(it is no package of the project: vehicles run it alone)."""

from __future__ import annotations

import importlib.util
from pathlib import Path
from types import ModuleType

TOOL = Path(__file__).resolve().parents[1] / "tools" / "verify_package.py"


def standalone_verifier() -> ModuleType:
    spec = importlib.util.spec_from_file_location("verify_package", TOOL)
    assert spec is not None and spec.loader is not None
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module
