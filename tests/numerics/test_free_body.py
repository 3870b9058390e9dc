"""Free bodies integrated on unit quaternions (`numerics._free_simulate`): against Euler's equations in SciPy.

The T-handle of ``examples/tumbling_body.toml`` spins about its intermediate axis and flips
over every few seconds; its Euler angle θ swings between 0.002 rad and π − 0.002, next to the
two singularities of the course's z-x-z angles.  The reference is written here by hand: Euler's
equations A ω̇_x = (B − C) ω_y ω_z ... with ė = ½ e ⊗ (0, ω), integrated by SciPy's DOP853.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from scipy.integrate import solve_ivp

import lagrangian
from lagrangian.errors import ModelError, SimulationError

EXAMPLE = Path(__file__).resolve().parents[2] / "examples" / "tumbling_body.toml"
QUATERNION = ("S_ew", "S_ex", "S_ey", "S_ez")
OMEGA = ("S_omega_x", "S_omega_y", "S_omega_z")


def _euler_equations(moments: np.ndarray):  # type: ignore[no-untyped-def]
    """d/dt (ω, e) of a torque-free rigid body, ω in its principal axes (Euler's equations)."""
    A, B, C = moments

    def f(t: float, s: np.ndarray) -> np.ndarray:
        wx, wy, wz, ew, ex, ey, ez = s
        return np.array([(B - C) * wy * wz / A, (C - A) * wz * wx / B, (A - B) * wx * wy / C,
                         -0.5 * (ex * wx + ey * wy + ez * wz), 0.5 * (ew * wx + ey * wz - ez * wy),
                         0.5 * (ew * wy + ez * wx - ex * wz), 0.5 * (ew * wz + ex * wy - ey * wx)])
    return f


def _rotation(e: np.ndarray) -> np.ndarray:
    """R (body → R0) of unit quaternions (N, 4), written out."""
    w, x, y, z = (e / np.linalg.norm(e, axis=1)[:, None]).T
    return np.stack([np.stack([1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)], -1),
                     np.stack([2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)], -1),
                     np.stack([2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)], -1)], -2)


@pytest.fixture(scope="module")
def handle() -> lagrangian.Trajectory:
    return lagrangian.simulate(EXAMPLE, 100.0, rtol=1e-12, atol=1e-12, n_out=1001)


def test_the_handle_flips_through_the_euler_singularities_with_sigma_and_energy_kept(handle) -> None:
    theta = handle.column("theta")
    assert theta.min() < 0.0021 and theta.max() > np.pi - 0.0021  # next to both singularities
    flips = np.count_nonzero(np.diff(np.sign(np.cos(theta))))
    assert flips >= 20
    assert handle.warnings == ()
    moments = np.array([handle.parameters[k] for k in "ABC"])
    omega = np.column_stack([handle.extra[k] for k in OMEGA])
    R = _rotation(np.column_stack([handle.extra[k] for k in QUATERNION]))
    sigma = np.einsum("nij,nj->ni", R, moments * omega)  # σ_G = R Π_G ω, by hand
    assert np.allclose(sigma, np.column_stack([handle.column(f"sigma_G_{a}") for a in ("x0", "y0", "z0")]),
                       rtol=0, atol=1e-14)
    assert np.max(np.abs(sigma - sigma[0])) / np.linalg.norm(sigma[0]) < 1e-9
    rotation_energy = 0.5 * np.sum(moments * omega ** 2, axis=1)
    assert np.max(np.abs(rotation_energy / rotation_energy[0] - 1)) < 1e-9
    assert handle.drift["E"] < 1e-9 and all(handle.drift[f"sigma_G_{a}"] < 1e-9 for a in ("x0", "y0", "z0"))


