"""One exception hierarchy for the whole package.

Every message is a full sentence in the house form: what was wrong (names in
backticks), the rule, and how to fix it.  Model-file errors also carry the file,
the line (where TOML gives one) and the offending symbol, so the command line can
print ``FILE:LINE: error: ...`` followed by a ``tip:`` line.
"""

from __future__ import annotations

__all__ = [
    "AnalysisError",
    "DerivationError",
    "EnsembleInterrupted",
    "ExportError",
    "IdentificationError",
    "Interrupted",
    "KinematicsError",
    "LagrangianError",
    "ModelError",
    "OptimizationError",
    "OutputError",
    "ProblemError",
    "SimulationError",
    "VerificationError",
]


class LagrangianError(Exception):
    """Base class of every error `lagrangian` raises on purpose.

    ``exit_code`` is what the command line returns for it: 2 for a bad model or a
    derivation that cannot be done, 3 for an output that cannot be written, 4 for a
    simulation that cannot go on.

    Parameters
    ----------
    message : str
        What was wrong, a full sentence naming the culprit in backticks.
    fix : str, optional
        How to fix it, printed after the message (``Fix: ...``); None when there is nothing to add.
    """

    exit_code = 2

    def __init__(self, message: str, *, fix: str | None = None) -> None:
        super().__init__(message)
        self.message = message
        self.fix = fix

    def __str__(self) -> str:
        return self.message if self.fix is None else f"{self.message} Fix: {self.fix}"


