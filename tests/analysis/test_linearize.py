"""Linearization about equilibria and steady motions, against closed forms, SymPy's Linearizer and
finite differences of the compiled right-hand side."""

from __future__ import annotations

import math
import subprocess
import sys

import numpy as np
import pytest
import symengine as se
import sympy as sp
import sympy.physics.mechanics as me
from lagrangian_test_support import EXAMPLES_DIR

import lagrangian
from lagrangian import LinearizationError, linearize
from lagrangian.analysis import eigenvalue_sweep
from lagrangian.model import parse_model
from lagrangian.model.zoo import planar_chain


def _eom(name: str) -> lagrangian.EquationsOfMotion:
    return lagrangian.derive(lagrangian.load_model(EXAMPLES_DIR / f"{name}.toml"))


def _num(m: se.DenseMatrix) -> np.ndarray:
    return np.array(m.tolist(), dtype=float)


# -- closed forms -----------------------------------------------------------------------------

def test_simple_pendulum_bottom_and_top():
    eom = _eom("simple_pendulum")
    m, l, g = 1.0, 0.5, 9.81
    down = linearize(eom, {"theta": 0})
    assert down.state == ("theta", "theta_dot")
    np.testing.assert_allclose(down.numeric()[0], [[0, 1], [-g / l, 0]], rtol=1e-14)
    np.testing.assert_allclose(_num(down.second_order.M), [[m * l**2]], rtol=1e-14)
    np.testing.assert_allclose(_num(down.second_order.K), [[m * g * l]], rtol=1e-14)
    assert down.modes().pulsations == pytest.approx([math.sqrt(g / l)], rel=1e-13)
    st = down.stability()
    assert st.stable is True and "Lagrange–Dirichlet" in st.reason
    up = linearize(eom, {"theta": "pi"})
    np.testing.assert_allclose(sorted(up.eigenvalues().real), [-math.sqrt(g / l), math.sqrt(g / l)], rtol=1e-13)
    assert up.stability().stable is False
    near = linearize(eom, {"theta": 3.14159})  # the issue's `--at theta=3.14159`: within POINT_RTOL
    assert 0 < near.residual < 1e-5 and near.stability().stable is False


_PRINT_WITHOUT_INPUTS = """
import pickle, sys
import symengine as se
import lagrangian
eom = lagrangian.derive(lagrangian.load_model(sys.argv[1]))
lin = lagrangian.linearize(eom, {"theta": 0})
assert lin.inputs == () and lin.B.shape == (2, 0) and lin.second_order.B.shape == (1, 0)
assert str(lin.B) == repr(lin.B) == "[]\\n[]\\n", repr(str(lin.B))
assert ", B=[]\\n[]\\n, " in repr(lin) and "B=[]\\n)" in repr(lin.second_order)
assert str(lin) == repr(lin)
copy = pickle.loads(pickle.dumps(lin.B))
assert copy.shape == (2, 0) and copy == se.zeros(2, 0) and str(copy) == str(lin.B)
assert (lin.B.T * lin.A).shape == (0, 2)
print("printed")
"""


def test_model_without_inputs_prints_its_empty_input_matrix():
    """B is n × 0 without inputs; SymEngine's printer crashes (segmentation fault) on such a matrix,
    so the check runs in a child process, where a crash is a failed exit code, not a lost test run."""
    done = subprocess.run([sys.executable, "-c", _PRINT_WITHOUT_INPUTS, str(EXAMPLES_DIR / "simple_pendulum.toml")],
                          check=False, capture_output=True, text=True, timeout=120)
    assert done.returncode == 0 and done.stdout.strip() == "printed", (done.returncode, done.stderr[-2000:])


def test_double_pendulum_point_masses_symbolic_and_the_two_pulsations():
    eom = lagrangian.derive(planar_chain(2))
    lin = linearize(eom, {"theta1": 0, "theta2": 0}, symbolic=("g", "m1", "m2", "l1", "l2"))
    m1, m2, l1, l2, g = se.symbols("m1 m2 l1 l2 g")
    M, K = lin.second_order.M, lin.second_order.K
    expected_M = [[(m1 + m2) * l1**2, m2 * l1 * l2], [m2 * l1 * l2, m2 * l2**2]]
    expected_K = [[(m1 + m2) * g * l1, 0], [0, m2 * g * l2]]
    for i in range(2):
        for j in range(2):
            assert se.expand(M[i, j] - expected_M[i][j]) == 0
            assert se.expand(K[i, j] - expected_K[i][j]) == 0
    assert set(map(str, lin.symbols)) == {"g", "m1", "m2", "l1", "l2"}
    w = lin.modes(g=9.81, m1=2.0, m2=2.0, l1=0.7, l2=0.7).pulsations
    assert np.square(w) == pytest.approx([(2 - math.sqrt(2)) * 9.81 / 0.7, (2 + math.sqrt(2)) * 9.81 / 0.7], rel=1e-12)


