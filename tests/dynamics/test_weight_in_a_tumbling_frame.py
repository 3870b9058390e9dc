"""The weight seen from a tumbling frame derives from a time-dependent potential (`dynamics._forces`).

A uniform field g fixed in R0, seen from a frame R turned by b·t about x0, has components
in R that depend on t: the weight's Q_i = m g·∂O'G/∂q_i are those of U = −m g·O'G(q, t), a
potential that depends on t.  The truth is the same motion derived in R0, where the weight's
potential −m g·OG has the same value (O' = O).
"""

from __future__ import annotations

import numpy as np
import symengine as se

import lagrangian
from lagrangian._identity import is_zero
from lagrangian.analysis import energy_balance

#: A spherical pendulum hung at O from a frame R that tumbles about x0 at the rate b.
TUMBLING = """
[parameters]
m = 1.2
l = 0.7
g = 9.81
b = 0.8

[coordinates]
th = { initial = 0.3, rate = 0.1 }
ph = { initial = -0.2, rate = 0.5 }

[frames]
R = { from = "R0", rotation = ["b*t", "x"] }
S1 = { from = "R", rotation = ["th", "y"] }
S = { from = "S1", rotation = ["ph", "x"] }

[particles.P]
mass = "m"
position = "-l*S.z"

[loads]
weight = { gravity = "-g*R0.z" }
"""
IN_R = '\n[reference]\nframe = "R"\n'


def derive(text: str) -> lagrangian.EquationsOfMotion:
    return lagrangian.derive(lagrangian.parse_model(text))


def test_the_weight_has_a_time_dependent_potential_in_the_tumbling_frame() -> None:
    relative, galilean = derive(TUMBLING + IN_R), derive(TUMBLING)
    weight = next(f for f in relative.loads if f.name == "weight")
    assert weight.potential is not None  # not "non-conservative"
    assert relative.kinematics.t in weight.potential.free_symbols  # U(q, t)
    reference = next(f for f in galilean.loads if f.name == "weight")
    assert is_zero(weight.potential - reference.potential)  # −m g·OG, the same function of (q, t)
    # Ω(R/R0) = b x0 is constant: entrainment is conservative too; only Coriolis has no potential.
    assert [f.name for f in relative.loads if f.potential is None] == ["Coriolis"]
    # The explicit time of the weight's potential is what the energy balance reports.
    kinds = {t.kind for t in energy_balance(relative).terms}
    assert "explicit time" in kinds


def test_the_tumbling_frame_gives_the_motion_derived_in_R0() -> None:
    relative, galilean = derive(TUMBLING + IN_R), derive(TUMBLING)
    values = {se.Symbol(p.name): p.value for p in relative.model.parameters}
    exprs = [se.sympify(x).subs(values) for eom in (relative, galilean)
             for x in (*(x for row in eom.M for x in row), *eom.F)]
    f = se.Lambdify([*relative.q, *relative.qd, relative.t], exprs, real=True)
    rng = np.random.default_rng(5)
    for _ in range(5):
        v = np.asarray(f(list(rng.uniform(-1.5, 1.5, 5))), dtype=float).ravel()
        ours = np.linalg.solve(v[:4].reshape(2, 2), v[4:6])
        theirs = np.linalg.solve(v[6:10].reshape(2, 2), v[10:12])
        assert np.allclose(ours, theirs, rtol=1e-10, atol=1e-10 * np.max(np.abs(theirs))), (ours, theirs)
