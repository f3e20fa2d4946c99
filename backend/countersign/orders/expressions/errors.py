"""Limits on expression text and the error every reader of it raises: a message and the 1-based
column where the problem starts."""

from __future__ import annotations

MAX_LENGTH = 10_000
MAX_DEPTH = 40
MAX_TERMS = 1_000
MAX_TOKENS = 4 * MAX_TERMS
MAX_DIGITS = 30
MAX_EXPONENT = 30


class ExprError(ValueError):
    """A syntax or type error at a 1-based column of the expression text."""

    def __init__(self, message: str, column: int) -> None:
        super().__init__(message)
        self.message = message
        self.column = column

    def located(self, label: str) -> str:
        return f"{label}, column {self.column}: {self.message}"
