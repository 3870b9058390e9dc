"""The report's statements about mechanics, each tested against the equations, not only against its text.

Each test reads a French report of an example and checks one claim it makes — a constraint is (not) perfect,
a coordinate integrates, an effort derives from a potential, N = m g cos α, the oscillation plane turns at
−Ω sin λ … — against what the equations (or a hand derivation, SciPy, the model file) say.
"""

from __future__ import annotations

import math
import re
import xml.etree.ElementTree as ET
from functools import cache

import numpy as np
import pytest
import symengine as se
import sympy
import tomllib
from lagrangian_test_support import EXAMPLES_DIR, mutated_example, plain

import lagrangian
from lagrangian.output import report
from lagrangian.output._report.document import Math, Para, walk

URDF = EXAMPLES_DIR / "rrr_arm.urdf"


@cache
def _eom(name: str) -> lagrangian.EquationsOfMotion:
    return lagrangian.derive(lagrangian.load_model(EXAMPLES_DIR / name))


@cache
def _report(name: str, verification: bool = False, small: bool = False):  # type: ignore[no-untyped-def]
    return report(_eom(name), lang="fr", verification=verification or None, small_motions=True if small else None)


def _words(r, key: str) -> str:  # type: ignore[no-untyped-def]
    """A section's words and inline mathematics ($…$), in plain spacing."""
    out = []
    for b in walk(r.document.section(key).blocks):
        runs = b.runs if isinstance(b, Para) else [x for item in b.items for x in item] if hasattr(b, "items") else []
        out.append("".join(x if isinstance(x, str) else f"${x.latex}$" for x in runs))
        if hasattr(b, "equations"):
            out += [" ".join(eq.lines) for eq in b.equations]
        if hasattr(b, "rows"):  # a table: its cells, a row a line
            out += [" | ".join("".join(x if isinstance(x, str) else f"${x.latex}$" for x in cell) for cell in row)
                    for row in b.rows]
    return plain("\n".join(out))


def _paras(r, key: str) -> list[tuple[str, list[str]]]:  # type: ignore[no-untyped-def]
    """(words, inline formulas) of each paragraph of a section."""
    return [(plain("".join(x for x in b.runs if isinstance(x, str))), [x.latex for x in b.runs if isinstance(x, Math)])
            for b in walk(r.document.section(key).blocks) if isinstance(b, Para)]


# -- a damped joint is not perfect; the theorems list every effort their checks use -------------------------------
@pytest.mark.slow
def test_damped_urdf_joints_are_not_called_perfect_and_their_damping_is_in_q_nc():
    eom = _eom("rrr_arm.urdf")
    damping = {j.get("name"): float(j.find("dynamics").get("damping"))
               for j in ET.parse(URDF).getroot().iter("joint") if j.find("dynamics") is not None}
    assert damping == {"waist": 0.5, "shoulder": 0.5, "elbow": 0.2}
    for q, eq in zip(eom.q, eom.equations, strict=True):  # the file's damping is −c q̇ in Q_nc of that joint's equation
        rate = se.Symbol(f"{q}_dot")
        assert float(eq.Q_nc.diff(rate)) == pytest.approx(-damping[str(q)])
    step1 = _words(_report("rrr_arm.urdf"), "step1")
    assert step1.count("n'est pas parfaite") == 3 and "Elle est parfaite" not in step1
    assert "frottement visqueux « amortissement des liaisons »" in step1
    # Without damping, the same pivots are perfect: their Q_nc holds the motors' τ only (no rate).
    undamped = lagrangian.derive(lagrangian.load_urdf(URDF, damping=False))
    assert all(not eq.Q_nc.diff(se.Symbol(f"{q}_dot")).free_symbols and eq.Q_nc.diff(se.Symbol(f"{q}_dot")) == 0
               for q, eq in zip(undamped.q, undamped.equations, strict=True))
    step1 = plain(" ".join(x for b in walk(report(undamped, lang="fr").document.section("step1").blocks)
                           if isinstance(b, Para) for x in b.runs if isinstance(x, str)))
    assert step1.count("Elle est parfaite (sans frottement") == 3 and "n'est pas parfaite" not in step1


