"""``lagrangian linearize`` and ``lagrangian modes``, called in-process, against closed forms written here.

Every reference is derived by hand in this file, in another formulation than the engine's
(absolute angles for the double pendulum, T and U of the cart–pendulum written from the
model's comment), and compared with what the command prints (--json, validated against the
schema ``lagrangian.linearize``).
"""

from __future__ import annotations

import json
import math
from pathlib import Path

import jsonschema
import numpy as np
import pytest
from lagrangian_test_support import EXAMPLES_DIR
from scipy import linalg

import lagrangian
from lagrangian.cli.main import main

ROOT = Path(__file__).resolve().parents[2]
SCHEMA = json.loads((ROOT / "src/lagrangian/output/linearize.schema.json").read_text())
#: √eps: the relative accuracy a linearization about a point given with 16 digits keeps.
RTOL = 1.5e-8


def _values(name: str) -> dict[str, float]:
    return dict(lagrangian.load_model(EXAMPLES_DIR / name).parameter_values)


def _json(capsys, *argv: str) -> dict:
    assert main([*argv, "--json"]) == 0, capsys.readouterr().err
    doc = json.loads(capsys.readouterr().out)
    jsonschema.validate(doc, SCHEMA)
    return doc


def _eig(doc: dict) -> np.ndarray:
    return np.array([complex(re_, im) for re_, im in doc["eigenvalues"]])


def test_schema_is_a_valid_draft_2020_12_schema():
    jsonschema.Draft202012Validator.check_schema(SCHEMA)


def test_simple_pendulum_hanging_and_inverted(capsys):
    v = _values("simple_pendulum.toml")
    g, l, m = v["g"], v["l"], v["m"]
    doc = _json(capsys, "linearize", str(EXAMPLES_DIR / "simple_pendulum.toml"), "--at", "theta=0")
    assert doc["state"] == ["theta", "theta_dot"] and doc["coordinates"] == ["theta"] and doc["inputs"] == []
    assert doc["point"] == {"theta": 0, "theta_dot": 0}
    # m l² δθ̈ + m g l δθ = 0; A = [[0, 1], [−g/l, 0]].
    np.testing.assert_allclose(doc["M"], [[m * l**2]], rtol=1e-14)
    np.testing.assert_allclose(doc["K"], [[m * g * l]], rtol=1e-14)
    assert doc["D"] == [[0.0]] and doc["G"] == [[0.0]] and doc["N"] == [[0.0]]
    np.testing.assert_allclose(doc["A"], [[0, 1], [-g / l, 0]], rtol=1e-14)
    np.testing.assert_allclose(sorted(_eig(doc).imag), [-math.sqrt(g / l), math.sqrt(g / l)], rtol=1e-12)
    assert doc["stable"] is True and "Lagrange–Dirichlet" in doc["stability_reason"]
    np.testing.assert_allclose(doc["modes"]["pulsations"], [math.sqrt(g / l)], rtol=1e-12)
    # Inverted: θ = 3.14159 is refused by nothing (residual 3e-6 of the scale), and unstable: λ = ±√(g/l).
    doc = _json(capsys, "linearize", str(EXAMPLES_DIR / "simple_pendulum.toml"), "--at", "theta=3.14159")
    assert doc["stable"] is False and doc["stability_verdict"] == "unstable"
    np.testing.assert_allclose(max(_eig(doc).real), math.sqrt(g / l), rtol=1e-9)


def test_simple_pendulum_text_is_in_course_notation(capsys):
    assert main(["linearize", str(EXAMPLES_DIR / "simple_pendulum.toml"), "--at", "theta=0"]) == 0
    out = capsys.readouterr().out
    assert "M δq̈ + (D + G) δq̇ + (K + N) δq = B u" in out and "ẋ = A x + B u" in out
    assert "State x = (δθ, δθ̇)" in out and "Lagrange–Dirichlet" in out
    assert f"±{math.sqrt(9.81 / 0.5):.9g} i" in out


