"""Independent SymPy oracle of the linearized Whipple bicycle (benchmark "peer" check).

Reference
---------
J. P. Meijaard, J. M. Papadopoulos, A. Ruina and A. L. Schwab (2007), "Linearized dynamics
equations for the balance and steer of a bicycle: a benchmark and review", Proc. R. Soc. A
463, 1955-1982, doi:10.1098/rspa.2007.1857 (the benchmark bicycle of its Table 1).

Source of the formulation
-------------------------
The multibody model is the one of SymPy's own test suite,
``sympy/physics/mechanics/tests/test_kane3.py::test_bicycle`` (J. K. Moore's port of his
Autolev bicycle), rebuilt here with ``sympy.physics.mechanics.KanesMethod`` and
``KanesMethod.linearize``.  Nothing of the ``lagrangian`` package is imported.

* coordinates: yaw ``q1`` (about the ground's vertical), lean ``q2`` (about the yawed
  forward axis), pitch ``q4`` of the rear frame (dependent: fixed by the front contact,
  holonomic constraint ``(front contact - rear contact) . vertical = 0``), steer ``q5``
  (about the steering axis); the wheel rotation angles are ignorable and not introduced;
* speeds: ``u1 .. u6`` = yaw, lean, rear-wheel spin, pitch, steer and front-wheel spin
  rates; independent ``u2, u3, u5``, dependent ``u1, u4, u6`` fixed by the three
  nonholonomic rows "velocity of the front contact point = 0" (along the yawed x, y, z);
  the rear contact is used as the (instantaneously at rest) base point;
* linearization about upright, straight-ahead rolling at forward speed ``v``:
  ``q = 0``, ``u3 = v / rR``, ``u6 = v / rF``, every other speed and every ``u'`` zero; the
  4x4 state matrix is the lean/steer block ``[q2, q5, u2, u5]`` of the 6x6 matrix of the
  independent states ``[q1, q2, q5, u2, u3, u5]``.

Sign conventions and the conversions that were needed
-----------------------------------------------------
SymPy's model uses x forward, **y left, z up** (gravity ``-g * Y.z``), whereas the paper
uses x forward, y right, z down.  Hence, at the level of the *input data* only:

* the paper's mass-centre heights ``zB = -0.9`` and ``zH = -0.7`` (z down) become the
  heights ``-zB`` and ``-zH`` above the ground (z up), which are then projected on the
  rear-frame axes of the model (one axis along the steering axis, pointing down-forward,
  the other perpendicular to it, pointing up-forward) to give ``framecg1/3``,
  ``forkcg1/3``, ``framelength``, ``forklength`` and ``forkoffset``;
* the products of inertia change sign: in the frame (x, -y, -z) the xz product is
  ``-Ixz``, so ``Iframe31 = -IBxz = -2.4`` and ``Ifork31 = -IHxz = +0.00756``; the
  moments of inertia are unchanged.

No conversion is needed for the *state*: the lean ``q2`` is a right-handed rotation about
the forward axis in both frames (positive = lean to the right) and the steer ``q5`` is a
right-handed rotation about the steering axis pointing downward (positive = steer to the
right), exactly as the paper's phi and delta.  So ``[q2, q5, u2, u5]`` is the paper's
``[phi, delta, phi_dot, delta_dot]`` and the matrix returned is directly the paper's
``A = [[0, I], [-M^-1 (g K0 + v^2 K2), -M^-1 v C1]]``.  (Checked, outside this module,
against the paper's published M, C1, K0, K2: agreement to ~2e-14 relative to max|A| and
~2e-13 entrywise for v = 0..10; the paper's numbers are never used here.)

Public functions
----------------
``linearized_A(v_values)``
    list of 4x4 ``numpy`` arrays, one per forward speed.  The model is derived once, with
    every parameter except ``v`` already a number (SymPy Floats), linearized once with
    ``v`` symbolic, and cached; later calls only evaluate the quadratic in ``v``.  To make
    the one derivation fast (about 11 s on a 2-core machine instead of about 90 s), SymPy's
    ``Linearizer`` is given the *first-order Taylor polynomials*, about the operating
    point, of the equations ``KanesMethod.to_linearizer`` hands it (see ``_derive_fast``):
    the Linearizer only uses first partial derivatives at the operating point, so its
    result is unchanged, while it no longer has to differentiate ~1e5-operation
    nonlinear expressions.
``derive_and_linearize(symbolic_parameters=True)``
    the timed work of a benchmark: the whole derivation from scratch (no cache) through
    the plain public route ``KanesMethod.kanes_equations`` + ``KanesMethod.linearize``,
    by default with every parameter symbolic as a SymPy user would write it, the numbers
    substituted at the end; returns the 4x4 SymPy Matrix in ``v`` (about 70-75 s with
    symbolic parameters, about 90 s with numeric ones, on a 2-core machine; nearly all of
    it is spent in ``Linearizer`` differentiating the full nonlinear equations).

Caveats
-------
* Both routes use ``CRAMER`` for the constraint and linear solves, as SymPy's test does:
  with Float parameters SymPy's ``LU`` solver picks pivots that vanish at the operating
  point only up to rounding and returns a wrong matrix.
* The numbers are ~15-digit Floats; the two routes differ from each other by rounding
  only (~1e-14 relative).
"""

