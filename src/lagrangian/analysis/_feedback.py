"""`Feedback`: a linear state feedback u = u* − K (x − x*(t)) about a point, as a value.

About an equilibrium x* is constant; about a steady motion the coordinates that move (absent
from the equations: a spinning arm's angle) advance at their steady rates, x*(t) = x* + ẋ* t,
so that the law regulates the motion about the steady one, not about its start.

`lagrangian.lqr` (`_lqr`) makes one; `simulate(..., inputs=feedback)` runs the nonlinear closed
loop with the law compiled into the right-hand side (`lagrangian.numerics._inputs`).  It lives
here, in the analysis stage, so that numerics (the later stage) can read it without a circle.

The file form is a versioned JSON document (schema ``lagrangian.feedback``, version 1), written
atomically::

    {"schema": "lagrangian.feedback", "version": 1, "model": "...",
     "states": ["x", "theta", "x_dot", "theta_dot"], "inputs": ["F"],
     "K": [[...]], "x_star": [...], "x_star_rate": [...], "u_star": [...], "A": [[...]], "B": [[...]],
     "Q": [[...]], "R": [[...]], "eigenvalues": [[re, im], ...], "parameters": {"m": 0.2, ...}}
"""

from __future__ import annotations

import json
import math
from collections.abc import Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from ..errors import AnalysisError

__all__ = ["FEEDBACK_SCHEMA", "FEEDBACK_VERSION", "ControlError", "Feedback"]

FEEDBACK_SCHEMA = "lagrangian.feedback"
FEEDBACK_VERSION = 1


class ControlError(AnalysisError):
    """A feedback cannot be designed or read.

    An uncontrollable pair, weights of the wrong shape or sign, a point with symbols left, a feedback
    file that is not one.

    Parameters
    ----------
    message : str
        What was wrong, a full sentence naming the culprit in backticks.
    fix : str, optional
        How to fix it, printed after the message.
    """


def _matrix(value: Any, shape: tuple[int, ...], what: str) -> np.ndarray:
    try:
        a = np.array(value, dtype=float)
    except (TypeError, ValueError):
        raise ControlError(f"`{what}` of the feedback must hold numbers.", fix="write it as a list of numbers") \
            from None
    if a.shape != shape:
        raise ControlError(f"`{what}` of the feedback has shape {a.shape}, expected {shape}.",
                           fix="the feedback's states and inputs fix the shapes of K, x*, u*, A, B, Q and R")
    if not np.all(np.isfinite(a)):
        raise ControlError(f"`{what}` of the feedback holds a number that is not finite.",
                           fix="design the feedback again (lagrangian lqr)")
    a.setflags(write=False)
    return a