def test_symbolic_parameters_are_strings_that_read_back(capsys):
    import sympy

    doc = _json(capsys, "linearize", str(EXAMPLES_DIR / "simple_pendulum.toml"), "--at", "theta=0",
                "--symbolic", "g,l")
    assert doc["numeric"] is False and sorted(doc["symbols"]) == ["g", "l"]
    assert doc["eigenvalues"] is None and doc["stable"] is None and doc["modes"] is None
    g, l = sympy.symbols("g l")
    assert sympy.simplify(sympy.sympify(doc["A"][1][0]) + g / l) == 0
    assert sympy.sympify(doc["A"][0][1]) == 1


def test_double_pendulum_pulsations_match_absolute_angle_formulation(capsys):
    v = _values("double_pendulum.toml")
    m1, l1, m2, l2, g = v["m1"], v["l1"], v["m2"], v["l2"], v["g"]
    # Absolute angles φ1 = θ1, φ2 = θ1 + θ2; two uniform rods:
    # T = ½ (m1/3 + m2) l1² φ̇1² + ½ m2 l1 l2 cos(φ1 − φ2) φ̇1 φ̇2 + ½ (m2 l2²/3) φ̇2²,
    # U = −g [(m1/2 + m2) l1 cos φ1 + m2 l2/2 cos φ2].  ω² are invariant under the change of coordinates.
    M = np.array([[(m1 / 3 + m2) * l1**2, m2 * l1 * l2 / 2], [m2 * l1 * l2 / 2, m2 * l2**2 / 3]])
    K = np.diag([g * (m1 / 2 + m2) * l1, g * m2 * l2 / 2])
    omega = np.sqrt(linalg.eigh(K, M, eigvals_only=True))
    doc = _json(capsys, "modes", str(EXAMPLES_DIR / "double_pendulum.toml"), "--at", "theta1=0", "--at", "theta2=0")
    np.testing.assert_allclose(doc["modes"]["pulsations"], omega, rtol=1e-12)
    np.testing.assert_allclose(sorted(abs(_eig(doc).imag)), sorted(np.repeat(omega, 2)), rtol=1e-12)
    assert doc["stable"] is True
    periods = sorted(m["period"] for m in doc["modes"]["modes"])
    np.testing.assert_allclose(periods, sorted(np.repeat(2 * np.pi / omega, 2)), rtol=1e-12)


def test_double_pendulum_equal_rods_with_set(capsys):
    # Equal rods (m, l): M = m l² [[4/3, 1/2], [1/2, 1/3]], K = m g l [[3/2, 0], [0, 1/2]] in absolute angles;
    # det(K − ω² M) = 0 is 7/36 s² − 7/6 s + 3/4 = 0 with ω² = s g/l: s = 3 ± 6/√7.
    g, l = 9.81, 0.7
    roots = [3 - 6 / math.sqrt(7), 3 + 6 / math.sqrt(7)]
    doc = _json(capsys, "modes", str(EXAMPLES_DIR / "double_pendulum.toml"), "--at", "theta1=0", "--at", "theta2=0",
                "--set", "m1=2", "--set", "m2=2", "--set", f"l1={l}", "--set", f"l2={l}", "--set", f"g={g}")
    np.testing.assert_allclose(np.square(doc["modes"]["pulsations"]), np.array(roots) * g / l, rtol=1e-12)


@pytest.mark.slow
def test_bead_on_hoop_bottom_unstable_side_stable_and_sweep(capsys, tmp_path):
    v = _values("bead_rotating_hoop.toml")
    g, R, W = v["g"], v["R"], v["Omega"]
    hoop = str(EXAMPLES_DIR / "bead_rotating_hoop.toml")
    # θ = 0: δθ̈ = (Ω² − g/R) δθ, unstable when Ω² > g/R (here 36 > 19.62).
    doc = _json(capsys, "linearize", hoop, "--at", "theta=0")
    assert doc["stable"] is False
    np.testing.assert_allclose(max(_eig(doc).real), math.sqrt(W**2 - g / R), rtol=1e-12)
    # cos θ0 = g/(R Ω²): stable, ω² = Ω² sin²θ0.
    theta0 = math.acos(g / (R * W**2))
    doc = _json(capsys, "modes", hoop, "--at", f"theta={theta0!r}")
    assert doc["stable"] is True
    np.testing.assert_allclose(doc["modes"]["pulsations"], [W * math.sin(theta0)], rtol=RTOL)
    # The pitchfork: the bottom loses its stability at Ω = √(g/R).
    plots = tmp_path / "hoop"
    doc = _json(capsys, "modes", hoop, "--at", "theta=0", "--sweep", "Omega=0:10:0.01", "--plot", str(plots))
    assert doc["sweep"]["parameter"] == "Omega" and len(doc["sweep"]["values"]) == 1001
    lost = [c["value"] for c in doc["sweep"]["changes"] if c["kind"] == "stability lost"]
    assert len(lost) == 1 and abs(lost[0] - math.sqrt(g / R)) < 1e-8
    assert doc["modes_at"] == {"Omega": W}
    assert {p.name for p in plots.iterdir()} == {"eigenvalues.png", "mode_shapes.png"}
    assert (plots / "eigenvalues.png").read_bytes().startswith(b"\x89PNG")