@pytest.mark.slow
def test_the_motion_is_that_of_eulers_equations_integrated_by_scipy(handle) -> None:
    moments = np.array([handle.parameters[k] for k in "ABC"])
    start = np.concatenate([[handle.extra[k][0] for k in OMEGA], [handle.extra[k][0] for k in QUATERNION]])
    ref = solve_ivp(_euler_equations(moments), (0.0, 100.0), start, method="DOP853", rtol=1e-13, atol=1e-14,
                    t_eval=handle.t)
    assert ref.success
    R_ref = _rotation(ref.y[3:].T)
    R_ours = _rotation(np.column_stack([handle.extra[k] for k in QUATERNION]))
    assert np.max(np.abs(R_ours - R_ref)) < 1e-8
    omega = np.column_stack([handle.extra[k] for k in OMEGA])
    assert np.max(np.abs(omega - ref.y[:3].T)) / np.max(np.abs(omega)) < 1e-8
    # G falls on the parabola of its initial velocity (the rotation does not touch it)
    t, g = handle.t, handle.parameters["g"]
    assert np.allclose(handle.column("z"), 1.5 + 4.0 * t - 0.5 * g * t * t, rtol=1e-13, atol=1e-9)
    assert np.allclose(handle.column("x"), 0.5 * t, rtol=1e-13, atol=1e-12)


def test_the_angles_rates_and_accelerations_are_the_quaternions(handle) -> None:
    from lagrangian.numerics._euler import euler_matrix

    q = np.column_stack([handle.column(c) for c in ("psi", "theta", "phi")])
    R = _rotation(np.column_stack([handle.extra[k] for k in QUATERNION]))
    assert np.max(np.abs(euler_matrix("zxz", q) - R)) < 1e-12
    _, theta, phi = q.T
    dpsi, dtheta, dphi = (handle.column(c + "_dot") for c in ("psi", "theta", "phi"))
    omega_x = dpsi * np.sin(theta) * np.sin(phi) + dtheta * np.cos(phi)  # the course's Ω(R/R0) in R's basis
    omega_z = dphi + dpsi * np.cos(theta)
    assert np.allclose(omega_x, handle.extra["S_omega_x"], atol=1e-9)
    assert np.allclose(omega_z, handle.extra["S_omega_z"], atol=1e-9)
    # θ̈ from the course's Lagrange equations, at the output times (far enough from θ = 0 and π)
    regular = np.abs(np.sin(theta)) > 0.05
    lagrange = lagrangian.compile_system(lagrangian.derive(lagrangian.load_model(EXAMPLE)))
    p = lagrange.parameter_vector()
    Y = np.column_stack([handle.q, handle.qd])[regular]
    assert np.allclose(lagrange.rhs(0.0, Y, p)[:, 6:], handle.qdd[regular], rtol=1e-7, atol=1e-7)


def test_the_quaternions_norm_is_projected_and_its_drift_reported(handle) -> None:
    drift = handle.quaternion_drift["S"]
    assert 0 < drift < 1e-10
    norms = np.linalg.norm(np.column_stack([handle.extra[k] for k in QUATERNION]), axis=1)
    assert np.max(np.abs(norms - 1)) <= drift
    assert "quaternion norm drift S" in handle.drift_summary()
    # Without the projection (a SciPy method), the drift is that of the outputs, larger, and reported
    loose = lagrangian.simulate(EXAMPLE, 10.0, method="RK45", rtol=1e-6, atol=1e-6, n_out=101)
    assert loose.quaternion_drift["S"] > 100 * drift


def test_a_free_body_starts_at_the_singular_configuration_the_course_route_refuses() -> None:
    text = EXAMPLE.read_text()
    text = text.replace("theta = { initial = 0.0019999973333397333, rate = 0.0, unit = \"rad\" }",
                        "theta = { initial = 0.0, rate = 0.02, unit = \"rad\" }")
    text = text.replace("psi = { initial = 0.0, rate = 10.000019999980001", "psi = { initial = 0.0, rate = 0.0")
    text = text.replace("phi = { initial = 1.5707963267948966, rate = -5.000000000000002",
                        "phi = { initial = 0.0, rate = 5.0")
    free = lagrangian.parse_model(text)
    traj = lagrangian.simulate(free, 5.0, rtol=1e-12, atol=1e-12, n_out=11)
    assert traj.q[0, 4] == 0.0 and np.isnan(traj.qd[0, 3])  # θ = 0: ψ̇ and φ̇ undefined there, said so
    assert any("singular at 1 output time(s), first t = 0" in w for w in traj.warnings)
    omega = np.column_stack([traj.extra[k] for k in OMEGA])
    assert np.allclose(omega[0], [0.02, 0.0, 5.0], atol=1e-15)
    assert np.isfinite(traj.qd[1:]).all()
    with pytest.raises(SimulationError, match="singular"):  # the course's coordinates cannot start there
        lagrangian.simulate(lagrangian.parse_model(text.replace("free = true\n", "")), 5.0)


