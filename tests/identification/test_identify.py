"""identify(): parameters recovered from motions simulated by SciPy on hand-written equations, with noise.

The reference is a cart on a rail with viscous friction c, carrying a pendulum (bob m on a
massless rod l from the ascending vertical), pushed by a measured force F(t): written out by hand,

    (mc + m) ẍ + m l cos θ θ̈ − m l sin θ θ̇² = F − c ẋ,
    m l cos θ ẍ + m l² θ̈ − m g l sin θ = 0,

integrated by SciPy's DOP853 at 1e-11.  F is applied as the linear interpolation of its samples (what
`identify` assumes between samples).  Each estimate must lie within 3 standard errors of the truth.
"""

import functools

import numpy as np
import pytest
from lagrangian_test_support import EXAMPLES_DIR
from scipy.integrate import solve_ivp

import lagrangian
from lagrangian.errors import IdentificationError
from lagrangian.identification import SavitzkyGolay, Shooting, identify

CART_POLE = """
[model]
name = "cart and pendulum with friction"
[parameters]
mc = { value = 1.0, unit = "kg" }
m = { value = 0.2, unit = "kg" }
l = { value = 0.6, unit = "m" }
c = { value = 0.5, unit = "N*s/m" }
g = { value = 9.81, unit = "m/s^2" }
[inputs]
F = { unit = "N" }
[coordinates]
x = { initial = 0.0, rate = 0.0, unit = "m" }
theta = { initial = 0.05, rate = 0.0 }
[frames]
R0 = { axes = ["x0", "y0", "z0"] }
R1 = { from = "R0", rotation = ["theta", "y"], axes = ["x1", "y0", "z1"] }
[particles.C]
mass = "mc"
position = "x*R0.x"
[particles.P]
mass = "m"
position = "x*R0.x + l*R1.z"
[loads]
weight = { gravity = "-g*R0.z" }
push = { force = "F*R0.x", at = "C" }
friction = { generalized_force = { x = "-c*x_dot" } }
"""

TRUE = {"mc": 1.3, "m": 0.25, "l": 0.55, "c": 0.4}
G = 9.81