def test_sweep_text_names_the_change(capsys):
    assert main(["modes", str(EXAMPLES_DIR / "bead_rotating_hoop.toml"), "--at", "theta=0",
                 "--sweep", "Omega=4:5:0.1"]) == 0
    out = capsys.readouterr().out
    assert f"Ω = {math.sqrt(9.81 / 0.5):.12g} rad/s: stability lost" in out


def test_cart_pendulum_matches_its_lagrangian(capsys):
    v = _values("cart_pendulum.toml")
    mc, m, l, k, g = v["mc"], v["m"], v["l"], v["k"], v["g"]
    cart = str(EXAMPLES_DIR / "cart_pendulum.toml")
    # T = ½ (mc + m) ẋ² − m l cosθ ẋ θ̇ + ½ m l² θ̇², U = ½ k x² − m g l cosθ (the model's comment).
    for theta, c in ((0, 1.0), (math.pi, -1.0)):
        doc = _json(capsys, "linearize", cart, "--at", "x=0", "--at", f"theta={theta!r}")
        M = np.array([[mc + m, -m * l * c], [-m * l * c, m * l**2]])
        K = np.diag([k, m * g * l * c])
        np.testing.assert_allclose(doc["M"], M, rtol=1e-12, atol=1e-12)
        np.testing.assert_allclose(doc["K"], K, rtol=1e-12, atol=1e-12)
        A = np.block([[np.zeros((2, 2)), np.eye(2)], [-np.linalg.solve(M, K), np.zeros((2, 2))]])
        np.testing.assert_allclose(doc["A"], A, rtol=1e-12, atol=1e-12)
        assert doc["stable"] is (c > 0)


def test_inverted_cart_pendulum_with_a_force_input_is_unstable_and_controllable(tmp_path, capsys):
    text = (EXAMPLES_DIR / "cart_pendulum.toml").read_text()
    text = text.replace("[coordinates]", 'F = { value = 0.0, unit = "N", description = "push on the cart" }\n\n'
                                         "[coordinates]")
    text += '\npush = { force = "F*R0.x", at = "C" }\n'
    model = tmp_path / "cart_force.toml"
    model.write_text(text)
    v = _values("cart_pendulum.toml")
    mc, m, l = v["mc"], v["m"], v["l"]
    doc = _json(capsys, "linearize", str(model), "--at", "x=0", "--at", "theta=pi", "--inputs", "F")
    assert doc["inputs"] == ["F"] and doc["stable"] is False
    # M [ẍ, θ̈]ᵀ = [F, 0]ᵀ + ...: B = [0; M⁻¹ e1] (virtual power of F x0 at C: Q_x = F, Q_θ = 0).
    M = np.array([[mc + m, m * l], [m * l, m * l**2]])
    np.testing.assert_allclose(np.array(doc["B"])[:, 0], [0, 0, *np.linalg.solve(M, [1.0, 0.0])], atol=1e-12)
    A, B = np.array(doc["A"]), np.array(doc["B"])
    ctrb = np.hstack([np.linalg.matrix_power(A, k) @ B for k in range(4)])
    assert np.linalg.matrix_rank(ctrb) == 4


# -- bad input: a clear error with the fix, a non-zero exit code, nothing written -------------------