from __future__ import annotations

import functools
import math
from collections.abc import Iterable

import numpy as np
import sympy as sp
from sympy.physics.mechanics import (
    KanesMethod,
    Point,
    ReferenceFrame,
    RigidBody,
    dot,
    dynamicsymbols,
    inertia,
)
from sympy.physics.mechanics.linearize import Linearizer

__all__ = ["BENCHMARK_PARAMETERS", "linearized_A", "derive_and_linearize", "V"]

#: The forward speed, the only symbol left in the returned matrices.
V = sp.Symbol("v")

#: Table 1 of Meijaard et al. (2007), in the paper's own axes (x forward, y right, z down).
BENCHMARK_PARAMETERS: dict[str, float] = {
    "w": 1.02, "c": 0.08, "lam": math.pi / 10, "g": 9.81,
    "rR": 0.3, "mR": 2.0, "IRxx": 0.0603, "IRyy": 0.12,
    "xB": 0.3, "zB": -0.9, "mB": 85.0,
    "IBxx": 9.2, "IByy": 11.0, "IBzz": 2.8, "IBxz": 2.4,
    "xH": 0.9, "zH": -0.7, "mH": 4.0,
    "IHxx": 0.05892, "IHyy": 0.06, "IHzz": 0.00708, "IHxz": -0.00756,
    "rF": 0.35, "mF": 3.0, "IFxx": 0.1405, "IFyy": 0.28,
}

# Names of the parameters of the SymPy model (those of test_kane3.py).
_MODEL_PARAMETERS = (
    "WFrad WRrad htangle forkoffset forklength framelength forkcg1 forkcg3 framecg1 "
    "framecg3 Iwr11 Iwr22 Iwf11 Iwf22 Iframe11 Iframe22 Iframe33 Iframe31 Ifork11 "
    "Ifork22 Ifork33 Ifork31 g mframe mfork mwf mwr"
).split()


def _model_values(p: dict[str, float] = BENCHMARK_PARAMETERS) -> dict[str, float]:
    """The model's parameters from the paper's (Table 1), as Python floats.

    In the model's rear-frame axes at zero pitch (x forward, z up) the steering axis
    direction (``Frame.x``, pointing down) is ``(sin lam, -cos lam)`` and the normal to it
    (``Frame.z``) is ``(cos lam, sin lam)``; ``Steer`` is the foot of the perpendicular from
    the rear-wheel centre to the steering axis.  Every length below is a projection on
    these two directions of a vector known in the paper's data (heights as z up = -z_paper).
    """
    lam, w, c, rR, rF = p["lam"], p["w"], p["c"], p["rR"], p["rF"]
    sl, cl = math.sin(lam), math.cos(lam)

    def along_axis(dx: float, dz: float) -> float:   # component along Frame.x
        return dx * sl - dz * cl

    def normal(dx: float, dz: float) -> float:       # component along Frame.z
        return dx * cl + dz * sl

    forkoffset = rF * sl - c * cl                      # front-wheel centre off the axis
    # rear-wheel centre -> front-wheel centre is (w, rF - rR)
    forklength = along_axis(w, rF - rR)
    framelength = normal(w, rF - rR) - forkoffset
    # rear-wheel centre -> B's mass centre is (xB, -zB - rR)
    framecg1 = -along_axis(p["xB"], -p["zB"] - rR)
    framecg3 = normal(p["xB"], -p["zB"] - rR)
    # Steer -> H's mass centre
    hx, hz = p["xH"] - framelength * cl, -p["zH"] - rR - framelength * sl
    forkcg1 = -along_axis(hx, hz)
    forkcg3 = normal(hx, hz)
    return {
        "WFrad": rF, "WRrad": rR, "htangle": math.pi / 2 - lam,
        "forkoffset": forkoffset, "forklength": forklength, "framelength": framelength,
        "forkcg1": forkcg1, "forkcg3": forkcg3, "framecg1": framecg1, "framecg3": framecg3,
        "Iwr11": p["IRxx"], "Iwr22": p["IRyy"], "Iwf11": p["IFxx"], "Iwf22": p["IFyy"],
        "Iframe11": p["IBxx"], "Iframe22": p["IByy"], "Iframe33": p["IBzz"],
        "Iframe31": -p["IBxz"],                       # (x, y, z) -> (x, -y, -z)
        "Ifork11": p["IHxx"], "Ifork22": p["IHyy"], "Ifork33": p["IHzz"],
        "Ifork31": -p["IHxz"],                        # (x, y, z) -> (x, -y, -z)
        "g": p["g"], "mframe": p["mB"], "mfork": p["mH"], "mwf": p["mF"], "mwr": p["mR"],
    }


