"""`lagrangian.equilibria` against closed forms worked by hand, and a numeric case against a scan.

* Bead on the hoop turning at Ω (examples/bead_rotating_hoop.toml): in the hoop's frame
  m R² θ̈ = −m g R sinθ + m R² Ω² sinθ cosθ, so θ = 0, θ = π, and cosθ = g/(R Ω²) when R Ω² > g.
* Simple pendulum: sinθ = 0.
* Double pendulum of two rods, θ2 relative to rod 1: U = −(m1 l1/2 + m2 l1) g cosθ1 −
  m2 g l2/2 cos(θ1 + θ2), so sinθ1 = 0 and sin(θ1 + θ2) = 0: four equilibria.
* Cart on a spring with a pendulum: k x = 0 (the spring's length |x + l0| = l0: x = 0 or −2 l0),
  sinθ = 0.
* Pendulum with a torsion spring of rest angle α: −k(θ − α) − m g l sinθ = 0 has no closed form;
  its roots are counted and bracketed by a sign-change scan and `scipy.optimize.brentq`.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
import symengine as se
import sympy
from scipy import optimize

import lagrangian
from lagrangian.analysis import EquilibriumError

ROOT = Path(__file__).resolve().parents[2]


def derive(name: str) -> lagrangian.EquationsOfMotion:
    return lagrangian.derive(lagrangian.load_model(ROOT / "examples" / f"{name}.toml"))


def points(found, *names):  # type: ignore[no-untyped-def]
    rows = sorted(tuple(round(e.numeric[n], 9) for n in names) for e in found)
    return [r[0] for r in rows] if len(names) == 1 else rows


# -- bead on the rotating hoop ---------------------------------------------------------------------
@pytest.mark.slow
def test_bead_above_the_critical_rate_has_four_equilibria() -> None:
    eom = derive("bead_rotating_hoop")  # R = 0.5, g = 9.81, Omega = 6: R Ω² = 18 > g
    found = lagrangian.equilibria(eom)
    a = math.acos(9.81 / (0.5 * 36))
    assert points(found, "theta") == sorted(round(x, 9) for x in (0.0, math.pi, a, -a))
    assert all(e.closed_form and e.residual < 1e-12 for e in found)
    tilted = [e for e in found if e.condition is not None]
    assert len(tilted) == 2
    for e in tilted:
        assert e.exists is True
        assert e.condition_text == "Omega**2*R > g"
    upright = [e for e in found if e.condition is None]
    assert sorted(str(e.values["theta"]) for e in upright) == ["0", "pi"]


@pytest.mark.slow
def test_bead_below_the_critical_rate_has_two() -> None:
    eom = derive("bead_rotating_hoop")
    found = lagrangian.equilibria(eom, parameters={"Omega": 2.0})  # R Ω² = 2 < g
    assert points(found, "theta") == [0.0, round(math.pi, 9)]
    every = lagrangian.equilibria(eom, parameters={"Omega": 2.0}, all_branches=True)
    assert [e.exists for e in every].count(False) == 2


@pytest.mark.slow
def test_bead_at_the_critical_rate_the_double_root_is_theta_zero() -> None:
    # R Ω² = g: cosθ = 1 is θ = 0, already listed; the tilted branch needs R Ω² > g strictly.
    eom = derive("bead_rotating_hoop")
    exact = {"R": 1.0, "g": 4.0, "Omega": 2.0}  # R Ω² = g exactly in floating point
    found = lagrangian.equilibria(eom, parameters=exact)
    assert points(found, "theta") == [0.0, round(math.pi, 9)]
    assert all(e.condition is None for e in found)
    every = lagrangian.equilibria(eom, parameters=exact, all_branches=True)
    assert sorted(e.exists for e in every) == [False, False, True, True]


# -- pendulums ---------------------------------------------------------------------------------------
def test_simple_pendulum_sin_theta_zero() -> None:
    found = lagrangian.equilibria(derive("simple_pendulum"))
    assert points(found, "theta") == [0.0, round(math.pi, 9)]
    assert all(e.closed_form and e.condition is None for e in found)


@pytest.mark.slow
def test_double_pendulum_four_equilibria() -> None:
    found = lagrangian.equilibria(derive("double_pendulum"))
    pi = round(math.pi, 9)
    # down-down, down-up (θ2 = π relative), up-down (θ1 = π, θ1 + θ2 ≡ 0), up-up (θ1 = π, θ2 = 0)
    assert points(found, "theta1", "theta2") == sorted([(0.0, 0.0), (0.0, pi), (pi, pi), (pi, 0.0)])
    assert all(e.residual < 1e-12 for e in found)


@pytest.mark.slow
def test_cart_pendulum_with_a_spring() -> None:
    eom = derive("cart_pendulum")  # l0 = 0.5
    found = lagrangian.equilibria(eom)
    pi = round(math.pi, 9)
    assert points(found, "x", "theta") == sorted([(0.0, 0.0), (0.0, pi), (-1.0, 0.0), (-1.0, pi)])
    assert {str(e.values["x"]) for e in found} == {"0", "-2*l0"}
    near = lagrangian.equilibria(eom, ranges={"x": (-0.4, 2.0)})
    assert points(near, "x", "theta") == [(0.0, 0.0), (0.0, pi)]


@pytest.mark.slow
def test_constrained_pendulum_uses_the_multiplier() -> None:
    # x² + y² = l² kept complementary: F + λ ∇f = 0 gives x = 0, y = ±l.
    found = lagrangian.equilibria(derive("pendulum_tension"))
    assert points(found, "x", "y") == [(0.0, -0.5), (0.0, 0.5)]


TORSION = """\
[parameters]
m = 1.0
l = 1.0
g = 1.0
k = 0.1
alpha = 0.3