@pytest.mark.slow
def test_the_stated_theorems_list_the_actuators_and_damping_their_projections_use():
    eom = _eom("rrr_arm.urdf")
    v = lagrangian.verify(eom)
    by_power = {f.name for f in eom.loads if f.name in v.virtual_power_loads and any(x != 0 for x in f.Q)}
    assert by_power == {"actuators", "joint_damping"}  # what the checks add to each projection
    check = _words(_report("rrr_arm.urdf", verification=True), "check")
    statements = [line for line in check.splitlines() if r"\vec{\delta}_{" in line]
    assert len(statements) == 3
    for line in statements:
        assert r"(\text{actionneurs})" in line and r"(\text{amortissement des liaisons})" in line
    assert "donnés par leurs composantes généralisées" in check
    assert "sauf leurs frottements" in check  # the damped joints' actions do not all drop out


# -- rolling without slipping: perfect, and adherent -------------------------------------------------------------
@pytest.mark.slow
@pytest.mark.parametrize("name", ["rolling_coin.toml", "whipple_bicycle.toml"])
def test_a_rolling_contact_is_perfect_without_being_frictionless(name):
    """The contact's principal constraint (the coin kept upright on the plane, the bicycle's placement) is perfect
    because its actions do no virtual power; the tangential action, adherence, is the rolling reaction."""
    step1 = _words(_report(name), "step1")
    # Only a hinge (the bicycle's rear hub) may be called frictionless; no contact is.
    denied = step1.count("Ce n'est pas un contact sans frottement")
    assert denied <= 1 and step1.count("sans frottement") - denied == step1.count("Elle est parfaite (sans frottement, $")
    assert "supposée parfaite (sans frottement)" not in step1 and "adhérence" in step1
    assert "sans frottement" not in _words(_report(name), "step3")


def test_the_coins_contact_must_supply_a_tangential_force_the_adherence():
    """R_I = λ1 x1 + λ2 y1 (step 7) is horizontal and, along the model's initial motion, not zero: the plane must
    pull the coin sideways, which a frictionless contact cannot do."""
    eom = _eom("rolling_coin.toml")
    from lagrangian.dynamics import multiplier_formulas

    formulas = multiplier_formulas(eom)
    model = eom.model
    values = {p.symbol: p.value for p in model.parameters}
    values |= {c.symbol: c.initial for c in model.coordinates} | {c.rate_symbol: c.rate for c in model.coordinates}
    lam = [float(f.xreplace({k: se.Float(v) for k, v in values.items()})) for f in formulas]
    # By hand: λ2 = m ψ̇ (ẋ cos ψ + ẏ sin ψ) = 0.01 × 2 × 1 (the centripetal force of the turning coin).
    assert lam[1] == pytest.approx(0.01 * 2 * 1) and abs(lam[1]) > 0
    reaction = next(r for r in eom.reactions if r.point is not None)
    z = eom.kinematics.frames.express(reaction.force, "R0")[2]
    assert se.expand(z) == 0  # tangential: the adherence
    assert "C'est la force d'adhérence au contact" in _words(_report("rolling_coin.toml"), "step1")


# -- the block on the incline: its one constraint, N by the resultant theorem, the stick condition --------------
def test_the_blocks_only_constraint_is_not_called_one_of_the_others():
    step5 = _words(_report("block_on_incline.toml"), "step5")
    assert "Les autres liaisons principales" not in step5
    assert "La liaison principale n'est pas parfaite, mais seul son frottement" in step5