def _kane(par: dict[str, sp.Expr]):
    """Kane's equations of the bicycle; ``par`` maps each model parameter name to a SymPy
    symbol or number.  Returns the ``KanesMethod`` (after ``kanes_equations``) and the
    operating point of upright straight-ahead rolling at speed ``V``."""
    WFrad, WRrad, htangle = par["WFrad"], par["WRrad"], par["htangle"]
    forkoffset, forklength, framelength = par["forkoffset"], par["forklength"], par["framelength"]
    forkcg1, forkcg3, framecg1, framecg3 = (par[k] for k in ("forkcg1", "forkcg3", "framecg1", "framecg3"))
    Iwr11, Iwr22, Iwf11, Iwf22 = (par[k] for k in ("Iwr11", "Iwr22", "Iwf11", "Iwf22"))
    Iframe11, Iframe22, Iframe33, Iframe31 = (par[k] for k in ("Iframe11", "Iframe22", "Iframe33", "Iframe31"))
    Ifork11, Ifork22, Ifork33, Ifork31 = (par[k] for k in ("Ifork11", "Ifork22", "Ifork33", "Ifork31"))
    g, mframe, mfork, mwf, mwr = (par[k] for k in ("g", "mframe", "mfork", "mwf", "mwr"))

    q1, q2, q4, q5 = dynamicsymbols("q1 q2 q4 q5")
    q1d, q2d, q4d, q5d = dynamicsymbols("q1 q2 q4 q5", 1)
    u1, u2, u3, u4, u5, u6 = dynamicsymbols("u1 u2 u3 u4 u5 u6")

    # Frames: N inertial (z up), Y yaw, R roll (lean), Frame rear frame (pitched so that
    # Frame.x lies along the steering axis, pointing down), Fork, wheels WR and WF (their
    # rotation angles are ignorable); the Temp frames carry the paper's inertia axes.
    N = ReferenceFrame("N")
    Y = N.orientnew("Y", "Axis", [q1, N.z])
    R = Y.orientnew("R", "Axis", [q2, Y.x])
    Frame = R.orientnew("Frame", "Axis", [q4 + htangle, R.y])
    WR = ReferenceFrame("WR")
    TempFrame = Frame.orientnew("TempFrame", "Axis", [-htangle, Frame.y])
    Fork = Frame.orientnew("Fork", "Axis", [q5, Frame.x])
    TempFork = Fork.orientnew("TempFork", "Axis", [-htangle, Fork.y])
    WF = ReferenceFrame("WF")

    # rear contact -> rear-wheel centre -> frame mass centre / steering axis point ->
    # fork mass centre / front-wheel centre -> front contact
    WR_cont = Point("WR_cont")
    WR_mc = WR_cont.locatenew("WR_mc", WRrad * R.z)
    Steer = WR_mc.locatenew("Steer", framelength * Frame.z)
    Frame_mc = WR_mc.locatenew("Frame_mc", -framecg1 * Frame.x + framecg3 * Frame.z)
    Fork_mc = Steer.locatenew("Fork_mc", -forkcg1 * Fork.x + forkcg3 * Fork.z)
    WF_mc = Steer.locatenew("WF_mc", forklength * Fork.x + forkoffset * Fork.z)
    WF_cont = WF_mc.locatenew(
        "WF_cont", WFrad * (dot(Fork.y, Y.z) * Fork.y - Y.z).normalize())

    Y.set_ang_vel(N, u1 * Y.z)
    R.set_ang_vel(Y, u2 * R.x)
    WR.set_ang_vel(Frame, u3 * Frame.y)
    Frame.set_ang_vel(R, u4 * Frame.y)
    Fork.set_ang_vel(Frame, u5 * Fork.x)
    WF.set_ang_vel(Fork, u6 * Fork.y)

    WR_cont.set_vel(N, 0)
    WR_mc.v2pt_theory(WR_cont, N, WR)
    Steer.v2pt_theory(WR_mc, N, Frame)
    Frame_mc.v2pt_theory(WR_mc, N, Frame)
    Fork_mc.v2pt_theory(Steer, N, Fork)
    WF_mc.v2pt_theory(Steer, N, Fork)
    WF_cont.v2pt_theory(WF_mc, N, WF)

    Frame_I = (inertia(TempFrame, Iframe11, Iframe22, Iframe33, 0, 0, Iframe31), Frame_mc)
    Fork_I = (inertia(TempFork, Ifork11, Ifork22, Ifork33, 0, 0, Ifork31), Fork_mc)
    WR_I = (inertia(Frame, Iwr11, Iwr22, Iwr11), WR_mc)
    WF_I = (inertia(Fork, Iwf11, Iwf22, Iwf11), WF_mc)
    bodies = [
        RigidBody("BodyFrame", Frame_mc, Frame, mframe, Frame_I),
        RigidBody("BodyFork", Fork_mc, Fork, mfork, Fork_I),
        RigidBody("BodyWR", WR_mc, WR, mwr, WR_I),
        RigidBody("BodyWF", WF_mc, WF, mwf, WF_I),
    ]
    loads = [
        (Frame_mc, -mframe * g * Y.z),
        (Fork_mc, -mfork * g * Y.z),
        (WF_mc, -mwf * g * Y.z),
        (WR_mc, -mwr * g * Y.z),
    ]

    kd = [q1d - u1, q2d - u2, q4d - u4, q5d - u5]
    # nonholonomic: the front contact point does not move (no slip, x and y; z keeps it on
    # the ground, the velocity form of the holonomic constraint below)
    conlist_speed = [WF_cont.vel(N) & Y.x, WF_cont.vel(N) & Y.y, WF_cont.vel(N) & Y.z]
    # holonomic: the front contact is on the ground (fixes the pitch q4); used by linearize
    conlist_coord = [WF_cont.pos_from(WR_cont) & Y.z]

    KM = KanesMethod(
        N, q_ind=[q1, q2, q5], q_dependent=[q4], configuration_constraints=conlist_coord,
        u_ind=[u2, u3, u5], u_dependent=[u1, u4, u6], velocity_constraints=conlist_speed,
        kd_eqs=kd, constraint_solver="CRAMER",
    )
    KM.kanes_equations(bodies, loads)

    rR, rF = par["WRrad"], par["WFrad"]
    op_point = {q1: 0, q2: 0, q4: 0, q5: 0,
                u1: 0, u2: 0, u3: V / rR, u4: 0, u5: 0, u6: V / rF}
    op_point.update({u.diff(): 0 for u in (u1, u2, u3, u4, u5, u6)})
    return KM, op_point