@dataclass(frozen=True, eq=False)
class Feedback:
    """The state feedback u = u* − K (x − x*(t)) about the point x* held by the inputs u* (module docstring).

    Parameters
    ----------
    model : str
        The model's name.
    states : tuple of str
        The names of x (coordinates ``theta`` and rates ``theta_dot``), in the order of K's columns.
    inputs : tuple of str
        The names of u, in the order of K's rows.
    K : ndarray of shape (m, nx)
        The gain.
    x_star : ndarray of shape (nx,)
        The point.
    u_star : ndarray of shape (m,)
        The inputs that hold it.
    A : ndarray of shape (nx, nx)
        The linearization ẋ = A δx + B δu at the point (`lagrangian.linearize`).
    B : ndarray of shape (nx, m)
        Its input matrix.
    Q : ndarray of shape (nx, nx)
        The weight of δx in the cost ∫ (δxᵀ Q δx + δuᵀ R δu) dt the gain minimizes (LQR).
    R : ndarray of shape (m, m)
        The weight of δu.
    eigenvalues : ndarray of shape (nx,), complex
        Those of A − B K (the closed loop, linearized).
    parameters : mapping of str to float
        The parameter values the linearization used.
    x_star_rate : ndarray of shape (nx,), optional
        The rate ẋ* of each coordinate state along the steady motion (0 about an equilibrium; a
        rate state's entry is always 0): x*(t) = x* + ẋ* t.
    """

    model: str
    states: tuple[str, ...]
    inputs: tuple[str, ...]
    K: np.ndarray
    x_star: np.ndarray
    u_star: np.ndarray
    A: np.ndarray
    B: np.ndarray
    Q: np.ndarray
    R: np.ndarray
    eigenvalues: np.ndarray = field(default_factory=lambda: np.zeros(0, complex))
    parameters: Mapping[str, float] = field(default_factory=dict)
    x_star_rate: np.ndarray | None = None

    def __post_init__(self) -> None:
        nx, m = len(self.states), len(self.inputs)
        if nx == 0 or m == 0:
            raise ControlError("A feedback needs at least one state and one input.", fix="check the linearization")
        for name in ("K", "x_star", "u_star", "A", "B", "Q", "R"):
            shape = {"K": (m, nx), "x_star": (nx,), "u_star": (m,), "A": (nx, nx), "B": (nx, m), "Q": (nx, nx),
                     "R": (m, m)}[name]
            object.__setattr__(self, name, _matrix(getattr(self, name), shape, name))
        rate = np.zeros(nx) if self.x_star_rate is None else self.x_star_rate
        object.__setattr__(self, "x_star_rate", _matrix(rate, (nx,), "x_star_rate"))
        eig = np.asarray(self.eigenvalues, dtype=complex)
        if eig.size == 0:
            eig = np.linalg.eigvals(self.A - self.B @ self.K)
        eig = eig.copy()
        eig.setflags(write=False)
        object.__setattr__(self, "eigenvalues", eig)
        object.__setattr__(self, "states", tuple(self.states))
        object.__setattr__(self, "inputs", tuple(self.inputs))
        object.__setattr__(self, "parameters", dict(self.parameters))

    def __call__(self, x: np.ndarray, t: float | np.ndarray = 0.0) -> np.ndarray:
        """u = u* − K (x − x*(t)) for a state x (nx,) or states (N, nx), in `states` order, at t (N,)."""
        x = np.asarray(x, dtype=float)
        t = np.asarray(t, dtype=float)
        reference = self.x_star + (t[..., None] if t.ndim else t) * self.x_star_rate
        return self.u_star - (x - reference) @ self.K.T

    @property
    def stable(self) -> bool:
        """Every closed-loop eigenvalue has a negative real part."""
        return bool(np.all(self.eigenvalues.real < 0))

    # -- the file form ------------------------------------------------------------------------
    def to_dict(self) -> dict[str, Any]:
        """The versioned JSON document (module docstring) as plain Python values.

        Returns
        -------
        dict of str to object
            The document: lists, numbers and strings.
        """
        return {
            "schema": FEEDBACK_SCHEMA, "version": FEEDBACK_VERSION, "model": self.model,
            "states": list(self.states), "inputs": list(self.inputs),
            "K": self.K.tolist(), "x_star": self.x_star.tolist(), "x_star_rate": self.x_star_rate.tolist(),
            "u_star": self.u_star.tolist(),
            "A": self.A.tolist(), "B": self.B.tolist(), "Q": self.Q.tolist(), "R": self.R.tolist(),
            "eigenvalues": [[float(z.real), float(z.imag)] for z in self.eigenvalues],
            "parameters": {k: float(v) for k, v in self.parameters.items()},
        }

    @classmethod
    def from_dict(cls, doc: Mapping[str, Any], *, where: str = "the feedback") -> Feedback:
        """The `Feedback` of a document made by `to_dict`.

        Parameters
        ----------
        doc : mapping of str to object
            The document.
        where : str, optional
            Names the document in error messages.

        Returns
        -------
        Feedback
            The feedback it holds.

        Raises
        ------
        ControlError
            Another schema or version, a missing key, shapes that do not match, a NaN.
        """
        if not isinstance(doc, Mapping) or doc.get("schema") != FEEDBACK_SCHEMA:
            raise ControlError(f"{where} is not a feedback document (schema `{FEEDBACK_SCHEMA}`).",
                               fix="write one with `lagrangian lqr MODEL ... -o feedback.json` or Feedback.save")
        if doc.get("version") != FEEDBACK_VERSION:
            raise ControlError(f"{where} has version {doc.get('version')!r}; this lagrangian reads version "
                               f"{FEEDBACK_VERSION}.", fix="design the feedback again with this version")
        missing = [k for k in ("model", "states", "inputs", "K", "x_star", "u_star", "A", "B", "Q", "R")
                   if k not in doc]
        if missing:
            raise ControlError(f"{where} has no `{missing[0]}`.", fix="write it with Feedback.save")
        states, inputs = doc["states"], doc["inputs"]
        if not (isinstance(states, list) and all(isinstance(s, str) for s in states)
                and isinstance(inputs, list) and all(isinstance(s, str) for s in inputs)):
            raise ControlError(f"`states` and `inputs` of {where} must be lists of names.",
                               fix="write it with Feedback.save")
        eig = doc.get("eigenvalues") or []
        try:
            eigenvalues = np.array([complex(float(re), float(im)) for re, im in eig], dtype=complex)
        except (TypeError, ValueError):
            raise ControlError(f"`eigenvalues` of {where} must be [re, im] pairs.",
                               fix="write it with Feedback.save") from None
        parameters = doc.get("parameters") or {}
        if not isinstance(parameters, Mapping) or not all(
                isinstance(v, (int, float)) and math.isfinite(v) for v in parameters.values()):
            raise ControlError(f"`parameters` of {where} must map names to finite numbers.",
                               fix="write it with Feedback.save")
        try:
            return cls(str(doc["model"]), tuple(states), tuple(inputs), doc["K"], doc["x_star"], doc["u_star"],
                       doc["A"], doc["B"], doc["Q"], doc["R"], eigenvalues, dict(parameters),
                       doc.get("x_star_rate"))
        except ControlError as exc:
            raise ControlError(f"In {where}: {exc.message}", fix=exc.fix) from None

    def save(self, path: str | Path) -> Path:
        """Write the JSON document to ``path`` atomically.

        Parameters
        ----------
        path : str or Path
            The file to write.

        Returns
        -------
        Path
            The path written.
        """
        from .._atomic import write_atomic

        path = Path(path)
        write_atomic(path, json.dumps(self.to_dict(), indent=2) + "\n")
        return path

    @classmethod
    def load(cls, path: str | Path) -> Feedback:
        """Read a feedback written by `save` (or ``lagrangian lqr ... -o FILE``).

        Parameters
        ----------
        path : str or Path
            The file to read.

        Returns
        -------
        Feedback
            The feedback it holds.

        Raises
        ------
        ControlError
            A file that cannot be read, is not JSON, or is not a feedback document.
        """
        path = Path(path)
        try:
            doc = json.loads(path.read_text(encoding="utf-8"))
        except OSError as exc:
            raise ControlError(f"The feedback file `{path}` cannot be read ({exc.strerror or exc}).",
                               fix="give the file `lagrangian lqr ... -o FILE` wrote") from None
        except (json.JSONDecodeError, UnicodeDecodeError) as exc:
            raise ControlError(f"The feedback file `{path}` is not JSON ({exc}).",
                               fix="give the file `lagrangian lqr ... -o FILE` wrote") from None
        return cls.from_dict(doc, where=f"`{path}`")

    def __repr__(self) -> str:
        return (f"Feedback(model={self.model!r}, states={self.states}, inputs={self.inputs}, "
                f"closed-loop eigenvalues {np.round(self.eigenvalues, 4).tolist()})")