def test_the_blocks_normal_force_is_derived_and_agrees_with_the_models():
    """N = m g cos α by hand (m γ(B)·z_I = 0: B stays on the incline; the weight's normal part is −m g cos α)."""
    m, g, alpha = sympy.symbols("m g alpha")
    by_hand = m * g * sympy.cos(alpha)
    step7 = _words(_report("block_on_incline.toml"), "step7")
    assert r"\Rightarrow\quad N = m g \cos\alpha" in step7
    assert r"m\,\vec{\gamma}(B/R_{0})\cdot\vec{z}_{I} = 0" in step7 and "que la loi de frottement du modèle" in step7
    model = lagrangian.load_model(EXAMPLES_DIR / "block_on_incline.toml")
    declared = next(x for x in model.loads if x.name == "friction").normal_force
    assert sympy.simplify(declared._sympy_() - by_hand) == 0


@pytest.mark.slow
def test_the_blocks_stick_condition_is_tan_alpha_below_fs_and_the_simulation_agrees(tmp_path):
    data = tomllib.loads((EXAMPLES_DIR / "block_on_incline.toml").read_text(encoding="utf-8"))
    alpha, fs = data["parameters"]["alpha"]["value"], data["parameters"]["f_s"]["value"]
    assert math.tan(alpha) < fs  # the model's block stays once stopped
    step7 = _words(_report("block_on_incline.toml"), "step7")
    assert r"\left|\tan\alpha\right| \le f_{s}" in step7 and "reste immobile" in step7
    assert f"{math.tan(alpha):.4f}".replace(".", ",") in step7
    steep = mutated_example(tmp_path, "block_on_incline.toml", "alpha = { value = 0.2,", "alpha = { value = 0.5,")
    eom = lagrangian.derive(lagrangian.load_model(steep))
    text = _words(report(eom, lang="fr"), "step7")
    assert "ne peut rester immobile et repart" in text  # tan 0.5 = 0.546 > 0.4
    for eq, stays in ((_eom("block_on_incline.toml"), True), (eom, False)):
        run = lagrangian.simulate(eq, 1.0, n_out=201)
        x = run.column("x")
        assert (abs(x[-1] - x[100]) < 1e-9) == stays  # stopped at t* ≈ 0.2 s: stays, or slides back down


# -- a cyclic coordinate with multipliers ----------------------------------------------------------------------
def test_a_coordinate_integrates_only_when_no_complementary_row_acts_on_it():
    """The coin: x, y, ψ, φ all have ∂L/∂q = 0 and Q_nc = 0; only ψ is free of the rows (a_{k,ψ} = 0), so only L(ψ)
    integrates: the report says it for ψ with that third condition, and says why x, y and φ do not integrate."""
    eom = _eom("rolling_coin.toml")
    symbols = ("x", "y", r"\psi", r"\varphi")
    integrates, driven = [], []
    for words, formulas in _paras(_report("rolling_coin.toml"), "integrals"):
        if "paramètre cyclique :" in words:
            assert "ne figure dans aucune équation de liaison complémentaire" in words
            integrates.append(symbols.index(formulas[0]))
        elif "mais cela ne suffit pas pour intégrer" in words:
            assert "une liaison complémentaire agit sur lui" in words
            driven.append(symbols.index(formulas[0]))
    assert integrates == [2] and sorted(driven) == [0, 1, 3]
    for i, eq in enumerate(eom.equations):
        cyclic = se.expand(eq.dT_dq - eq.dU_dq) == 0 and se.expand(eq.Q_nc) == 0
        rows_act = eq.multiplier_terms != 0 and se.expand(eq.multiplier_terms) != 0
        assert cyclic  # all four, which is why ∂L/∂q = 0 and Q_nc = 0 are not enough
        assert rows_act == (i in driven) and (not rows_act) == (i in integrates), eom.coordinates[i]