def test_bead_on_rotating_hoop_pitchfork():
    eom = _eom("bead_rotating_hoop")
    m, R, g = 0.1, 0.5, 9.81
    lin = linearize(eom, {"theta": 0}, symbolic=("Omega",))
    Om = se.Symbol("Omega")
    assert se.expand(lin.second_order.K[0, 0] - m * R**2 * (g / R - Om**2)) == 0 or \
        abs(float((lin.second_order.K[0, 0] - m * R**2 * (g / R - Om**2)).subs({Om: 1.3}))) < 1e-12
    crit = math.sqrt(g / R)
    assert lin.stability(Omega=0.9 * crit).stable is True
    assert lin.stability(Omega=1.1 * crit).stable is False
    # The off-axis branch cosθ0 = g/(RΩ²): stable, ω² = Ω² sin²θ0.
    Omega = 6.0
    theta0 = math.acos(g / (R * Omega**2))
    off = linearize(eom, {"theta": theta0})
    assert off.stability().stable is True
    assert off.modes().pulsations[0] ** 2 == pytest.approx(Omega**2 * math.sin(theta0) ** 2, rel=1e-10)
    # The sweep finds the pitchfork at Ω² = g/R.
    sw = lagrangian.sweep(lin, "Omega", np.linspace(1.0, 8.0, 71))
    lost = [c for c in sw.changes if c.kind == "stability lost"]
    assert len(lost) == 1 and lost[0].value == pytest.approx(crit, rel=1e-10)
    # `lagrangian.sweep` (numerics) hands a linearization to the analysis' own sweep, which takes nothing else.
    again = eigenvalue_sweep(lin, "Omega", np.linspace(1.0, 8.0, 71))
    assert [(c.value, c.kind) for c in again.changes] == [(c.value, c.kind) for c in sw.changes]
    with pytest.raises(LinearizationError, match="takes a linearization"):
        eigenvalue_sweep(eom, "Omega", [1.0])  # type: ignore[arg-type]


def test_constraint_reduction_cartesian_pendulum():
    """x, y with x² + y² = l² kept complementary: one independent coordinate, ω² = g/l (y eliminated)."""
    eom = _eom("pendulum_tension")
    lin = linearize(eom, {"x": 0, "y": "-l"})
    assert lin.dependent_coordinates == ("y",) and lin.coordinates == ("x",)
    assert lin.dependent_speeds == ("y_dot",) and lin.speeds == ("x_dot",)
    assert lin.modes().pulsations[0] ** 2 == pytest.approx(9.81 / 0.5, rel=1e-13)
    assert lin.multipliers  # λ0 carries the weight: the rod's tension m g = −2 l λ
    lam = float(next(iter(lin.multipliers.values())))
    assert -2 * 0.5 * lam == pytest.approx(1.0 * 9.81, rel=1e-13)


def test_rolling_coin_straight_rolling_reduction():
    eom = _eom("rolling_coin")
    lin = linearize(eom, {"x": 0, "y": 0, "psi": 0, "phi": 0, "phi_dot": 10.0})
    assert set(lin.dependent_speeds) == {"x_dot", "y_dot"}
    assert float(lin.point["x_dot"]) == pytest.approx(1.0)  # r φ̇: solved from the rolling rows
    assert set(lin.ignorable) >= {"x", "y", "phi"}


# -- peers: SymPy's Linearizer, finite differences of the compiled right-hand side ------------