@functools.cache
def _exact_record(t_end: float, rate: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(t, F, y) from SciPy on the equations written above, sample interval by sample interval (F is linear
    on each, so every piece is smooth for DOP853's error control)."""
    t = np.linspace(0.0, t_end, round(t_end * rate) + 1)
    F = 2 * np.sin(2.1 * t) + 1.5 * np.sin(5.3 * t + 1) + 0.8 * np.sin(11 * t)
    mc, m, l, c = (TRUE[k] for k in ("mc", "m", "l", "c"))

    def f(time, y, k):
        _, th, xd, thd = y
        force = F[k] + (F[k + 1] - F[k]) * (time - t[k]) / (t[k + 1] - t[k])
        a11, a12, a22 = mc + m, m * l * np.cos(th), m * l * l
        r1, r2 = force - c * xd + m * l * np.sin(th) * thd**2, m * G * l * np.sin(th)
        det = a11 * a22 - a12 * a12
        return [xd, thd, (a22 * r1 - a12 * r2) / det, (a11 * r2 - a12 * r1) / det]

    y = np.empty((len(t), 4))
    y[0] = [0.0, 2.5, 0.0, 0.0]
    for k in range(len(t) - 1):
        sol = solve_ivp(f, (t[k], t[k + 1]), y[k], args=(k,), rtol=1e-11, atol=1e-11, method="DOP853")
        y[k + 1] = sol.y[:, -1]
    return t, F, y


def cart_pole_record(t_end: float, rate: float, noise: float, seed: int, span: float | None = None
                     ) -> dict[str, np.ndarray]:
    """Samples of x, θ (with white noise) and F over [0, span] of the record of [0, t_end]."""
    t, F, y = _exact_record(t_end, rate)
    keep = slice(None) if span is None else slice(0, round(span * rate) + 1)
    rng = np.random.default_rng(seed)
    t, F, y = t[keep], F[keep], y[keep]
    return {"t": t, "x": y[:, 0] + rng.normal(scale=noise, size=len(t)),
            "theta": y[:, 1] + rng.normal(scale=noise, size=len(t)), "F": F}


def _exact_states_and_accelerations(t_end: float, rate: float) -> dict[str, np.ndarray]:
    """q, q̇ and q̈ of the exact record, q̈ from the equations written above (no derivative estimated)."""
    t, F, y = _exact_record(t_end, rate)
    mc, m, l, c = (TRUE[k] for k in ("mc", "m", "l", "c"))
    th, xd, thd = y[:, 1], y[:, 2], y[:, 3]
    a11, a12, a22 = mc + m, m * l * np.cos(th), m * l * l
    r1, r2 = F - c * xd + m * l * np.sin(th) * thd**2, m * G * l * np.sin(th)
    det = a11 * a22 - a12 * a12
    return {"t": t, "x": y[:, 0], "theta": th, "x_dot": xd, "theta_dot": thd,
            "x_ddot": (a22 * r1 - a12 * r2) / det, "theta_ddot": (a11 * r2 - a12 * r1) / det, "F": F}


@pytest.fixture(scope="module")
def cart_pole():
    return lagrangian.derive(lagrangian.parse_model(CART_POLE))


def _within(fit, names, k=3.0):
    for name in names:
        error = (fit[name] - TRUE[name]) / fit.std[name]
        assert abs(error) < k, f"{name} = {fit[name]:.8g} ± {fit.std[name]:.2g}, true {TRUE[name]} ({error:+.1f} σ)"


@pytest.mark.slow
def test_regressor_recovers_masses_and_friction_within_three_standard_errors(cart_pole):
    # Linear in (mc, m, c) with l known.  The accelerations come from the noisy positions (a 31-sample
    # window at 200 Hz): their noise biases least squares (errors in variables) by about 1 σ here.
    data = cart_pole_record(6.0, 200.0, 1e-5, seed=3)
    fit = identify(cart_pole, data, ["mc", "m", "c"], values={"l": TRUE["l"]}, derivatives=SavitzkyGolay(31, 4))
    assert fit.route == "regressor" and fit.full_rank
    _within(fit, ["mc", "m", "c"])
    assert fit.residuals.shape == (len(data["t"]) - 30, 2)
    assert fit.covariance.shape == (3, 3)
    assert any("errors in variables" in note and "shooting" in note for note in fit.notes)
    measured = identify(cart_pole, _exact_states_and_accelerations(2.0, 200.0), ["mc", "m", "c"],
                        values={"l": TRUE["l"]})
    assert not any("errors in variables" in note for note in measured.notes)  # nothing estimated, nothing said
    assert [measured[k] for k in ("mc", "m", "c")] == pytest.approx([TRUE[k] for k in ("mc", "m", "c")], rel=1e-6)


@pytest.mark.slow
def test_shooting_recovers_a_length_within_three_standard_errors(cart_pole):
    # l enters M and F nonlinearly (m l², m g l): the regressor does not apply, shooting does.
    data = cart_pole_record(4.0, 100.0, 1e-4, seed=4)
    fit = identify(cart_pole, data, ["mc", "m", "c", "l"], guess={"mc": 1.0, "m": 0.2, "c": 0.5, "l": 0.6},
                   shooting=Shooting(segments=8))
    assert fit.route == "shooting" and fit.status == "converged"
    _within(fit, ["mc", "m", "c", "l"])
    np.testing.assert_allclose(list(fit.sigma.values()), 1e-4, rtol=0.15)  # the noise, found again
    assert fit.initial["theta"] == pytest.approx(2.5, abs=5e-4)


@pytest.mark.slow
def test_single_and_multiple_shooting_find_the_same_optimum(cart_pole):
    data = cart_pole_record(4.0, 100.0, 1e-4, seed=5, span=2.0)
    fits = [identify(cart_pole, data, ["l", "c"], values={"mc": TRUE["mc"], "m": TRUE["m"]},
                     shooting=Shooting(segments=s)) for s in (1, 6)]
    for name in ("l", "c"):
        assert fits[0][name] == pytest.approx(fits[1][name], rel=1e-6)
        assert fits[0].std[name] == pytest.approx(fits[1].std[name], rel=1e-3)


@pytest.mark.slow
def test_shooting_fits_from_some_coordinates_only(cart_pole):
    # only the pendulum's angle measured (the cart unobserved): its motion still shows l and c; the cart's
    # position does not act on anything measured (x is cyclic), and is said to be undetermined
    data = cart_pole_record(4.0, 100.0, 1e-4, seed=6, span=3.0)
    del data["x"]
    fit = identify(cart_pole, data, ["l", "c"], values={"mc": TRUE["mc"], "m": TRUE["m"]}, guess={"l": 0.5, "c": 0.3},
                   initial={"x": 0.0, "x_dot": 0.0})
    assert fit.route == "shooting"
    _within(fit, ["l", "c"])
    assert any("x at t0 not determined" in note for note in fit.notes)


@pytest.fixture(scope="module")
def swing():
    """A pendulum swing by SciPy (θ̈ = −(g/l) sin θ), its record in each form `identify` reads."""
    g, l = 9.81, 0.5
    t = np.linspace(0.0, 3.0, 151)
    sol = solve_ivp(lambda _, y: [y[1], -g / l * np.sin(y[0])], (0, 3), [1.0, 0.0], t_eval=t, rtol=1e-12,
                    atol=1e-12)
    theta = sol.y[0] + np.random.default_rng(7).normal(scale=1e-3, size=len(t))
    return lagrangian.derive(lagrangian.load_model(EXAMPLES_DIR / "simple_pendulum.toml")), t, theta


@pytest.mark.slow
def test_every_form_of_the_data_gives_the_same_fit(swing, tmp_path):
    xr = pytest.importorskip("xarray")
    eom, t, theta = swing
    csv = tmp_path / "swing.csv"
    csv.write_text("# a measured swing\nt,theta\n" + "".join(f"{float(a)!r},{float(b)!r}\n" for a, b in zip(t, theta, strict=True)))
    traj = lagrangian.simulate(eom, 3.0, t_eval=t)
    sources = [{"t": t, "theta": theta}, csv, xr.Dataset({"theta": ("t", theta)}, coords={"t": t})]
    fits = [identify(eom, s, ["l"], guess={"l": 0.4}, shooting=Shooting(segments=1)) for s in sources]
    for fit in fits[1:]:
        assert fit["l"] == pytest.approx(fits[0]["l"], rel=1e-9)
    assert abs(fits[0]["l"] - 0.5) < 3 * fits[0].std["l"]
    # a Trajectory is read as measurements of q and q̇ (here the model's own motion: l exactly)
    fit = identify(eom, traj, ["l"], guess={"l": 0.45}, shooting=Shooting(segments=1), noise={"theta": 1e-6,
                                                                                             "theta_dot": 1e-6})
    assert fit["l"] == pytest.approx(0.5, rel=1e-7)


def test_a_pendulums_mass_is_not_identifiable_from_its_swing(swing):
    # m l² θ̈ + m g l sin θ = 0 is linear in m, with nothing else in it: any m fits, and both routes say so
    eom, t, theta = swing
    with pytest.raises(IdentificationError, match="homogeneous in m"):
        identify(eom, {"t": t, "theta": theta}, ["m"])
    with pytest.raises(IdentificationError, match="does not determine m"):
        identify(eom, {"t": t, "theta": theta}, ["m", "l"], shooting=Shooting(segments=1))


@pytest.mark.parametrize("data, message", [
    ({"t": [0, 0.1, 0.2, 0.2, 0.4, 0.5], "theta": [1, 1, 1, 1, 1, 1]}, "do not increase at row 4 \\(.*\\): t = 0.2 then 0.2\\."),
    ({"t": [0, 0.1, 0.2, 0.3, 0.4, 0.5], "theta": [1, 1, np.nan, 1, 1, 1]}, "holds nan at row 3"),
    ({"t": [0, 0.1, 0.2, 0.3, 0.4, 0.5], "theta": [1] * 6, "phi": [0] * 6}, "`phi` of the measurements"),
    ({"theta": [1] * 6}, "no column `t`"),
    ({"t": [0, 0.1, 0.2], "theta": [1, 1, 1]}, "fewer than"),
    ({"t": [0, 0.1, 0.2, 0.3, 0.4, 0.5], "theta": [1] * 5}, "has 5 samples"),
])
def test_bad_data_is_refused_with_the_column_and_the_row(swing, data, message):
    eom, _, _ = swing
    with pytest.raises(IdentificationError, match=message):
        identify(eom, data, ["l"])


def test_bad_requests_are_refused_clearly(swing, cart_pole):
    eom, t, theta = swing
    data = {"t": t, "theta": theta}
    with pytest.raises(IdentificationError, match="`nope` is not a parameter"):
        identify(eom, data, ["nope"])
    with pytest.raises(IdentificationError, match="not linear in l"):
        identify(eom, data, ["l"], route="regressor")
    with pytest.raises(IdentificationError, match="reversed"):
        identify(eom, data, ["l"], bounds={"l": (1.0, 0.1)})
    record = cart_pole_record(4.0, 100.0, 1e-4, seed=1, span=1.0)
    with pytest.raises(IdentificationError, match="`F` is an input"):
        identify(cart_pole, record, ["F"])
    with pytest.raises(IdentificationError, match="needs every coordinate measured, and x is not"):
        identify(cart_pole, {k: v for k, v in record.items() if k != "x"}, ["c"], route="regressor")
    del record["F"]
    with pytest.raises(IdentificationError, match="The input `F` is neither in the measurements"):
        identify(cart_pole, record, ["l"])
    with pytest.raises(IdentificationError, match="complementary constraints"):
        identify(EXAMPLES_DIR / "pendulum_tension.toml", {"t": t, "x": theta, "y": theta}, ["l"])


@pytest.mark.slow
def test_an_arms_unidentifiable_parameters_are_refused_or_fitted_as_combinations():
    # The RRR arm's 30 inertial parameters have 15 identifiable combinations (tests/identification/
    # test_regressor.py checks them against Pinocchio's regressor): refused by default, naming them;
    # fitted as combinations with deficient="base", and a parameter without an estimate of its own
    # names its combination.
    import warnings

    from lagrangian.model.urdf import inertial_parameter_names, load_urdf

    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        arm = load_urdf(EXAMPLES_DIR / "rrr_arm.urdf", inertial_parameters=True)
    fitted = [name for names in inertial_parameter_names(arm).values() for name in names]
    torques = {"tau_waist": 0.5, "tau_shoulder": 5.0, "tau_elbow": 1.0}
    motion = lagrangian.simulate(arm, 2.0, initial={"shoulder": 0.3, "elbow": 0.5, "waist_dot": 1.0}, n_out=801,
                                 parameters=torques)
    data = {"t": motion.t, **{c: motion.q[:, i] for i, c in enumerate(motion.coordinates)}}
    with pytest.raises(IdentificationError, match=r"rank 15 of 30.*`mx_upper_arm \+ 0\.5 m_forearm`"):
        identify(arm, data, fitted, inputs=torques)
    fit = identify(arm, data, fitted, inputs=torques, deficient="base")
    assert len(fit.base) == 15 and not fit.full_rank
    assert "mx_upper_arm + 0.5 m_forearm" in fit.identifiable
    with pytest.raises(IdentificationError, match=r"enters only .*`mx_upper_arm \+ 0\.5 m_forearm`"):
        fit["m_forearm"]
    with pytest.raises(IdentificationError, match="does not act on the motion at all"):
        fit["m_column"]
    # the forearm's Iyy is identified on its own; the motion's accelerations come from a 21-sample
    # filter at 400 Hz, whose bias on this fast swing stays below a percent
    assert fit["Iyy_forearm"] == pytest.approx(arm.parameter_values["Iyy_forearm"], rel=1e-2)
