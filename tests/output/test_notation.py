"""The course's notation: the seed's top must print exactly as the seed writes it."""

import sympy

import lagrangian
from lagrangian.output import Notation, course_form, render_latex, render_text


def _form():
    eom = lagrangian.derive(lagrangian.lagrange_top())
    return course_form(eom, lagrangian.first_integrals(eom))


def test_top_prints_like_the_seed():
    text = render_text(_form())
    # Seed, worked example (T, U, L(θ), K, H, energy integral), in our Unicode rendering.
    for line in [
        "T(S/R0) = ½ A (θ̇² + ψ̇² sin²θ) + ½ C (φ̇ + ψ̇ cosθ)²",
        "weight: m g a cosθ",
        "A θ̈ − A ψ̇² sinθ cosθ + C ψ̇ sinθ (φ̇ + ψ̇ cosθ) = m g a sinθ",
        "A θ̈ − A ψ̇² sinθ cosθ + H ψ̇ sinθ = m g a sinθ",
        "A ψ̇ sin²θ + C cosθ (φ̇ + ψ̇ cosθ) = K",
        "C (φ̇ + ψ̇ cosθ) = H",
        "½ A (θ̇² + ψ̇² sin²θ) + ½ C (φ̇ + ψ̇ cosθ)² + m g a cosθ = E",
        "Ω(R/R0) = ψ̇ z0 + θ̇ u + φ̇ z = θ̇ u + ψ̇ sinθ w + (φ̇ + ψ̇ cosθ) z",
    ]:
        assert line in text, f"missing {line!r} in\n{text}"


def test_latex_uses_dots_and_greek_letters():
    tex = render_latex(_form())
    assert r"\ddot{\theta}" in tex and r"\dot{\psi}" in tex and r"\varphi" in tex
    math = tex.split(r"\par", 1)[1]  # after the model's own description
    assert "psi_dot" not in math and "theta" not in math.replace(r"\theta", "")
    assert tex.count(r"\begin{align*}") == tex.count(r"\end{align*}")


def test_notation_orders_factors_and_terms():
    n = Notation(coordinates=["x", "theta"], parameters=["m", "l", "g"])
    x, th, xd, thdd, m, l, g = sympy.symbols("x theta x_dot theta_ddot m l g")
    assert n.text(g * m * l * sympy.sin(th)) == "m l g sinθ"
    assert n.text(-g * sympy.sin(th) + l * thdd) == "l θ̈ − g sinθ"
    assert n.text(sympy.Rational(1, 2) * m * xd**2) == "½ m x\u0307²"
    assert n.text(sympy.sin(th + x) ** 2) == "sin²(x + θ)"
    assert n.latex(sympy.cos(th) ** 2 / l) == r"\frac{\cos^{2}\theta}{l}"


def test_the_dot_goes_on_the_letter_not_on_its_index():
    n = Notation(["theta1", "x2"])
    assert n.latex(sympy.Symbol("theta1_dot")) == r"\dot{\theta}_{1}"
    assert n.latex(sympy.Symbol("theta1_ddot")) == r"\ddot{\theta}_{1}"
    assert n.latex(sympy.Symbol("x2_dot")) == r"\dot{x}_{2}"
    assert n.text(sympy.Symbol("theta1_dot")) == "θ̇1"
    assert n.latex(sympy.Symbol("theta_dot")) == r"\dot{\theta}"


def test_a_greek_letter_with_a_capital_index_is_that_letter_indexed():
    # The bicycle's rear-wheel angle thetaR is θ_R, its rate θ̇_R (not "thetaṘ"); a lower-case tail is a word.
    n = Notation(coordinates=("thetaR",))
    assert n.symbol("thetaR") == "θR" and n.symbol("thetaR_dot") == "θ̇R"
    assert n.symbol("thetaR", latex=True) == r"\theta_{R}"
    assert n.symbol("thetaR_dot", latex=True) == r"\dot{\theta}_{R}"
    assert n.symbol("omegaZ1_ddot", latex=True) == r"\ddot{\omega}_{Z1}"
    assert n.symbol("thetas") == "thetas" and n.symbol("beta") == "β" and n.symbol("eta") == "η"