@pytest.mark.parametrize("argv, words", [
    (["simple_pendulum.toml", "--at", "phi=0"], ["`phi`", "not a coordinate", "theta"]),
    (["simple_pendulum.toml", "--at", "g=0"], ["`g`", "parameter", "--set g="]),
    (["double_pendulum.toml", "--at", "theta1=0"], ["`theta2`", "no value", "--at theta2=VALUE"]),
    (["simple_pendulum.toml", "--at", "theta=1"], ["not an equilibrium", "residual", "theta"]),
    (["simple_pendulum.toml", "--at", "theta=0", "--inputs", "tau"], ["`tau`", "neither a parameter"]),
    (["cart_pendulum.toml", "--at", "theta=0", "--at", "x=0", "--inputs", "mc"], ["no load uses", "mc"]),
    (["simple_pendulum.toml", "--at", "theta=0", "--set", "theta=1"], ["--at theta=VALUE"]),
    (["simple_pendulum.toml", "--at", "theta=0", "--symbolic", "q"], ["`q`", "not a parameter"]),
])
def test_bad_input_is_refused_with_the_fix(argv, words, tmp_path, capsys):
    out = tmp_path / "out.json"
    argv = [str(EXAMPLES_DIR / argv[0]), *argv[1:]]
    assert main(["linearize", *argv, "--json", "-o", str(out)]) == 2
    err = capsys.readouterr().err
    assert err.startswith("error: ") and "Traceback" not in err
    for w in words:
        assert w in err
    assert not out.exists()


def test_not_an_equilibrium_gives_the_residual_and_the_nearest_equilibrium(capsys):
    assert main(["linearize", str(EXAMPLES_DIR / "simple_pendulum.toml"), "--at", "theta=0.1"]) == 2
    err = capsys.readouterr().err
    residual = 0.5 * 1.0 * 9.81 * math.sin(0.1)  # F_θ = −m g l sin θ
    assert f"{-residual:.6g}" in err and "nearest equilibrium" in err


def test_singular_mass_matrix_is_refused(capsys):
    # The top in Euler angles at θ = 0: ψ and φ turn about the same axis, M is singular.
    assert main(["linearize", "zoo:lagrange_top", "--at", "theta=0", "--at", "psi=0", "--at", "phi=0"]) == 2
    assert "singular" in capsys.readouterr().err


@pytest.mark.parametrize("sweep, words", [
    ("Omega=5:4:0.1", ["no point", "b < a"]),
    ("Omega=0:1:0", ["step", "not positive"]),
    ("theta=0:1:0.1", ["`theta` is a coordinate", "parameter"]),
    ("Omega=0:1", ["NAME=a:b:step"]),
    ("Omega=a:1:0.1", ["decimal numbers"]),
])
def test_bad_sweep_is_refused_and_nothing_is_drawn(sweep, words, tmp_path, capsys):
    plots = tmp_path / "plots"
    assert main(["modes", str(EXAMPLES_DIR / "bead_rotating_hoop.toml"), "--at", "theta=0", "--sweep", sweep,
                 "--plot", str(plots)]) == 2
    err = capsys.readouterr().err
    for w in words:
        assert w in err
    assert not plots.exists()


def test_sweep_of_a_parameter_the_matrices_ignore_is_refused(capsys, tmp_path):
    plots = tmp_path / "plots"
    # The bead's mass cancels from δθ̈ = (Ω² − g/R) δθ: m is not a symbol of A.
    assert main(["modes", str(EXAMPLES_DIR / "bead_rotating_hoop.toml"), "--at", "theta=0", "--sweep", "m=0.1:1:0.1",
                 "--plot", str(plots)]) == 2
    assert "`m`" in capsys.readouterr().err
    assert not plots.exists()


def test_rolling_coin_records_the_dependent_speeds_it_solved(capsys):
    # Rolling without slipping with ψ = 0: ẋ = r φ̇, ẏ = 0 (the model's comment); the other speeds are free.
    r = _values("rolling_coin.toml")["r"]
    doc = _json(capsys, "linearize", str(EXAMPLES_DIR / "rolling_coin.toml"), "--at", "x=0", "--at", "y=0",
                "--at", "psi=0", "--at", "phi=0", "--at", "phi_dot=10")
    assert doc["steady"] is True and sorted(doc["dependent_speeds"]) == ["x_dot", "y_dot"]
    assert doc["point"]["x_dot"] == pytest.approx(r * 10, rel=1e-14) and doc["point"]["y_dot"] == 0
    assert doc["state"] == doc["coordinates"] + doc["speeds"] and "x_dot" not in doc["speeds"]
    assert doc["choice"]