def _sympy_double_pendulum():
    m1, m2, l1, l2, g = sp.symbols("m1 m2 l1 l2 g")
    q1, q2 = me.dynamicsymbols("q1 q2")
    N = me.ReferenceFrame("N")
    O = me.Point("O")
    O.set_vel(N, 0)
    P1 = O.locatenew("P1", l1 * (sp.cos(q1) * N.x + sp.sin(q1) * N.y))
    P2 = P1.locatenew("P2", l2 * (sp.cos(q2) * N.x + sp.sin(q2) * N.y))
    for P in (P1, P2):
        P.set_vel(N, P.pos_from(O).dt(N))
    L = me.Lagrangian(N, me.Particle("a", P1, m1), me.Particle("b", P2, m2))
    L += m1 * g * P1.pos_from(O).dot(N.x) + m2 * g * P2.pos_from(O).dot(N.x)  # x down
    lm = me.LagrangesMethod(L, [q1, q2])
    lm.form_lagranges_equations()
    return lm, (q1, q2), (m1, m2, l1, l2, g)


@pytest.mark.slow
@pytest.mark.parametrize("point", [(0.0, 0.0), (math.pi, 0.0), (0.0, math.pi), (math.pi, math.pi)])
def test_double_pendulum_against_sympy_linearizer(point):
    lm, (q1, q2), (m1, m2, l1, l2, g) = _sympy_double_pendulum()
    values = {m1: 1.3, m2: 0.7, l1: 0.9, l2: 0.4, g: 9.81}
    exact = {0.0: sp.S.Zero, math.pi: sp.pi}  # SymPy's Linearizer wants exact operating points
    op = {q1: exact[point[0]], q2: exact[point[1]], q1.diff(): 0, q2.diff(): 0}
    A_sp = lm.linearize(q_ind=[q1, q2], qd_ind=[q1.diff(), q2.diff()], op_point=op, A_and_B=True)[0]
    A_sp = np.array(A_sp.subs(values).evalf(), dtype=float)
    eom = lagrangian.derive(planar_chain(2))
    lin = linearize(eom, {"theta1": point[0], "theta2": point[1]},
                    parameters={"m1": 1.3, "m2": 0.7, "l1": 0.9, "l2": 0.4, "g": 9.81})
    np.testing.assert_allclose(lin.numeric()[0], A_sp, rtol=1e-11, atol=1e-11)


@pytest.mark.parametrize("n, seed", [(3, 1), (4, 2)])
def test_chain_A_against_finite_differences_of_compiled_rhs(n, seed):
    rng = np.random.default_rng(seed)
    angles = rng.choice([0.0, math.pi], size=n)
    eom = lagrangian.derive(planar_chain(n))
    lin = linearize(eom, {f"theta{k + 1}": angles[k] for k in range(n)})
    A = lin.numeric()[0]
    system = lagrangian.compile_system(eom)
    p = system.parameter_vector()
    y0 = np.concatenate([angles, np.zeros(n)])
    h = 1e-6
    fd = np.empty((2 * n, 2 * n))
    for j in range(2 * n):
        e = np.zeros(2 * n)
        e[j] = h
        fd[:, j] = (system.rhs(0.0, y0 + e, p) - system.rhs(0.0, y0 - e, p)) / (2 * h)
    np.testing.assert_allclose(A, fd, rtol=1e-6, atol=1e-6 * np.abs(A).max())


def test_cart_pendulum_against_finite_differences():
    eom = _eom("cart_pendulum")
    lin = linearize(eom, {c: 0 for c in eom.coordinates})
    system = lagrangian.compile_system(eom)
    p = system.parameter_vector()
    n = len(eom.coordinates)
    y0 = np.zeros(2 * n)
    h = 1e-6
    fd = np.column_stack([(system.rhs(0.0, y0 + h * e, p) - system.rhs(0.0, y0 - h * e, p)) / (2 * h)
                          for e in np.eye(2 * n)])
    np.testing.assert_allclose(lin.numeric()[0], fd, rtol=1e-6, atol=1e-7)


# -- inputs, control ---------------------------------------------------------------------------