def test_a_cyclic_coordinate_driven_by_an_effort_integrates_only_while_the_effort_is_off():
    """The cart pushed by F(t): ∂L/∂x = 0, but Q_x,nc = F, so L(x) integrates (to p_x) only with the input off."""
    eom = _eom("inverted_pendulum_cart.toml")
    eq = eom.equation("x")
    assert se.expand(eq.dT_dq - eq.dU_dq) == 0 and eq.Q_nc == se.Symbol("F")
    off = {fi.name: fi for fi in lagrangian.first_integrals(eom)}  # the inputs' default: off
    assert set(off) == {"p_x", "E"} and "F = 0" in off["p_x"].reason
    # p_x is ∂T/∂ẋ, as a hand derivation of T = ½ (mc + m) ẋ² + m l ẋ θ̇ cos θ + ½ m l² θ̇² gives.
    x_dot, theta, theta_dot = se.symbols("x_dot theta theta_dot")
    m, mc, l = se.symbols("m mc l")
    difference = off["p_x"].expression - ((mc + m) * x_dot + m * l * theta_dot * se.cos(theta))
    for point in ({m: 0.3, mc: 1.1, l: 0.7, x_dot: 0.4, theta: 2.1, theta_dot: -1.3},
                  {m: 2.0, mc: 0.5, l: 1.5, x_dot: -3.0, theta: -0.4, theta_dot: 0.8}):
        assert abs(float(difference.xreplace({k: se.Float(v) for k, v in point.items()}))) < 1e-12
    assert lagrangian.first_integrals(eom, inputs={"F": "varying"}) == ()  # pushed: neither p_x nor E holds
    text = _words(report(eom, lang="fr"), "integrals")
    assert "F = 0" in text or r"F = 0" in text.replace("{", "").replace("}", "")


# -- actuators: given non-conservative efforts; constants derive from −C q ---------------------------------------
def test_input_torques_are_not_folded_into_the_potential_and_the_energy_is_the_mechanical_one():
    eom = _eom("rrr_arm.urdf")
    r = _report("rrr_arm.urdf")
    step4, step5 = _words(r, "step4"), _words(r, "step5")
    assert r"U_P(\text{actionneurs})" not in step4 and r"\tau" not in step4
    assert "« actionneurs » est commandé par" in step5 and "« actionneurs » dérive" not in step5
    balance = lagrangian.energy_balance(eom)
    taus = [p.symbol for p in eom.model.parameters if p.input]
    assert taus and not (set(balance.E.free_symbols) & set(taus))  # E = T + U_gravity: mechanical energy
    power = next(t.power for t in balance.terms if t.name == "actuators")
    assert se.expand(power - sum(t * qd for t, qd in zip(taus, eom.qd, strict=True))) == 0  # dE/dt holds Σ τ_j q̇_j


@pytest.mark.slow
def test_a_constant_couple_is_said_constant_and_derives_from_minus_c_theta(tmp_path):
    path = mutated_example(tmp_path, "double_pendulum.toml", "[loads]",
                           "[loads]\nmotor = { torque = \"C*R0.x\", on = \"S1\" }\n")
    text = path.read_text().replace("[parameters]", '[parameters]\nC = { value = 0.3, unit = "N*m" }')
    path.write_text(text)
    eom = lagrangian.derive(lagrangian.load_model(path))
    motor = next(f for f in eom.loads if f.name == "motor")
    theta, C = eom.q[0], se.Symbol("C")  # S1 turns by θ1 about x0
    assert se.expand(motor.potential + C * theta) == 0  # U = −C θ: −∂U/∂θ = C, the couple's Q
    step5 = _words(report(eom, lang="fr"), "step5")
    assert "« moteur » est constant ($C$ est une constante du problème) : il dérive" in step5