def test_steady_precession_of_the_top_nutation_frequency_from_routh(capsys):
    """Steady precession of the Lagrange top at θ0 = 0.5, ψ̇ = 2: ω3 = (A ψ̇² cosθ0 + m g a)/(C ψ̇) (the θ equation
    with θ̇ = θ̈ = 0), and the small nutation about it has ω² = U_eff''(θ0)/A with Routh's effective potential
    U_eff = (K − H cosθ)²/(2 A sin²θ) + m g a cosθ at the momenta K, H of the motion."""
    import sympy

    v = dict(lagrangian.lagrange_top().parameter_values)
    m, g, a, A, C = v["m"], v["g"], v["a"], v["A"], v["C"]
    theta0, psi_dot = 0.5, 2.0
    omega3 = (A * psi_dot**2 * math.cos(theta0) + m * g * a) / (C * psi_dot)
    phi_dot = omega3 - psi_dot * math.cos(theta0)
    H = C * omega3
    K = A * psi_dot * math.sin(theta0) ** 2 + H * math.cos(theta0)
    th = sympy.Symbol("theta")
    U = (K - H * sympy.cos(th)) ** 2 / (2 * A * sympy.sin(th) ** 2) + m * g * a * sympy.cos(th)
    assert abs(float(U.diff(th).subs(th, theta0))) < 1e-12  # a steady motion indeed
    omega = math.sqrt(float(U.diff(th, 2).subs(th, theta0)) / A)
    doc = _json(capsys, "modes", "--at", "psi=0", "--at", f"theta={theta0!r}", "--at", "phi=0",
                "--at", f"psi_dot={psi_dot!r}", "--at", f"phi_dot={phi_dot!r}")
    assert doc["steady"] is True and doc["stable"] is True
    assert {n["name"] for n in doc["modes"]["neutral"]} >= {"psi", "phi"}
    assert len(doc["eigenvalues"]) == 6 and len(doc["essential_eigenvalues"]) == 2
    essential = np.array([complex(re_, im) for re_, im in doc["essential_eigenvalues"]])
    np.testing.assert_allclose(sorted(abs(essential.imag)), [omega, omega], rtol=1e-9)
    # The four others are the neutral zeros (ψ, φ and the momenta K, H).
    assert np.sum(np.abs(_eig(doc)) < 1e-9) == 4


@pytest.mark.slow
def test_animate_writes_one_gif_per_mode_into_the_plot_folder(tmp_path, capsys):
    args = ["modes", str(EXAMPLES_DIR / "double_pendulum.toml"), "--at", "theta1=0", "--at", "theta2=0"]
    assert main([*args, "--animate"]) == 2
    assert "--plot DIR" in capsys.readouterr().err
    plots = tmp_path / "dp"
    assert main([*args, "--plot", str(plots), "--animate"]) == 0
    out = capsys.readouterr().out
    assert "λ₁" in out and "λ₂" in out and "λ₃" not in out  # two conjugate pairs, each written once
    assert {p.name for p in plots.iterdir()} == {"mode_shapes.png", "mode_1.gif", "mode_2.gif"}
    assert (plots / "mode_1.gif").read_bytes()[:6] in (b"GIF89a", b"GIF87a")


def test_the_models_operating_point_fills_in_and_at_overrides_it(monkeypatch, capsys):
    # Until the model format has an [operating_point] table, a model carrying the attribute stands in for one.
    import dataclasses

    from lagrangian.cli import _linearize

    base = lagrangian.load_model(EXAMPLES_DIR / "cart_pendulum.toml")

    class WithPoint(type(base)):  # no __slots__: the instance takes one more attribute
        pass

    model = WithPoint(**{f.name: getattr(base, f.name) for f in dataclasses.fields(base) if f.init})
    object.__setattr__(model, "operating_point", {"x": 0, "theta": "pi"})
    monkeypatch.setattr(_linearize, "load_source", lambda name: model)
    doc = _json(capsys, "linearize", "cart")
    assert doc["point"]["theta"] == pytest.approx(math.pi, rel=1e-15) and doc["stable"] is False
    doc = _json(capsys, "linearize", "cart", "--at", "theta=0")
    assert doc["point"]["theta"] == 0 and doc["stable"] is True
