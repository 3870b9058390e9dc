"""The linearized Whipple bicycle as published: Meijaard, Papadopoulos, Ruina & Schwab (2007).

"Linearized dynamics equations for the balance and steer of a bicycle: a benchmark and review",
Proc. R. Soc. A 463, 1955–1982.  Its Appendix A gives M, C1, K0 and K2 of

    M q̈ + v C1 q̇ + (g K0 + v² K2) q = f,      q = (φ, δ)   (lean, steer; eq. (A 1))

in closed form from the parameters of its Table 1, and prints their values for the benchmark
bicycle (eq. (A 20)ff.); Table 2 gives the speeds where the motion changes character.  Nothing
here comes from `lagrangian`: it is the reference the engine is held against.
"""

from __future__ import annotations

import math

import numpy as np

#: Table 1 of the paper (SI units), under the names of examples/whipple_bicycle.toml.
PARAMETERS = dict(
    w=1.02, c=0.08, lam=math.pi / 10, g=9.81,
    rR=0.3, mR=2.0, IRxx=0.0603, IRyy=0.12,
    xB=0.3, zB=-0.9, mB=85.0, IBxx=9.2, IByy=11.0, IBzz=2.8, IBxz=2.4,
    xH=0.9, zH=-0.7, mH=4.0, IHxx=0.05892, IHyy=0.06, IHzz=0.00708, IHxz=-0.00756,
    rF=0.35, mF=3.0, IFxx=0.1405, IFyy=0.28,
)

#: The matrices as printed in the paper (eq. (A 20)–(A 23)), to check the closed forms below.
PUBLISHED = dict(
    M=np.array([[80.81722, 2.31941332208709], [2.31941332208709, 0.29784188199686]]),
    C1=np.array([[0.0, 33.86641391492494], [-0.85035641456978, 1.68540397397560]]),
    K0=np.array([[-80.95, -2.59951685249872], [-2.59951685249872, -0.80329488458618]]),
    K2=np.array([[0.0, 76.59734589573222], [0.0, 2.65431523794604]]),
)

#: Table 2: where the weave eigenvalues meet on the real axis (and leave it), the weave speed
#: (a Hopf bifurcation: the oscillation becomes stable) and the capsize speed (the real
#: capsize eigenvalue crosses zero).  The last two are given to 10 digits.
V_WEAVE_REAL = 0.684283
V_WEAVE = 4.292382536
V_CAPSIZE = 6.024262015


def matrices(p: dict | None = None) -> dict[str, np.ndarray]:
    """M, C1, K0, K2 from the closed forms of the paper's Appendix A (eq. (A 3)–(A 19))."""
    p = dict(PARAMETERS if p is None else p)
    w, c, lam = p["w"], p["c"], p["lam"]
    rR, mR, IRxx, IRyy = p["rR"], p["mR"], p["IRxx"], p["IRyy"]
    xB, zB, mB = p["xB"], p["zB"], p["mB"]
    xH, zH, mH = p["xH"], p["zH"], p["mH"]
    rF, mF, IFxx, IFyy = p["rF"], p["mF"], p["IFxx"], p["IFyy"]
    IRzz, IFzz = IRxx, IFxx            # the wheels are symmetric about their planes
    sl, cl = math.sin(lam), math.cos(lam)
    # The whole bicycle: total mass, centre of mass, inertia about the rear contact point.
    mT = mR + mB + mH + mF
    xT = (xB * mB + xH * mH + w * mF) / mT
    zT = (-rR * mR + zB * mB + zH * mH - rF * mF) / mT
    ITxx = IRxx + p["IBxx"] + p["IHxx"] + IFxx + mR * rR**2 + mB * zB**2 + mH * zH**2 + mF * rF**2
    ITxz = p["IBxz"] + p["IHxz"] - mB * xB * zB - mH * xH * zH + mF * w * rF
    ITzz = IRzz + p["IBzz"] + p["IHzz"] + IFzz + mB * xB**2 + mH * xH**2 + mF * w**2
    # The front assembly A (front frame and wheel), and its inertia about the steer axis.
    mA = mH + mF
    xA = (xH * mH + w * mF) / mA
    zA = (zH * mH - rF * mF) / mA
    IAxx = p["IHxx"] + IFxx + mH * (zH - zA) ** 2 + mF * (rF + zA) ** 2
    IAxz = p["IHxz"] - mH * (xH - xA) * (zH - zA) + mF * (w - xA) * (rF + zA)
    IAzz = p["IHzz"] + IFzz + mH * (xH - xA) ** 2 + mF * (w - xA) ** 2
    uA = (xA - w - c) * cl - zA * sl
    IAll = mA * uA**2 + IAxx * sl**2 + 2 * IAxz * sl * cl + IAzz * cl**2
    IAlx = -mA * uA * zA + IAxx * sl + IAxz * cl
    IAlz = mA * uA * xA + IAxz * sl + IAzz * cl
    mu = c * cl / w
    SR, SF = IRyy / rR, IFyy / rF
    ST = SR + SF
    SA = mA * uA + mu * mT * xT
    M = np.array([[ITxx, IAlx + mu * ITxz], [IAlx + mu * ITxz, IAll + 2 * mu * IAlz + mu**2 * ITzz]])
    K0 = np.array([[mT * zT, -SA], [-SA, -SA * sl]])
    K2 = np.array([[0.0, (ST - mT * zT) * cl / w], [0.0, (SA + SF * sl) * cl / w]])
    C1 = np.array([[0.0, mu * ST + SF * cl + ITxz * cl / w - mu * mT * zT],
                   [-(mu * ST + SF * cl), IAlz * cl / w + mu * (SA + ITzz * cl / w)]])
    return {"M": M, "C1": C1, "K0": K0, "K2": K2}


def state_matrix(v: float, p: dict | None = None) -> np.ndarray:
    """A of ẋ = A x for x = (φ, δ, φ̇, δ̇): [[0, I], [−M⁻¹(g K0 + v² K2), −M⁻¹ v C1]]."""
    m = matrices(p)
    g = (PARAMETERS if p is None else p)["g"]
    Minv = np.linalg.inv(m["M"])
    return np.block([[np.zeros((2, 2)), np.eye(2)],
                     [-Minv @ (g * m["K0"] + v**2 * m["K2"]), -Minv @ (v * m["C1"])]])