# -- the Foucault pendulum ------------------------------------------------------------------------------------------
def test_foucault_hangs_at_rest_along_the_apparent_vertical():
    """By hand: the attraction a plus the centrifugal acceleration Ω² OP⊥ at OP = −l u is −g u."""
    data = tomllib.loads((EXAMPLES_DIR / "foucault_pendulum.toml").read_text(encoding="utf-8"))
    p = {k: v["value"] for k, v in data["parameters"].items()}
    g, l, Om, lam = p["g"], p["l"], p["Omega"], p["lam"]
    u = np.array([0.0, 0.0, 1.0])  # in R_L (s, e, u): s south, u up
    z0 = np.array([-math.cos(lam), 0.0, math.sin(lam)])
    attraction = -(g - Om**2 * l * math.cos(lam) ** 2) * u + Om**2 * l * math.sin(lam) * math.cos(lam) * np.array(
        [1.0, 0.0, 0.0])
    OP = -l * u
    centrifugal = Om**2 * (OP - (OP @ z0) * z0)
    np.testing.assert_allclose(attraction + centrifugal, -g * u, atol=1e-12)
    eom = _eom("foucault_pendulum.toml")
    rest = {s: se.Integer(0) for s in (*eom.q, *eom.qd)}
    assert all(se.expand(f.xreplace(rest)) == 0 for f in eom.F)  # α = β = 0 is an equilibrium, for every Ω


def test_foucault_statement_names_what_it_uses_and_its_small_motions_precess_at_minus_omega_sin_lambda():
    r = _report("foucault_pendulum.toml", small=True)
    statement = _words(r, "system")
    assert "AP" not in statement and "OP = l" in statement and r"\mathrm{lat}" not in statement
    everything = "\n".join(_words(r, s.key) for s in r.document.sections)
    assert r"(\Sigma/E)" not in everything and r"R_{T}" in everything  # no frame E beside the energy E
    small = _words(r, "small motions")
    assert r"\omega_p = \frac{G_{12}}{2\, M_{11}} = -\Omega \sin\lambda" in small
    assert "−0,1414" in small and r"s = \pm" in small  # s for the eigenvalues: λ is the latitude
    from lagrangian.output._report.steps.precession import precession_rate

    so = lagrangian.linearize(_eom("foucault_pendulum.toml"), {"alpha": 0, "beta": 0}, symbolic=("m", "l", "g",
                                                                                               "Omega", "lam"))
    rate, order = precession_rate(so.second_order)
    assert str(order) == "Omega"
    assert sympy.simplify(rate._sympy_() + sympy.Symbol("Omega") * sympy.sin(sympy.Symbol("lam"))) == 0


@pytest.mark.slow
def test_larmor_precession_rate_is_what_the_linear_motion_does():
    """μ q̈ + G q̇ + κ q = 0 integrated by SciPy: the major axis of the oscillation turns at G₁₂/(2μ)."""
    from scipy.integrate import solve_ivp

    from lagrangian.output._report.steps.precession import precession_rate

    mu, gamma, kappa = 2.0, -0.3, 50.0

    class Form:
        coordinates = ("a", "b")
        M = se.DenseMatrix([[mu, 0], [0, mu]])
        G = se.DenseMatrix([[0, gamma], [-gamma, 0]])
        K = se.DenseMatrix([[kappa, 0], [0, kappa]])
        D = N = se.zeros(2, 2)

    rate, order = precession_rate(Form)
    assert order is None and float(rate) == pytest.approx(gamma / (2 * mu))

    def rhs(t, y):
        q, v = y[:2], y[2:]
        return [*v, *(-(np.array([[0, gamma], [-gamma, 0]]) @ v + kappa * q) / mu)]

    t = np.linspace(0, 40, 40001)
    y = solve_ivp(rhs, (0, 40), [1.0, 0.0, 0.0, 0.0], t_eval=t, rtol=1e-11, atol=1e-12).y
    r = np.hypot(y[0], y[1])
    ends = np.flatnonzero((r[1:-1] >= r[:-2]) & (r[1:-1] > r[2:])) + 1
    plane = np.unwrap(2 * np.arctan2(y[1][ends], y[0][ends])) / 2
    assert np.polyfit(t[ends], plane, 1)[0] == pytest.approx(gamma / (2 * mu), rel=1e-3)


