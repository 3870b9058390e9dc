"""Reference systems: the one source of example models for tests, examples and benchmarks."""

from __future__ import annotations

from importlib import resources

from ._toml import parse_model
from .build import ModelBuilder
from .spec import Model

__all__ = ["lagrange_top", "LAGRANGE_TOP_TOML", "planar_chain", "spatial_chain", "relative_chain", "serial_arm",
           "MAX_LINKS"]

#: Most links of a zoo chain: a 100-link chain already has a 100 x 100 mass matrix, and a
#: size from the command line (``zoo:planar_chain:N``) must not start an endless derivation.
MAX_LINKS = 100


def _read(name: str) -> str:
    return resources.files("lagrangian.model").joinpath("data").joinpath(name).read_text(encoding="utf-8")


#: The seed's heavy symmetric top as a model file (the default of `lagrangian derive`).
LAGRANGE_TOP_TOML = _read("lagrange_top.toml")


def lagrange_top() -> Model:
    """The seed's worked example: the heavy symmetric top with a fixed point O.

    Returns
    -------
    Model
        The top, with its parameters' values and an initial state.
    """
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

    Parameters
    ----------
    n : int
        The number of links.

    Returns
    -------
    Model
        The chain, ready to simulate.

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

    Parameters
    ----------
    n : int
        The number of rods.

    Returns
    -------
    Model
        The chain, ready to simulate.

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


def relative_chain(n: int) -> Model:
    """`planar_chain` written as a robot: the same pendulum in **relative** joint angles.

    Frame ``R<k>`` comes from ``R<k-1>`` by the rotation (φ_k, z), so φ_k is the angle of rod
    k from rod k − 1 (φ_1 from the downward vertical x0) and θ_k = φ_1 + ... + φ_k::

        OP_k = l_1 R1.x + l_2 R2.x + ... + l_k Rk.x

    The expanded mass matrix then holds cos(φ_{i+1} + ... + φ_j) and grows several-fold per
    link; `derive` gives this model the recursive formulation (`dynamics._recursive`), whose
    intermediates grow linearly.  Same parameters (``m<k>``, ``l<k>``, ``g``) and values as
    `planar_chain`; at rest with φ_1(0) = 0.5 rad and the other angles 0 (the same start).

    Parameters
    ----------
    n : int
        The number of links.

    Returns
    -------
    Model
        The chain, ready to simulate.

    Examples
    --------
    >>> [c.name for c in relative_chain(2).coordinates]
    ['phi1', 'phi2']
    """
    _check_links(n, "planar")
    b = ModelBuilder(f"planar {n}-link pendulum, relative angles",
                     f"Planar pendulum of {n} point masses on massless rods, relative joint angles")
    b.parameter("g", 9.81, unit="m/s^2", description="gravitational acceleration (along x0, downwards)")
    for k in range(1, n + 1):
        b.parameter(f"m{k}", 1.0, unit="kg", description=f"mass of P{k}")
        b.parameter(f"l{k}", 1.0, unit="m", description=f"length of rod {k}, P{k - 1}P{k}")
    for k in range(1, n + 1):
        b.coordinate(f"phi{k}", initial=0.5 if k == 1 else 0.0, rate=0.0, unit="rad",
                     description="angle of rod 1 from the downward vertical" if k == 1 else
                     f"angle of rod {k} from rod {k - 1}")
    b.frame("R0", None, axes=("x0", "y0", "z0"))
    for k in range(1, n + 1):
        b.frame(f"R{k}", "R0" if k == 1 else f"R{k - 1}", rotation=(f"phi{k}", "z"))
    for k in range(1, n + 1):
        b.particle(f"P{k}", mass=f"m{k}", position=f"l{k}*R{k}.x", relative_to="O" if k == 1 else f"P{k - 1}")
    b.gravity("weight", "g*R0.x")
    return b.build()


#: The joint axes of `serial_arm`, in turn (a common 6R/7R pattern of a robot arm).
ARM_AXES = ("z", "y", "y", "x", "y", "x", "z")