class ModelError(LagrangianError):
    """The description of the system is wrong: bad syntax, unknown name, non-physical data.

    Parameters
    ----------
    message : str
        What was wrong, a full sentence naming the culprit in backticks.
    fix : str, optional
        How to fix it, printed after the message.
    file : str, optional
        The file where the problem is, when known.
    line : int, optional
        Its 1-based line in ``file``, when known.
    column : int, optional
        Its 1-based column in that line, when known.
    symbol : str, optional
        The offending name, when there is one.
    source_line : str, optional
        The text of that line, for the command line to print under the message.
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
    """The kinematics cannot be computed (e.g. a declared fixed point moves).

    Parameters
    ----------
    message : str
        What was wrong, a full sentence naming the culprit in backticks.
    fix : str, optional
        How to fix it, printed after the message.
    """


class DerivationError(LagrangianError):
    """The equations of motion cannot be formed (e.g. a singular mass matrix).

    Parameters
    ----------
    message : str
        What was wrong, a full sentence naming the culprit in backticks.
    fix : str, optional
        How to fix it, printed after the message.
    """


class AnalysisError(LagrangianError):
    """A motion cannot be analysed: a missing value, an unbounded or singular motion.

    The analysis stage's errors derive from it (`lagrangian.analysis`: `LinearizationError`,
    `EquilibriumError`, `ControlError`, `StructureError`, ...).

    Parameters
    ----------
    message : str
        What was wrong, a full sentence naming the culprit in backticks.
    fix : str, optional
        How to fix it, printed after the message.
    """


class SimulationError(LagrangianError):
    """A simulation cannot start or go on: missing value, bad initial state, singular M, step underflow.

    Parameters
    ----------
    message : str
        What was wrong, a full sentence naming the culprit in backticks.
    fix : str, optional
        How to fix it, printed after the message.
    t : float, optional
        The time reached when it stopped, when it had started.
    state : ndarray, optional
        The state (q, q̇) at that time, when known.
    trajectory : Trajectory, optional
        The part computed before a run stopped early (stiff equations, ``max_steps``), its status
        saying so, or None.
    """

    exit_code = 4

    def __init__(self, message: str, *, fix: str | None = None, t: float | None = None, state=None,
                 trajectory=None) -> None:
        super().__init__(message, fix=fix)
        self.t = t
        self.state = state
        self.trajectory = trajectory


class ProblemError(ModelError):
    """An optimal-control problem is ill-stated (`lagrangian.optimize`, a problem file).

    An unknown name, reversed bounds, too few nodes, a model without inputs, a value or an expression
    that cannot be read.  A `ModelError`, so that a problem file's mistake is printed with its file and
    line; ``table`` is the problem file's table the offending ``symbol`` is a key of (``"final"``,
    ``"bounds"``...), when known.

    Parameters
    ----------
    message : str
        What was wrong, a full sentence naming the culprit in backticks.
    fix : str, optional
        How to fix it, printed after the message.
    file : str, optional
        The problem file, when known.
    line : int, optional
        The 1-based line of the problem in ``file``, when known.
    column : int, optional
        Its 1-based column in that line, when known.
    symbol : str, optional
        The offending name, when there is one.
    source_line : str, optional
        The text of that line, for the command line to print under the message.
    """

    table: str | None = None


class OptimizationError(LagrangianError):
    """An optimization cannot be run: CasADi is missing, or the solver stopped on an error of its own.

    A problem that has no solution is not an error: `lagrangian.optimize` returns the solver's last
    iterate with its status (``infeasible``) for the caller to look at.

    Parameters
    ----------
    message : str
        What was wrong, a full sentence naming the culprit in backticks.
    fix : str, optional
        How to fix it, printed after the message.
    """

    exit_code = 4


class Interrupted(KeyboardInterrupt):
    """Ctrl-C (SIGINT) stopped a compiled run between two steps.

    A `KeyboardInterrupt`, so code that stops on Ctrl-C still stops; ``written`` is the file the
    command line saved the part computed so far to, or None.

    Parameters
    ----------
    t : float
        The time reached.
    trajectory : Trajectory, optional
        The part computed so far (its ``status`` says it was interrupted), or None when no output
        time was reached.
    """

    def __init__(self, t: float, trajectory=None) -> None:
        super().__init__(f"interrupted at t = {t:.9g}")
        self.t = t
        self.trajectory = trajectory
        self.written: str | None = None


class EnsembleInterrupted(KeyboardInterrupt):
    """Ctrl-C (SIGINT) stopped an ensemble: ``done`` of ``count`` members were finished.

    ``written`` is the Zarr store that holds them (finish it with ``resume``), or None;
    ``dataset`` the in-memory results (pending members have status ``pending``), or None.

    Parameters
    ----------
    done : int
        How many members were finished.
    count : int
        How many members the ensemble has.
    """

    def __init__(self, done: int, count: int) -> None:
        super().__init__(f"interrupted after {done} of {count} members")
        self.done, self.count = done, count
        self.written: str | None = None
        self.dataset = None


class OutputError(LagrangianError):
    """An output file cannot be written; whatever was there before is left as it was.

    Parameters
    ----------
    message : str
        What was wrong, a full sentence naming the culprit in backticks.
    fix : str, optional
        How to fix it, printed after the message.
    """

    exit_code = 3


class ExportError(LagrangianError):
    """The equations cannot be exported as asked; nothing is written.

    The target may be unknown, or the model one the target cannot express (complementary
    constraints, an exact stick/slip contact).

    Parameters
    ----------
    message : str
        What was wrong, a full sentence naming the culprit in backticks.
    fix : str, optional
        How to fix it, printed after the message.
    """


class VerificationError(LagrangianError):
    """A cross-check failed: the Lagrange equations disagree with the Newton–Euler theorems.

    Parameters
    ----------
    message : str
        What was wrong, a full sentence naming the culprit in backticks.
    fix : str, optional
        How to fix it, printed after the message.
    """

    exit_code = 5


class IdentificationError(LagrangianError):
    """Parameters cannot be identified from the measurements given.

    The data may be unreadable or inconsistent (a missing value, times that do not increase, an
    unknown column), a parameter unknown or unidentifiable (the combinations that can be identified
    are listed), or the fit may not converge.

    Parameters
    ----------
    message : str
        What was wrong, a full sentence naming the culprit in backticks.
    fix : str, optional
        How to fix it, printed after the message.
    """

    exit_code = 2