# -- the entrainment potential's conditions ----------------------------------------------------------------------
def test_the_entrainment_potential_is_said_to_exist_because_omega_is_constant_and_o_fixed(tmp_path):
    eom = _eom("bead_rotating_hoop.toml")
    kin = eom.kinematics
    assert kin.frame_omega_rate.is_zero() and kin.origin_acceleration.is_zero()
    step4 = _words(_report("bead_rotating_hoop.toml"), "step4")
    assert "Cette énergie potentielle existe parce que la rotation" in step4 and "étant fixe dans" in step4
    # Ω(R1/R0) = 2 Ω t z0: dΩ/dt ≠ 0, so "because the rotation is constant" would be false; the report does not
    # say it (the potential still exists here: dΩ/dt ∧ OP is normal to the hoop, so it does no virtual work).
    path = mutated_example(tmp_path, "bead_rotating_hoop.toml", '"Omega*t"', '"Omega*t^2"')
    accelerating = lagrangian.derive(lagrangian.load_model(path))
    assert not accelerating.kinematics.frame_omega_rate.is_zero()
    assert "Cette énergie potentielle existe" not in _words(report(accelerating, lang="fr"), "step4")


# -- the statement says which way z0 points ------------------------------------------------------------------------
@pytest.mark.slow
@pytest.mark.parametrize(("name", "down"), [("whipple_bicycle.toml", True), ("lagrange_top.toml", False)])
def test_the_statement_says_whether_z0_points_up_or_down(name, down):
    data = tomllib.loads((EXAMPLES_DIR / name).read_text(encoding="utf-8"))
    field = next(v["gravity"] for v in data["loads"].values() if "gravity" in v)
    assert field.replace(" ", "") == ("g*R0.z" if down else "-g*R0.z")  # the model file's own words
    statement = _words(_report(name), "system")
    assert ("verticale descendante" if down else "verticale ascendante") in statement


# -- a check too long to print is written member by member ---------------------------------------------------------
def test_summarized_checks_say_what_was_compared(monkeypatch):
    from functools import partial

    from lagrangian.output._report import build, size

    monkeypatch.setattr(size, "SMALL_OPS", 4)
    monkeypatch.setattr(build, "SizeGate", partial(size.SizeGate, max_ops=12))
    r = report(_eom("double_pendulum.toml"), lang="fr", verification=True)
    check = _words(r, "check")
    assert "trop longue pour être écrite ici" in check  # the projections are summarized here
    for line in check.splitlines():
        if r"\checkmark" in line:
            assert r"\rangle" not in line, line  # never ⟨N termes⟩ = … ✓
    assert r"\Gamma^{\mathrm{NE}}_{\theta_{1}} - \left(\frac{d}{dt}" in check
    assert "redonne" in check


# -- robots in French ----------------------------------------------------------------------------------------------
def test_a_robots_french_report_has_q_k_units_decimals_and_no_code_marks():
    r = _report("rrr_arm.urdf")
    md = r.markdown()
    assert r"\dot{\mathrm{" not in md and "`waist`" not in md and "\\`" not in md
    assert r"m_{\mathrm{column}} = 8\ \mathrm{kg}" in md and r"\frac{17}{250}" not in md and "0{,}068" in md
    assert r"\frac{1}{2} 8" not in md and r"\frac{1}{2} m_{\mathrm{column}}\,\vec{V}^{2}" in md
    assert "| q₁ |" not in md and r"$`q_{1}`$ | waist |" in md  # the joints' names beside q_k
    assert "limites [−3,1 ; 3,1] rad" in plain(md).replace("\\[", "[").replace("\\]", "]")
    statement = _words(r, "system")
    assert "Entrées (commandes, fonctions du temps données)" in statement
    assert re.search(r"\\tau_\{1\}`?\$?[^|]*\| 0 \|", md) is None  # an input has no value in the constants' table