def test_a_function_is_set_apart_from_a_word_or_latin_argument():
    lat, x1, theta = sympy.symbols("lat x_1 theta")
    n = Notation(["lat"], ["g"])
    assert n.latex(sympy.cos(lat)) == r"\cos\,\mathrm{lat}"
    assert n.latex(sympy.Symbol("g") * sympy.sin(lat) ** 2) == r"g \sin^{2}\,\mathrm{lat}"
    assert n.text(sympy.cos(lat)) == "cos lat" and n.text(sympy.sin(lat) ** 2) == "sin² lat"
    assert n.latex(sympy.cos(x1)) == r"\cos x_{1}"  # not the unknown command \cosx
    assert n.latex(sympy.cos(theta)) == r"\cos\theta" and n.text(sympy.cos(theta)) == "cosθ"


def test_a_coordinate_or_its_rate_comes_first_in_a_sum():
    n = Notation(coordinates=["x", "phi"], parameters=["m", "r", "v_b", "eps"])
    x, xd, phid, r, vb, eps = sympy.symbols("x x_dot phi_dot r v_b eps")
    assert n.text(xd - vb) == "x\u0307 − v_b"
    assert n.text(xd - r * phid) == "x\u0307 − r φ̇"
    assert n.text(vb - xd) == "v_b − x\u0307"  # a negative rate does not lead
    assert n.text(r**2 - x**2) == "r² − x²"  # nor a square
    assert n.text((xd - vb) ** 2 + eps**2) == "(x\u0307 − v_b)² + ε²"


def test_eps_is_epsilon():
    n = Notation(parameters=["eps", "epsilon"])
    eps, epsilon = sympy.symbols("eps epsilon")
    assert (n.text(eps), n.latex(eps)) == ("ε", r"\varepsilon")
    assert (n.text(epsilon), n.latex(epsilon)) == ("ε", r"\varepsilon")


def test_sign_function_prints_sgn_with_parentheses():
    n = Notation(coordinates=["x"])
    xd = sympy.Symbol("x_dot")
    assert n.text(sympy.sign(xd)) == "sgn(x\u0307)"
    assert n.latex(sympy.sign(xd)) == r"\operatorname{sgn}\left(\dot{x}\right)"


def test_an_axis_indexed_by_its_frame_has_the_index_after_the_arrow():
    from lagrangian.output._notation import _axis_latex

    assert _axis_latex("x_I") == r"\vec{x}_{I}"  # a frame's default axes (examples/block_on_incline.toml)
    assert _axis_latex("xE") == r"\vec{x}_{E}"  # a letter and the frame's name (examples/foucault_pendulum.toml)
    assert _axis_latex("xe", frames=["e"]) == r"\vec{x}_{e}"
    assert (_axis_latex("z0"), _axis_latex("u"), _axis_latex("xe")) == (r"\vec{z}_{0}", r"\vec{u}", r"\vec{xe}")
    n = Notation(coordinates=["x"])
    assert n.vector([(sympy.Symbol("x_dot"), "x_I")], latex=True) == r"\dot{x}\,\vec{x}_{I}"


def test_a_multipliers_index_is_one_level_deep():
    """λ of constraint `rolling`, row x1: λ_{rolling, x₁}, not λ_{rolling_{x₁}} (an index of an index)."""
    n = Notation()
    assert n.symbol("lambda_rolling_x1", latex=True) == r"\lambda_{\mathrm{rolling},x_{1}}"
    assert n.symbol("lambda_length", latex=True) == r"\lambda_{\mathrm{length}}"
    assert n.symbol("x_I", latex=True) == "x_{I}"


def test_the_rate_of_a_word_keeps_its_name_instead_of_a_dot_on_its_last_letter() -> None:
    # URDF joints are words: "shouldeṙ" read as a dotted r; the rate is written as the user types it.
    n = Notation(("shoulder", "theta1", "x"), ("g",))
    assert n.symbol("shoulder_dot") == "shoulder_dot" and n.symbol("shoulder_ddot") == "shoulder_ddot"
    assert n.symbol("shoulder_dot", latex=True) == r"\dot{\mathrm{shoulder}}"
    assert n.symbol("theta1_dot") == "θ\u03071" and n.symbol("x_ddot") == "x\u0308"  # letters keep Newton's dots