def test_inverted_cart_pendulum_unstable_and_controllable():
    eom = _eom("inverted_pendulum_cart")
    lin = linearize(eom)  # the model's [operating_point] (upright) and its declared input F
    assert lin.inputs == ("F",) and lin.point["theta"] == 0
    A, B = lin.numeric()
    M, m, l, g = 1.0, 0.2, 0.6, 9.81
    lam = np.sort(lin.eigenvalues().real)
    unstable = math.sqrt((M + m) * g / (M * l))  # θ̈ = (mc + m) g θ/(mc l) − F/(mc l), x free
    assert lam[-1] == pytest.approx(unstable, rel=1e-12)
    st = lin.stability()
    assert st.stable is False
    ctrb = np.hstack([np.linalg.matrix_power(A, k) @ B for k in range(4)])
    assert np.linalg.matrix_rank(ctrb) == 4
    # B: ẍ = F/mc, θ̈ = −F/(mc l) (θ measured from the upward vertical, towards +x).
    i_xd, i_td = lin.state.index("x_dot"), lin.state.index("theta_dot")
    assert B[i_xd, 0] == pytest.approx(1 / M) and abs(B[i_td, 0]) == pytest.approx(1 / (M * l))
    sys_scipy = lin.to_scipy()
    np.testing.assert_allclose(sys_scipy.A, A)


def test_to_control_names_states_and_inputs():
    control = pytest.importorskip("control")
    sys = linearize(_eom("inverted_pendulum_cart")).to_control()
    assert isinstance(sys, control.StateSpace)
    assert list(sys.state_labels) == ["x", "theta", "x_dot", "theta_dot"] and list(sys.input_labels) == ["F"]


# -- bad input -----------------------------------------------------------------------------------

def test_errors_name_the_problem_and_the_fix():
    eom = _eom("double_pendulum")
    with pytest.raises(LinearizationError, match="`theta2`.*no value") as e:
        linearize(eom, {"theta1": 0})
    assert "--at theta2=0" in e.value.fix
    with pytest.raises(LinearizationError, match="`phi` is neither a coordinate"):
        linearize(eom, {"theta1": 0, "theta2": 0, "phi": 1})
    with pytest.raises(LinearizationError, match="not an equilibrium.*nearest equilibrium found"):
        linearize(eom, {"theta1": 0.3, "theta2": 0})
    with pytest.raises(LinearizationError, match="`k` is not a parameter"):
        linearize(eom, {"theta1": 0, "theta2": 0}, symbolic=("k",))
    with pytest.raises(LinearizationError, match="depend on the time"):
        kap = _eom("kapitza_pendulum")
        linearize(kap, {c: 0 for c in kap.coordinates})
    top = _eom("lagrange_top")
    with pytest.raises(LinearizationError, match="mass matrix M is singular"):
        linearize(top, {"psi": 0, "theta": 0, "phi": 0})
    cart = _eom("inverted_pendulum_cart")
    with pytest.raises(LinearizationError, match="no load uses the input `mc`"):
        linearize(cart, inputs=("mc",))


def test_moving_coordinate_that_the_equations_hold_is_refused():
    eom = _eom("simple_pendulum")
    with pytest.raises(LinearizationError, match="moves at the point"):
        linearize(eom, {"theta": 0, "theta_dot": 1.0})


# -- steady motion: the top ------------------------------------------------------------------------

def test_top_steady_precession_pulsation_matches_closed_form():
    """Steady precession at θ0: ω_nut² = [(C ω3)² − 4 A C ω3 ψ̇ cosθ0 + 4 A² ψ̇² cos²θ0 ... ] — written in the
    form ω² = (A ψ̇ cosθ0 − C ω3)²/A² + ψ̇² sin²θ0 ... checked instead through a, U_eff'' below."""
    eom = _eom("lagrange_top")
    vals = {p.name: p.value for p in eom.model.parameters}
    A, C, m, g, a = (vals[k] for k in ("A", "C", "m", "g", "a"))
    theta0, psid = 0.5, 2.0
    # m g a = ψ̇ (C ω3 − A ψ̇ cosθ0): ω3 from the steady-precession relation, then φ̇ = ω3 − ψ̇ cosθ0.
    omega3 = (m * g * a / psid + A * psid * math.cos(theta0)) / C
    phid = omega3 - psid * math.cos(theta0)
    lin = linearize(eom, {"psi": 0, "theta": theta0, "phi": 0, "psi_dot": psid, "phi_dot": phid})
    assert set(lin.ignorable) == {"psi", "phi"}
    # Closed form (Goldstein §5.7; Routh): at fixed K, H the nutation pulsation is
    # ω² = [ (C ω3 − 2 A ψ̇ cosθ0)² + (A ψ̇² ... ) ] — computed here from U_eff'' / A independently:
    K = A * psid * math.sin(theta0) ** 2 + C * omega3 * math.cos(theta0)
    H = C * omega3

    def ueff(th):
        return (K - H * math.cos(th)) ** 2 / (2 * A * math.sin(th) ** 2) + m * g * a * math.cos(th)

    h = 1e-4
    d2 = (ueff(theta0 + h) - 2 * ueff(theta0) + ueff(theta0 - h)) / h**2
    md = lin.modes()
    osc = [mo for mo in md.modes if mo.damped_frequency > 1e-6]
    assert len(osc) == 2 and osc[0].damped_frequency == pytest.approx(math.sqrt(d2 / A), rel=1e-6)
    assert lin.stability().stable is True


