"""Kinematics of a model: positions, velocities, accelerations, Ω, and the virtual velocity field.

The virtual velocity field compatible with the principal constraints is
V*(P) = Σ_i ∂OP/∂q_i q_i*  (seed, section I), and ∂OP/∂q_i = ∂V(P/R0)/∂q̇_i, so the
*partial velocities* ∂V(P/R0)/∂q̇_i are the coefficients of the field.  Likewise the
partial angular velocities ∂Ω(S/R0)/∂q̇_i give the virtual rotation rate Ω*(S).
"""

from __future__ import annotations

import symengine as se

from ..errors import KinematicsError
from ..model import ORIGIN, TIME, Model, Point, Vector
from ._frames import FrameTree
from ._time import TimeDerivative

__all__ = ["Kinematics"]

_ZERO = se.Integer(0)
_ZERO_TYPE = type(_ZERO)


class Kinematics:
    """Everything kinematic about a `Model`, computed on demand and cached.

    Parameters
    ----------
    model : Model
        The model.

    Attributes
    ----------
    q, qd, qdd : tuple of SymEngine Symbol
        The symbols q_i, q̇_i, q̈_i in coordinate order.
    t : SymEngine Symbol
        The time symbol.
    frames : FrameTree
        Change of basis and Ω.
    """

    def __init__(self, model: Model) -> None:
        self.model = model
        self.q = tuple(c.symbol for c in model.coordinates)
        self.qd = tuple(c.rate_symbol for c in model.coordinates)
        self.qdd = tuple(c.acceleration_symbol for c in model.coordinates)
        self.q_star = tuple(se.Symbol(c.name + "_star") for c in model.coordinates)
        self.t = TIME
        self.d_dt = TimeDerivative.of(self.q, self.qd, self.qdd, self.t)
        self.frames = FrameTree(model, self.d_dt)
        points: dict[str, Point] = {p.name: p for p in model.points}
        points.update({b.name: Point(b.name, b.center) for b in model.bodies})
        points.update({p.name: Point(p.name, p.position) for p in model.particles})
        self._points = points
        self._velocity: dict[str, Vector] = {}
        self._acceleration: dict[tuple[str, bool], Vector] = {}
        self._partials: dict[str, tuple[Vector, ...]] = {}
        self._omega_partials: dict[str, tuple[Vector, ...]] = {}
        self._rate_index = {qd: i for i, qd in enumerate(self.qd)}

    @property
    def n(self) -> int:
        """Number of principal parameters (and of Lagrange equations, Remarque 1)."""
        return len(self.q)

    # -- points ------------------------------------------------------------------------------
    def position(self, point: str) -> Vector:
        """OP, the position of ``point`` from O (a body name means its centre of mass G).

        Parameters
        ----------
        point : str
            A point, body or particle name.

        Returns
        -------
        Vector
            OP.
        """
        try:
            return self._points[point].position
        except KeyError:
            raise KinematicsError(f"unknown point `{point}`", fix="use a declared point, body or particle") from None

    def velocity(self, point: str) -> Vector:
        """V(P/R0) = d OP/dt relative to R0.

        Parameters
        ----------
        point : str
            A point, body or particle name.

        Returns
        -------
        Vector
            V(P/R0).
        """
        if point not in self._velocity:
            self._velocity[point] = self.frames.derivative(self.position(point))
        return self._velocity[point]

    def acceleration(self, point: str, *, accelerations: bool = True) -> Vector:
        """The acceleration γ(P/R0), whole or without its part in q̈.

        Parameters
        ----------
        point : str
            A point, body or particle name.
        accelerations : bool, optional
            With ``accelerations=False``, the part free of q̈ (the q̈ part is Σ ∂V/∂q̇_j q̈_j).

        Returns
        -------
        Vector
            The acceleration γ(P/R0), or its part free of q̈.
        """
        key = (point, accelerations)
        if key not in self._acceleration:
            self._acceleration[key] = self.frames.derivative(self.velocity(point), accelerations=accelerations)
        return self._acceleration[key]

    def partial_velocities(self, point: str) -> tuple[Vector, ...]:
        """The partial velocities (∂OP/∂q_i)_i = (∂V(P/R0)/∂q̇_i)_i, the coefficients of V*(P).

        Parameters
        ----------
        point : str
            A point, body or particle name.

        Returns
        -------
        tuple of Vector
            One per coordinate.
        """
        if point not in self._partials:
            self._partials[point] = self._rate_partials(self.velocity(point))
        return self._partials[point]

    def _rate_partials(self, v: Vector) -> tuple[Vector, ...]:
        """(v.diff(q̇_i))_i, differentiating each component only by the rates it holds."""
        index = self._rate_index
        pieces: list[dict[str, list[se.Basic]]] = [{} for _ in self.qd]
        for frame, comps in v:
            for axis, c in enumerate(comps):
                if type(c) is _ZERO_TYPE:
                    continue
                for s in c.free_symbols:
                    i = index.get(s)
                    if i is not None:
                        pieces[i].setdefault(frame, [_ZERO, _ZERO, _ZERO])[axis] = c.diff(s)
        # Pieces keep v's frame order: `setdefault` meets the frames in that order.
        return tuple(Vector._trusted({f: tuple(c) for f, c in p.items()}) for p in pieces)

    def virtual_velocity(self, point: str) -> Vector:
        """V*(P) = Σ_i ∂OP/∂q_i q_i*, with the virtual rates written ``<q>_star``.

        Parameters
        ----------
        point : str
            A point, body or particle name.

        Returns
        -------
        Vector
            V*(P).
        """
        out = Vector.zero()
        for partial, star in zip(self.partial_velocities(point), self.q_star, strict=True):
            out = out + partial * star
        return out

    def is_fixed(self, point: str) -> bool:
        """True when V(P/R0) is identically zero.

        Parameters
        ----------
        point : str
            A point, body or particle name.

        Returns
        -------
        bool
            Whether the point is fixed in R0.
        """
        return point == ORIGIN or all(
            se.expand(c) == 0 for comps in self.velocity(point).pieces.values() for c in comps
        )

    # -- rotation ----------------------------------------------------------------------------
    def omega(self, frame: str) -> Vector:
        """Ω(frame/R0) as the sum of the rotation rates of its chain.

        Parameters
        ----------
        frame : str
            The frame.

        Returns
        -------
        Vector
            Ω(frame/R0).
        """
        return self.frames.omega(frame)

    def partial_omegas(self, frame: str) -> tuple[Vector, ...]:
        """The partial rotation rates (∂Ω(frame/R0)/∂q̇_i)_i, the coefficients of the virtual rotation rate Ω*.

        Parameters
        ----------
        frame : str
            The frame.

        Returns
        -------
        tuple of Vector
            One per coordinate.
        """
        if frame not in self._omega_partials:
            self._omega_partials[frame] = self._rate_partials(self.omega(frame))
        return self._omega_partials[frame]
