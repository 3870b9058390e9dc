"""One exception hierarchy for the whole package.

Every message is a full sentence in the house form: what was wrong (names in
backticks), the rule, and how to fix it.  Model-file errors also carry the file,
the line (where TOML gives one) and the offending symbol, so the command line can
print ``FILE:LINE: error: ...`` followed by a ``tip:`` line.
"""

from __future__ import annotations

__all__ = [
    "LagrangianError",
    "ModelError",
    "KinematicsError",
    "DerivationError",
]


class LagrangianError(Exception):
    """Base class of every error `lagrangian` raises on purpose."""

    def __init__(self, message: str, *, fix: str | None = None) -> None:
        super().__init__(message)
        self.message = message
        self.fix = fix

    def __str__(self) -> str:
        return self.message if self.fix is None else f"{self.message} Fix: {self.fix}"


class ModelError(LagrangianError):
    """The description of the system is wrong: bad syntax, unknown name, non-physical data.

    Attributes
    ----------
    file, line, column : where the problem is, when known (1-based).
    symbol : the offending name, when there is one.
    """

    def __init__(
        self,
        message: str,
        *,
        fix: str | None = None,
        file: str | None = None,
        line: int | None = None,
        column: int | None = None,
        symbol: str | None = None,
        source_line: str | None = None,
    ) -> None:
        super().__init__(message, fix=fix)
        self.file = file
        self.line = line
        self.column = column
        self.symbol = symbol
        self.source_line = source_line

    @property
    def location(self) -> str:
        """``file:line:column`` as far as it is known, or an empty string."""
        parts = [p for p in (self.file, self.line, self.column) if p is not None]
        return ":".join(str(p) for p in parts)

    def __str__(self) -> str:
        text = self.message if self.fix is None else f"{self.message} Fix: {self.fix}"
        return f"{self.location}: {text}" if self.location else text


class KinematicsError(LagrangianError):
    """The kinematics cannot be computed (e.g. a declared fixed point moves)."""


class DerivationError(LagrangianError):
    """The equations of motion cannot be formed (e.g. a singular mass matrix)."""