@pytest.mark.slow
def test_mode_drawn_as_a_motion_solves_the_linearized_equations(tmp_path):
    """The mode's motion satisfies M δq̈ + K δq = 0 (double pendulum), and the animation draws it."""
    from lagrangian.plotting import animate, mode_trajectory
    eom = lagrangian.derive(planar_chain(2))
    lin = linearize(eom, {"theta1": 0, "theta2": 0})
    traj = mode_trajectory(lin, 0, amplitude=0.05, samples=50)
    M, K = _num(lin.second_order.M), _num(lin.second_order.K)
    np.testing.assert_allclose(traj.qdd @ M.T + traj.q @ K.T, 0, atol=1e-10)
    assert np.abs(traj.q).max() == pytest.approx(0.05)
    out = animate(traj, eom, tmp_path / "mode.gif", frames=5)
    assert out.stat().st_size > 0


SLEEPING_TOP = """
[model]
name = "Heavy symmetric top in Cardan angles"
[parameters]
m = 1.0
g = 9.81
a = 0.1
A = 0.02
C = 0.01
omega = { value = 40.0, description = "spin rate of the sleeping top" }
[coordinates]
alpha = {}
beta = {}
phi = {}
[frames]
R1 = { from = "R0", rotation = ["alpha", "x"] }
R2 = { from = "R1", rotation = ["beta", "y"] }
R = { from = "R2", rotation = ["phi", "z"] }
[bodies.S]
frame = "R"
mass = "m"
center = "a*R2.z"
fixed_point = "O"
inertia = { at = "O", frame = "R2", diagonal = ["A", "A", "C"] }
[loads]
weight = { gravity = "-g*R0.z" }
"""


def test_sleeping_top_gyroscopic_stabilisation_agrees_with_analyse_top():
    """About α = β = 0, φ̇ = ω: M = A I, G = C ω J, K = −m g a I; stable iff C²ω² > 4 A m g a, the
    threshold `analyse_top` gives for the same top in Euler angles."""
    eom = lagrangian.derive(parse_model(SLEEPING_TOP))
    lin = linearize(eom, {"alpha": 0, "beta": 0, "phi": 0, "phi_dot": "omega"}, symbolic=("omega",))
    so = lin.second_order
    A, C, m, g, a = 0.02, 0.01, 1.0, 9.81, 0.1
    w = se.Symbol("omega")
    idx = [so.coordinates.index(c) for c in ("alpha", "beta")]
    for (i, j), expected in {(0, 0): A, (1, 1): A, (0, 1): 0}.items():
        assert abs(float(so.M[idx[i], idx[j]]) - expected) < 1e-15
        assert abs(float(so.K[idx[i], idx[j]]) - (-m * g * a if i == j else 0)) < 1e-15
    assert abs(float(se.expand(so.G[idx[0], idx[1]] / w))) == pytest.approx(C, rel=1e-14)
    critical = math.sqrt(4 * A * m * g * a) / C
    assert lin.stability(omega=1.05 * critical).verdict == "stable to first order"
    assert lin.stability(omega=0.95 * critical).stable is False
    sw = lagrangian.sweep(lin, "omega", np.linspace(1.0, 60.0, 60))
    changes = [c for c in sw.changes if c.kind.startswith("stability")]
    assert len(changes) == 1 and changes[0].value == pytest.approx(critical, rel=1e-10)
    top = lagrangian.analyse_top(_eom("lagrange_top"), initial={"theta": 0.0, "phi_dot": 40.0})
    assert top.sleeping[0].critical_spin == pytest.approx(critical, rel=1e-12)
