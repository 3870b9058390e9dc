"""Reference systems: the one source of example models for tests, examples and benchmarks."""

from __future__ import annotations

from importlib import resources

from ._toml import parse_model
from .build import ModelBuilder
from .spec import Model

__all__ = ["lagrange_top", "LAGRANGE_TOP_TOML", "planar_chain"]


def _read(name: str) -> str:
    return resources.files("lagrangian.model").joinpath("data", name).read_text(encoding="utf-8")


#: The seed's heavy symmetric top as a model file (the default of `lagrangian derive`).
LAGRANGE_TOP_TOML = _read("lagrange_top.toml")


def lagrange_top() -> Model:
    """The seed's worked example: the heavy symmetric top with a fixed point O."""
    return parse_model(LAGRANGE_TOP_TOML, source="<lagrange_top>")



def planar_chain(n: int) -> Model:
    """The planar n-link pendulum: point masses m_k on massless rods of length l_k.

    Rod k joins P_{k-1} to P_k (P_0 = O, a fixed pivot); the plane of motion is
    (O; x0, y0) with x0 pointing *down*, so gravity is ``g*R0.x``.

    Coordinates ``theta1`` ... ``theta<n>`` are **absolute** angles: θ_k is the angle
    of rod k from the downward vertical x0, and frame ``R<k>`` comes straight from R0
    by the rotation (θ_k, z0), with rod k along ``R<k>.x``::

        OP_k = l_1 R1.x + l_2 R2.x + ... + l_k Rk.x

    Absolute rather than relative angles (frame k from frame k−1) because that is
    what "measured from the vertical" means, and because it keeps every expression
    short: the frames R_i and R_j differ by the single rotation θ_j − θ_i, so the
    mass matrix is the textbook M_ij = (Σ_{k≥max(i,j)} m_k) l_i l_j cos(θ_i − θ_j)
    and gravity only gives −(Σ_{k≥i} m_k) g l_i sin θ_i.  (With relative angles the
    same system reads with cos(θ_{i+1} + ... + θ_j): longer and no faster.)

    Parameters ``m<k>`` = 1 kg, ``l<k>`` = 1 m and ``g`` = 9.81 m/s² have values, and
    the chain starts at rest with θ_k(0) = 0.5 rad, so the model can be simulated as is.

    Examples
    --------
    >>> [c.name for c in planar_chain(3).coordinates]
    ['theta1', 'theta2', 'theta3']
    """
    if isinstance(n, bool) or not isinstance(n, int) or n < 1:
        raise ValueError(f"a planar chain needs a positive whole number of links, not {n!r}")
    b = ModelBuilder(f"planar {n}-link pendulum",
                     f"Planar pendulum of {n} point masses on massless rods, absolute angles from the "
                     "downward vertical")
    b.parameter("g", 9.81, unit="m/s^2", description="gravitational acceleration (along x0, downwards)")
    for k in range(1, n + 1):
        b.parameter(f"m{k}", 1.0, unit="kg", description=f"mass of P{k}")
        b.parameter(f"l{k}", 1.0, unit="m", description=f"length of rod {k}, P{k - 1}P{k}")
    for k in range(1, n + 1):
        b.coordinate(f"theta{k}", initial=0.5, rate=0.0, unit="rad",
                     description=f"angle of rod {k} from the downward vertical")
    b.frame("R0", None, axes=("x0", "y0", "z0"))
    for k in range(1, n + 1):
        b.frame(f"R{k}", "R0", rotation=(f"theta{k}", "z"))
    position = ""
    for k in range(1, n + 1):
        position += f"{' + ' if k > 1 else ''}l{k}*R{k}.x"
        b.particle(f"P{k}", mass=f"m{k}", position=position)
    b.gravity("weight", "g*R0.x")
    return b.build()