[coordinates]
theta = {}

[frames]
R1 = { from = "R0", rotation = ["theta", "z"] }

[particles.P]
mass = "m"
position = "l*R1.x"

[loads]
weight = { gravity = "g*R0.x" }
torsion = { potential = "1/2*k*(theta - alpha)^2" }
"""


@pytest.mark.slow
@pytest.mark.parametrize("given", [True, False])
def test_torsion_pendulum_numeric_roots_match_a_sign_change_scan(given: bool) -> None:
    # θ is not an angle here (θ − α is not 2π-periodic): without a range it is searched from starting points
    # over every scale, and the search says so.  Every root has |θ| ≤ 10.3 (|0.1 (θ − 0.3)| ≤ 1).
    eom = lagrangian.derive(lagrangian.parse_model(TORSION))
    lo, hi = -12.0, 12.0
    found = lagrangian.equilibria(eom, ranges={"theta": (lo, hi)} if given else None)
    region = found.search.regions[0]
    assert (region.kind, region.bounds) == (("range", (lo, hi)) if given else ("scales", (-math.inf, math.inf)))
    assert found.search.unbounded == (() if given else ("theta",))

    def f(th: float) -> float:  # Q_θ = −k(θ − α) − m g l sinθ, written here from the physics
        return -0.1 * (th - 0.3) - math.sin(th)

    grid = np.linspace(lo, hi, 200001)
    values = np.array([f(x) for x in grid])
    brackets = np.nonzero(np.sign(values[:-1]) != np.sign(values[1:]))[0]
    expected = sorted(optimize.brentq(f, grid[i], grid[i + 1], xtol=1e-14) for i in brackets)
    assert len(expected) == 5  # the line −0.1(θ − 0.3) meets sinθ five times in [−12, 12]
    got = sorted(e.numeric["theta"] for e in found)
    assert len(got) == len(expected)
    assert np.allclose(got, expected, atol=1e-9)
    assert all(not e.closed_form and e.residual < 1e-10 for e in found)


# -- refusals ------------------------------------------------------------------------------------------
def test_time_dependent_model_is_refused() -> None:
    with pytest.raises(EquilibriumError) as info:
        lagrangian.equilibria(derive("kapitza_pendulum"))
    assert "depends on t explicitly" in info.value.message and "theta" in info.value.message


def test_unknown_names_are_refused() -> None:
    eom = derive("simple_pendulum")
    with pytest.raises(EquilibriumError, match="`w` is not a parameter"):
        lagrangian.equilibria(eom, parameters={"w": 1.0})
    with pytest.raises(EquilibriumError, match="`y` in the ranges is not a coordinate"):
        lagrangian.equilibria(eom, ranges={"y": (0.0, 1.0)})


def test_a_continuum_of_equilibria_is_reported_free() -> None:
    # The rolling coin on a level plane stays at rest anywhere: every coordinate is free.
    found = lagrangian.equilibria(derive("rolling_coin"))
    assert len(found) == 1 and set(found[0].free) == {"x", "y", "psi", "phi"}


def test_bead_symbolic_rate_keeps_the_condition() -> None:
    text = (ROOT / "examples" / "bead_rotating_hoop.toml").read_text()
    assert 'Omega = { value = 6.0, unit' in text
    eom = lagrangian.derive(lagrangian.parse_model(text.replace('Omega = { value = 6.0, unit', 'Omega = { unit')))
    found = lagrangian.equilibria(eom)
    tilted = [e for e in found if e.condition is not None]
    assert len(found) == 4 and len(tilted) == 2
    g, R, Om = (se.Symbol(n) for n in ("g", "R", "Omega"))
    expected = se.acos(g / (R * Om**2))
    assert sorted(str(e.values["theta"]) for e in tilted) == sorted([str(expected), str(-expected)])
    for e in tilted:
        assert e.exists is None and e.numeric is None
        names = {s.name: s for s in e.condition.free_symbols}
        at = {names["g"]: 9.81, names["R"]: 0.5}
        assert bool(e.condition.subs({**at, names["Omega"]: 4.5})) is (0.5 * 4.5**2 > 9.81)  # 10.125 > 9.81
        assert bool(e.condition.subs({**at, names["Omega"]: 4.4})) is (0.5 * 4.4**2 > 9.81)  # 9.68 < 9.81


def test_no_closed_form_and_a_missing_value_is_refused() -> None:
    eom = lagrangian.derive(lagrangian.parse_model(TORSION.replace("k = 0.1", "k = {}")))
    with pytest.raises(EquilibriumError) as info:
        lagrangian.equilibria(eom, ranges={"theta": (-1.0, 1.0)})
    assert "parameter `k` has no value" in info.value.message and "--set k=" in info.value.fix
    found = lagrangian.equilibria(eom, parameters={"k": 0.1}, ranges={"theta": (-1.0, 1.0)})
    root = optimize.brentq(lambda th: -0.1 * (th - 0.3) - math.sin(th), -1.0, 1.0, xtol=1e-14)
    assert len(found) == 1 and found[0].numeric["theta"] == pytest.approx(root, abs=1e-9)


def test_the_numeric_search_fills_in_what_the_closed_form_missed(monkeypatch) -> None:
    # SymPy's `solve` alone loses θ = π of the bead (tangent half-angle); were a closed form to
    # miss a root, the search must add it, numeric. Simulated by a closed form giving θ = 0 only.
    import lagrangian.analysis._equilibria as module

    monkeypatch.setattr(module, "closed_form", lambda *args: [{"theta": sympy.Integer(0)}])
    found = lagrangian.equilibria(derive("simple_pendulum"))
    assert [(e.closed_form, round(e.numeric["theta"], 9)) for e in found] == [(True, 0.0), (False, round(math.pi, 9))]


# -- dry friction: a rest holds while the friction it needs stays in the cone -------------------
# Block on an incline of angle α with exact Coulomb friction (examples/block_on_incline.toml):
# at rest the contact sticks and the friction holds m g sin α against N = m g cos α, so every
# x is an equilibrium if and only if |tan α| ≤ f_s (Coulomb's law of adherence).
@pytest.mark.parametrize("alpha", [0.2, 0.5, -0.3, -0.45])
def test_block_on_incline_rests_anywhere_iff_tan_alpha_is_at_most_f_s(alpha: float) -> None:
    found = lagrangian.equilibria(derive("block_on_incline"), parameters={"alpha": alpha}, all_branches=True)
    assert len(found) == 1 and found[0].free == ("x",)
    e = found[0]
    assert e.exists is (abs(math.tan(alpha)) <= 0.4)
    assert e.residual == 0.0  # the friction force is the multiplier of sticking, not 0/0
    sym = {s.name: s for s in e.condition.free_symbols}
    assert set(sym) == {"alpha", "f_s"}
    for a in np.linspace(-1.2, 1.2, 13):
        for fs in (0.1, 0.5, 1.0):
            assert bool(e.condition.subs({sym["alpha"]: a, sym["f_s"]: fs})) is (abs(math.tan(a)) <= fs)


def test_block_on_incline_without_enough_friction_has_no_rest(capsys: pytest.CaptureFixture[str]) -> None:
    assert lagrangian.equilibria(derive("block_on_incline"), parameters={"alpha": 0.5}) == ()
    from lagrangian.cli.main import main
    path = str(ROOT / "examples" / "block_on_incline.toml")
    assert main(["equilibria", path]) == 0
    out = capsys.readouterr().out
    assert "x any" in out and "tan" in out and "nan" not in out
    assert main(["equilibria", path, "--set", "alpha=0.5"]) == 0  # tan 0.5 = 0.55 > f_s = 0.4
    out = capsys.readouterr().out
    assert "none found" in out and "would be one if |tanα| ≤ f_s, which does not hold" in out


@pytest.mark.slow
def test_a_closed_form_with_no_value_at_the_parameters_is_skipped(tmp_path):
    # tools/fuzz.py seed 108, case 12483: inverted_pendulum_cart with its particles' names swapped (the force
    # F then acts on the bob).  One closed-form branch, 2 arctan((m g − √(m² g² + F²))/F), is 0/0 at F = 0;
    # its NaN reached round() (ValueError).  It has no value there; the rests are θ = 0 and θ = π.
    text = (ROOT / "examples" / "inverted_pendulum_cart.toml").read_text(encoding="utf-8")
    assert text.count("[particles.C]") == 1 and text.count("[particles.P]") == 1
    swapped = text.replace("[particles.C]", "[particles.@]").replace("[particles.P]", "[particles.C]")
    path = tmp_path / "swapped.toml"
    path.write_text(swapped.replace("[particles.@]", "[particles.P]"), encoding="utf-8")
    found = lagrangian.equilibria(lagrangian.derive(lagrangian.load_model(path)))
    thetas = sorted(abs(e.numeric["theta"]) for e in found if e.numeric is not None)
    assert thetas == pytest.approx([0.0, math.pi], abs=1e-12)
