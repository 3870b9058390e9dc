"""Reference systems: the one source of example models for tests, examples and benchmarks."""

from __future__ import annotations

from importlib import resources

from ._toml import parse_model
from .build import ModelBuilder
from .spec import Model

__all__ = ["lagrange_top", "LAGRANGE_TOP_TOML", "planar_chain", "spatial_chain", "MAX_LINKS"]

#: Most links of a zoo chain: a 100-link chain already has a 100 x 100 mass matrix, and a
#: size from the command line (``zoo:planar_chain:N``) must not start an endless derivation.
MAX_LINKS = 100


def _read(name: str) -> str:
    return resources.files("lagrangian.model").joinpath("data", name).read_text(encoding="utf-8")


#: The seed's heavy symmetric top as a model file (the default of `lagrangian derive`).
LAGRANGE_TOP_TOML = _read("lagrange_top.toml")


def lagrange_top() -> Model:
    """The seed's worked example: the heavy symmetric top with a fixed point O."""
    return parse_model(LAGRANGE_TOP_TOML, source="<lagrange_top>")



def _check_links(n: object, kind: str) -> None:
    if isinstance(n, bool) or not isinstance(n, int) or not 1 <= n <= MAX_LINKS:
        raise ValueError(f"a {kind} chain needs a whole number of links from 1 to {MAX_LINKS}, not {n!r}")


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
    _check_links(n, "planar")
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



def spatial_chain(n: int) -> Model:
    """The 3D n-link pendulum: uniform thin rods joined end to end by ball joints.

    Rod k (mass m_k, length l_k, uniform and thin) joins P_{k-1} to P_k (P_0 = O, a fixed
    point); gravity is ``-g*R0.z``.  Each rod's direction is given by two **absolute**
    angles, measured from the fixed frame R0 as in `planar_chain`::

        S<k> = R0 rotated by (alpha<k>, x0),   R<k> = S<k> rotated by (beta<k>, y),

    and the rod lies along −R<k>.z, the unit vector
    d_k = (−sin β_k, sin α_k cos β_k, −cos α_k cos β_k) in R0::

        OP_k = −l_1 R1.z − ... − l_k Rk.z,   OG_k = OP_{k−1} − (l_k/2) Rk.z.

    The inertia of rod k at G_k in R<k> is diag(m_k l_k²/12, m_k l_k²/12, 0): a thin rod
    has none about its own axis, so T and U depend only on the directions d_k and their
    rates, and the same system is described by a robot arm of universal joints (relative
    angles, e.g. Pinocchio's ``JointModelRX`` then ``JointModelRY`` per link) in other
    coordinates.  Absolute angles keep M_ij a short function of the angles of rods i
    and j (relative angles make every entry depend on all the angles before: the
    expressions of a 10-link chain run to millions of terms).  The angles are singular
    where cos β_k = 0 (rod k along ±x0: gimbal lock).

    Parameters ``m<k>`` = 1 kg, ``l<k>`` = 1 m and ``g`` = 9.81 m/s² have values; the
    chain starts at rest with α_k(0) = 0.4 rad and β_k(0) = 0.2 rad.

    Examples
    --------
    >>> [c.name for c in spatial_chain(2).coordinates]
    ['alpha1', 'beta1', 'alpha2', 'beta2']
    """
    _check_links(n, "spatial")
    b = ModelBuilder(f"spatial {n}-link pendulum",
                     f"3D pendulum of {n} uniform thin rods joined by ball joints, absolute angles")
    b.parameter("g", 9.81, unit="m/s^2", description="gravitational acceleration (along -z0)")
    for k in range(1, n + 1):
        b.parameter(f"m{k}", 1.0, unit="kg", description=f"mass of rod {k}")
        b.parameter(f"l{k}", 1.0, unit="m", description=f"length of rod {k}, P{k - 1}P{k}")
    for k in range(1, n + 1):
        b.coordinate(f"alpha{k}", initial=0.4, rate=0.0, unit="rad",
                     description=f"rotation of rod {k}'s direction about x0")
        b.coordinate(f"beta{k}", initial=0.2, rate=0.0, unit="rad",
                     description=f"rotation of rod {k}'s direction about the y-axis of S{k}")
    b.frame("R0", None, axes=("x0", "y0", "z0"))
    for k in range(1, n + 1):
        b.frame(f"S{k}", "R0", rotation=(f"alpha{k}", "x"))
        b.frame(f"R{k}", f"S{k}", rotation=(f"beta{k}", "y"))
    for k in range(1, n + 1):
        start = "O" if k == 1 else f"P{k - 1}"
        b.point(f"P{k}", f"-l{k}*R{k}.z", relative_to=start)
        rod = f"m{k}*l{k}^2/12"
        b.body(f"rod{k}", frame=f"R{k}", mass=f"m{k}", center=f"-l{k}/2*R{k}.z", center_from=start,
               inertia={"at": "G", "frame": f"R{k}", "diagonal": [rod, rod, "0"]})
    b.gravity("weight", "-g*R0.z")
    return b.build()