def serial_arm(n: int, *, damping: bool = False) -> Model:
    """A 3D serial arm: n revolute joints about z, y, y, x, y, x, z, z, y, ... (relative angles).

    Link k turns by q_k about axis ``ARM_AXES[(k-1) % 7]`` of link k − 1 (of R0 for k = 1) at
    the joint J_k, J_1 = O and J_{k+1} = J_k + a_k Rk.z.  Link k (mass m_k) has its centre
    of mass off every axis, G_k = J_k + cx_k Rk.x + cy_k Rk.y + cz_k Rk.z, and a full inertia
    matrix at G_k in Rk (moments I1_k, I2_k, I3_k and products P_k); gravity is −g z0.
    Each joint has a motor torque input ``tau<k>`` (on link k, reacting on link k − 1), and
    with ``damping`` a viscous joint damper of coefficient ``c<k>``.  The kind of system
    Pinocchio, Drake or SymPy's mechanics simulate as a robot; the benchmark
    ``benchmarks/robot_chains.py`` checks it against Pinocchio.

    Values: a_k = 0.3 m, m_k = 1 kg, (cx, cy, cz) = (0.02, −0.01, 0.15) m,
    (I1, I2, I3, P) = (0.010, 0.012, 0.004, 0.001) kg·m², g = 9.81 m/s²; q_k(0) = 0.3 rad.

    Parameters
    ----------
    n : int
        The number of joints.
    damping : bool, optional
        Adds a viscous joint damper of coefficient ``c<k>`` to each joint.

    Returns
    -------
    Model
        The arm, ready to simulate.

    Examples
    --------
    >>> [c.name for c in serial_arm(3).coordinates]
    ['q1', 'q2', 'q3']
    """
    _check_links(n, "serial arm")
    b = ModelBuilder(f"{n}-joint serial arm", f"3D serial arm of {n} revolute joints, relative angles")
    b.parameter("g", 9.81, unit="m/s^2", description="gravitational acceleration (along -z0)")
    for k in range(1, n + 1):
        b.parameter(f"a{k}", 0.3, unit="m", description=f"length of link {k}, J{k}J{k + 1} along R{k}.z")
        b.parameter(f"m{k}", 1.0, unit="kg", description=f"mass of link {k}")
        for axis, value in (("x", 0.02), ("y", -0.01), ("z", 0.15)):
            b.parameter(f"c{axis}{k}", value, unit="m", description=f"centre of mass of link {k} along R{k}.{axis}")
        for name, value in (("I1", 0.010), ("I2", 0.012), ("I3", 0.004), ("P", 0.001)):
            b.parameter(f"{name}_{k}", value, unit="kg*m^2", description=f"inertia of link {k} at G{k} in R{k}")
        if damping:
            b.parameter(f"c{k}", 0.05, unit="N*m*s", description=f"viscous damping of joint {k}")
        b.input(f"tau{k}", unit="N*m", description=f"motor torque of joint {k}")
    for k in range(1, n + 1):
        b.coordinate(f"q{k}", initial=0.3, rate=0.0, unit="rad", description=f"angle of joint {k}")
    b.frame("R0", None, axes=("x0", "y0", "z0"))
    for k in range(1, n + 1):
        axis = ARM_AXES[(k - 1) % len(ARM_AXES)]
        b.frame(f"R{k}", "R0" if k == 1 else f"R{k - 1}", rotation=(f"q{k}", axis))
        b.point(f"J{k + 1}", f"a{k}*R{k}.z", relative_to="O" if k == 1 else f"J{k}")
        b.body(f"link{k}", frame=f"R{k}", mass=f"m{k}", center=f"cx{k}*R{k}.x + cy{k}*R{k}.y + cz{k}*R{k}.z",
               center_from="O" if k == 1 else f"J{k}",
               inertia={"at": "G", "frame": f"R{k}",
                        "matrix": [[f"I1_{k}", f"-P_{k}", "0"], [f"-P_{k}", f"I2_{k}", f"P_{k}"],
                                   ["0", f"P_{k}", f"I3_{k}"]]})
        b.torque(f"motor{k}", f"tau{k}*R{k}.{axis}", on=f"link{k}", reaction_on=f"link{k - 1}" if k > 1 else None)
        if damping:
            b.joint_damper(f"damper{k}", (f"link{k - 1}" if k > 1 else "R0", f"link{k}"), coefficient=f"c{k}")
    b.gravity("weight", "-g*R0.z")
    return b.build()