def test_away_from_the_singularity_the_two_routes_agree() -> None:
    text = EXAMPLE.read_text().replace("0.0019999973333397333", "0.6")
    fixed = lagrangian.parse_model(text.replace("free = true\n", ""))
    quaternion = lagrangian.simulate(lagrangian.parse_model(text), 1.0, rtol=1e-12, atol=1e-12, n_out=21)
    course = lagrangian.simulate(fixed, 1.0, rtol=1e-12, atol=1e-12, n_out=21)
    assert np.allclose(quaternion.q, course.q, atol=1e-9)
    assert np.allclose(quaternion.qd, course.qd, atol=1e-8)
    assert np.allclose(quaternion.qdd, course.qdd, atol=1e-7)


def test_events_on_positions_work_and_on_euler_angles_are_refused() -> None:
    model = lagrangian.load_model(EXAMPLE)
    traj = lagrangian.simulate(model, 2.0, events=[lagrangian.EventSpec("ground", "z", terminal=True)])
    g = 9.81
    landing = (4.0 + np.sqrt(16.0 + 2 * g * 1.5)) / g  # z = 1.5 + 4 t − g t²/2 = 0
    assert traj.status == "stopped by a terminal event" and abs(traj.events[0].t - landing) < 1e-9
    assert abs(traj.events[0].q[2]) < 1e-9
    with pytest.raises(SimulationError, match="an Euler angle"):
        lagrangian.simulate(model, 1.0, events=["theta - 1"])
    with pytest.raises(SimulationError, match="gauss-legendre"):
        lagrangian.simulate(model, 1.0, method="gauss-legendre")


def test_a_load_the_quaternion_route_cannot_take_is_refused() -> None:
    text = EXAMPLE.read_text() + 'push = { force = "0.1*R.x", at = "S" }\n'
    with pytest.raises(lagrangian.DerivationError, match="load `push` acts on a free body"):
        lagrangian.simulate(lagrangian.parse_model(text), 1.0)


def test_couples_on_a_free_body_in_its_frame_and_in_r0() -> None:
    # Couples Γ0 z0 (fixed in R0) and Γ1 x (turning with the handle): Euler's equations with the couple
    # in the body's basis, Rᵀ Γ0 z0 + Γ1 x, written by hand.
    text = EXAMPLE.read_text() + ('spin = { torque = "0.001*R0.z", on = "S" }\n'
                                  'kick = { torque = "0.0005*R.x", on = "S" }\n')
    traj = lagrangian.simulate(lagrangian.parse_model(text), 2.0, rtol=1e-12, atol=1e-12, n_out=21)
    assert "sigma_G_z0" not in traj.integrals and "E" not in traj.integrals  # external couples
    moments = np.array([0.002, 0.006, 0.004])
    free = _euler_equations(moments)

    def forced(t: float, s: np.ndarray) -> np.ndarray:
        out = free(t, s)
        R = _rotation(s[None, 3:])[0]
        out[:3] += (R.T @ [0.0, 0.0, 0.001] + [0.0005, 0.0, 0.0]) / moments
        return out

    start = np.concatenate([[traj.extra[k][0] for k in OMEGA], [traj.extra[k][0] for k in QUATERNION]])
    ref = solve_ivp(forced, (0.0, 2.0), start, method="DOP853", rtol=1e-13, atol=1e-14, t_eval=traj.t)
    omega = np.column_stack([traj.extra[k] for k in OMEGA])
    assert np.max(np.abs(omega - ref.y[:3].T)) < 1e-9
    R = _rotation(np.column_stack([traj.extra[k] for k in QUATERNION]))
    assert np.max(np.abs(R - _rotation(ref.y[3:].T))) < 1e-10