# The lean/steer block [q2, q5, u2, u5] = [phi, delta, phi_dot, delta_dot] of the 6x6 A of the
# independent states [q1, q2, q5, u2, u3, u5].
_LEAN_STEER = [1, 2, 3, 5]


def _derive(par: dict[str, sp.Expr]) -> sp.Matrix:
    """SymPy's own route: ``KanesMethod.linearize`` on the full nonlinear equations."""
    KM, op_point = _kane(par)
    A, _B, _r = KM.linearize(A_and_B=True, op_point=op_point, linear_solver="CRAMER")
    return A.extract(_LEAN_STEER, _LEAN_STEER)


def _first_order(exprs: sp.Matrix, x: list, x0: list) -> sp.Matrix:
    """The first-order Taylor polynomial about ``x0`` of each entry of ``exprs``.

    ``x`` lists the variables (time derivatives before the functions they differentiate,
    so that the top-down ``xreplace`` maps ``q'`` as a whole).  The partial derivative in
    ``x_j`` at ``x0`` is taken after every other variable has been set to its operating
    value, which collapses the huge nonlinear expressions (most operating values are 0);
    the variables are split in halves recursively so that each big expression is only
    rebuilt a few times.
    """
    dummies = [sp.Dummy(f"x{i}") for i in range(len(x))]
    at_op = dict(zip(dummies, x0, strict=True))
    back = {d: xi - xi0 for d, xi, xi0 in zip(dummies, x, x0, strict=True)}

    def gradient(expr: sp.Expr, idx: list[int]) -> list[sp.Expr]:
        if len(idx) == 1:
            d = dummies[idx[0]]
            return [expr.diff(d).xreplace({d: x0[idx[0]]})]
        half = len(idx) // 2
        lo, hi = idx[:half], idx[half:]
        e_lo = expr.xreplace({dummies[i]: x0[i] for i in hi})
        e_hi = expr.xreplace({dummies[i]: x0[i] for i in lo})
        return gradient(e_lo, lo) + gradient(e_hi, hi)

    out = []
    for expr in exprs:
        e = expr.xreplace(dict(zip(x, dummies, strict=True)))
        present = [i for i, d in enumerate(dummies) if e.has(d)]
        poly = e.xreplace(at_op)
        if present:
            poly += sum(g * back[dummies[i]] for i, g in zip(present, gradient(e, present), strict=True))
        out.append(sp.expand(poly))
    return sp.Matrix(exprs.rows, exprs.cols, out)


