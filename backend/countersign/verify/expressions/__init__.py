"""The expression language's meaning: types and units (types), partial evaluation on a goal's
facts (evaluate) and the translation to SMT-LIB and z3 (smt).

The syntax (tree, lexer, parser, errors with columns), the built-in vocabulary and the plain
words live in `countersign.orders.expressions`; they are re-exported here so that a check needs
one import for the whole language.
"""

from ...orders.expressions import *  # noqa: F403
from ...orders.expressions import __all__ as _syntax
from .evaluate import UNKNOWN, Facts, fold
from .smt import Translator, smt_int, smt_real, to_smtlib, to_z3
from .types import Kind, TypeChecker, Typed, check_condition

__all__ = [
    *_syntax,
    "UNKNOWN", "Facts", "Kind", "Translator", "TypeChecker", "Typed", "check_condition", "fold",
    "smt_int", "smt_real", "to_smtlib", "to_z3",
]