def test_a_free_body_with_a_zero_inertia_is_refused_in_the_file() -> None:
    text = EXAMPLE.read_text().replace('diagonal = ["A", "B", "C"]', 'diagonal = ["A", "B", "0"]')
    with pytest.raises(ModelError, match="free") as info:
        lagrangian.parse_model(text, source="handle.toml")
    assert info.value.line is not None


def test_ensembles_refuse_a_free_body_rather_than_meet_its_singularity() -> None:
    with pytest.raises(SimulationError, match="unit quaternion"):
        lagrangian.ensemble(EXAMPLE, 1.0, initial=lagrangian.grid(x=np.linspace(0.0, 1.0, 2)))


_PARAMETERS = "[parameters]\nm = 0.25\nA = 0.002\nB = 0.006\nC = 0.004\ng = 9.81\n"
_S = ("""x = { initial = 0.0, rate = 0.5 }
y = { initial = 0.0, rate = 0.0 }
z = { initial = 1.5, rate = 4.0 }
psi = { initial = 0.0, rate = 10.000019999980001 }
theta = { initial = 0.4, rate = 0.0 }
phi = { initial = 1.5707963267948966, rate = -5.000000000000002 }
""", 'R = { from = "R0", rotation = [["psi", "z"], ["theta", "x"], ["phi", "z"]] }\n', """[bodies.S]
frame = "R"
free = true
mass = "m"
center = "x*R0.x + y*R0.y + z*R0.z"
inertia = { frame = "R", diagonal = ["A", "B", "C"] }
""")
_T = ("""x2 = { initial = 1.0, rate = -1.0 }
y2 = { initial = 0.0, rate = 0.0 }
z2 = { initial = 0.0, rate = 2.0 }
psi2 = { initial = 0.3, rate = 1.0 }
theta2 = { initial = 1.0, rate = 2.0 }
phi2 = { initial = 0.0, rate = 3.0 }
""", 'R2 = { from = "R0", rotation = [["psi2", "z"], ["theta2", "y"], ["phi2", "x"]] }\n', """[bodies.T]
frame = "R2"
free = true
mass = "2*m"
center = "x2*R0.x + y2*R0.y + z2*R0.z + 0.1*R2.x"
inertia = { frame = "R2", diagonal = ["B", "C", "A"] }
""")


def _model(*parts: tuple[str, str, str]) -> str:
    return (_PARAMETERS + "[coordinates]\n" + "".join(c for c, _, _ in parts) + "[frames]\n"
            + "".join(f for _, f, _ in parts) + "".join(b for _, _, b in parts)
            + '[loads]\nweight = { gravity = "-g*R0.z" }\n')


def test_two_free_bodies_move_each_as_if_alone() -> None:
    # Two bodies in one model: each its own quaternion, its own σ_G (named after it), its own drift;
    # the second has Cardan angles and G off its frame's origin.
    both = lagrangian.simulate(lagrangian.parse_model(_model(_S, _T)), 3.0, rtol=1e-12, atol=1e-12, n_out=7)
    assert {"sigma_G_S_z0", "sigma_G_T_z0"} <= set(both.integrals) and set(both.quaternion_drift) == {"S", "T"}
    assert max(both.drift.values()) < 1e-9
    alone = lagrangian.simulate(lagrangian.load_model(EXAMPLE), 3.0, initial={"theta": 0.4}, rtol=1e-12,
                                atol=1e-12, n_out=7)
    assert np.allclose(both.q[:, :6], alone.q, atol=1e-9)
    assert np.allclose(both.extra["S_omega_z"], alone.extra["S_omega_z"], atol=1e-9)
    # T alone, integrated in its own coordinates (regular along this short motion)
    course = lagrangian.simulate(lagrangian.parse_model(_model(_T).replace("free = true\n", "")), 3.0, rtol=1e-12,
                                 atol=1e-12, n_out=7)
    assert np.allclose(both.q[:, 6:], course.q, atol=1e-8)