def _derive_fast(par: dict[str, sp.Expr]) -> sp.Matrix:
    """Same model and same SymPy ``Linearizer`` as :func:`_derive`, but the Linearizer is
    fed the first-order Taylor polynomials (about the operating point) of the equations
    that ``KanesMethod.to_linearizer`` hands it.  The Linearizer only ever uses first
    partial derivatives at the operating point (its M, A, C_0, C_1, C_2 blocks), so the
    result is the same matrix, obtained in a fraction of the time."""
    KM, op_point = _kane(par)
    lin = KM.to_linearizer(linear_solver="CRAMER")
    t = dynamicsymbols._t
    q, u = list(lin.q), list(lin.u)
    x = [qi.diff(t) for qi in q] + [ui.diff(t) for ui in u] + q + u
    # q' appears only in f_0 = K q' (linear), so its expansion point is immaterial; it is
    # the operating q' = 0 (q1', q2', q4', q5' = u1, u2, u4, u5 = 0).
    x0 = [op_point.get(xi, 0) for xi in x]
    reduced = {name: _first_order(getattr(lin, name), x, x0)
               for name in ("f_0", "f_1", "f_2", "f_3", "f_4", "f_c", "f_v", "f_a")}
    small = Linearizer(reduced["f_0"], reduced["f_1"], reduced["f_2"], reduced["f_3"],
                       reduced["f_4"], reduced["f_c"], reduced["f_v"], reduced["f_a"],
                       lin.q, lin.u, lin.q_i, lin.q_d, lin.u_i, lin.u_d, lin.r,
                       linear_solver="CRAMER")
    A, _B = small.linearize(op_point=op_point, A_and_B=True)
    return A.extract(_LEAN_STEER, _LEAN_STEER)


def derive_and_linearize(symbolic_parameters: bool = True) -> sp.Matrix:
    """Derive the bicycle with KanesMethod from scratch and linearize it (no cache).

    With ``symbolic_parameters`` (the default, what a SymPy user would write) every model
    parameter is a Symbol during derivation and linearization, and the numbers of the
    benchmark are substituted at the end; otherwise they are numbers from the start.
    Returns the 4x4 matrix A(v) for [phi, delta, phi_dot, delta_dot] (paper's signs).
    """
    values = _model_values()
    if symbolic_parameters:
        symbols = {name: sp.Symbol(name) for name in _MODEL_PARAMETERS}
        A = _derive(symbols)
        A = A.xreplace({symbols[k]: sp.Float(values[k], 30) for k in _MODEL_PARAMETERS})
    else:
        A = _derive({k: sp.Float(values[k]) for k in _MODEL_PARAMETERS})
    return A.evalf().applyfunc(lambda e: sp.expand(e))


@functools.cache
def _cached_numeric_A():
    """(A(v) as a SymPy Matrix, its numpy coefficients of v^0, v^1, v^2).

    Every parameter but ``v`` is a number from the start (SymPy Floats), and the
    Linearizer gets the first-order Taylor polynomials of the equations (``_derive_fast``).
    """
    values = _model_values()
    A = _derive_fast({k: sp.Float(values[k]) for k in _MODEL_PARAMETERS})
    A = A.evalf().applyfunc(sp.expand)
    coeffs = np.zeros((3, 4, 4))
    for i in range(4):
        for j in range(4):
            poly = sp.Poly(A[i, j], V)
            if poly.degree() > 2:
                raise AssertionError(f"A[{i},{j}] is not a quadratic in v: {A[i, j]}")
            for (k,), coeff in poly.terms():
                coeffs[k, i, j] = float(coeff)
    return A, coeffs


def linearized_A(v_values: Iterable[float]) -> list[np.ndarray]:
    """The 4x4 state matrices A(v) of the linearized upright straight-ahead motion, state
    [phi, delta, phi_dot, delta_dot] in the paper's sign convention, one per speed v."""
    _A, (c0, c1, c2) = _cached_numeric_A()
    return [c0 + float(v) * c1 + float(v) ** 2 * c2 for v in v_values]
