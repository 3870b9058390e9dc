"""The public multiplier formulas and the redundant-constraint message (`lagrangian.dynamics`).

Closed forms (docs/constraints.md, sign conventions): the pendulum's rod pulls with the tension
T = −2 l λ = m (g cos θ + l θ̇²); the disk on the incline gets the friction λ = −⅓ m g sin α
along x1.  A redundant row is blamed on the rows it actually repeats, not on all before it.
"""

from __future__ import annotations

import pytest
import symengine as se
from lagrangian_test_support import EXAMPLES_DIR

import lagrangian
from lagrangian._identity import is_zero
from lagrangian.dynamics import multiplier_formulas
from lagrangian.errors import ModelError


def S(name: str) -> se.Symbol:
    return se.Symbol(name)


def eom_of(name: str) -> lagrangian.EquationsOfMotion:
    return lagrangian.derive(lagrangian.load_model(EXAMPLES_DIR / name))


def test_pendulum_multiplier_is_minus_the_tension_over_2l() -> None:
    eom = eom_of("pendulum_tension.toml")
    (lam,) = multiplier_formulas(eom)
    m, g, l, th, thd = (S(n) for n in ("m", "g", "l", "theta", "theta_dot"))
    on_circle = {S("x"): l * se.sin(th), S("y"): -l * se.cos(th),
                 S("x_dot"): l * se.cos(th) * thd, S("y_dot"): l * se.sin(th) * thd}
    assert is_zero(-2 * l * lam.xreplace(on_circle) - m * (g * se.cos(th) + l * thd**2))


def test_incline_friction_multiplier() -> None:
    (lam,) = multiplier_formulas(eom_of("rolling_disk_incline.toml"))
    assert is_zero(lam + S("m") * S("g") * se.sin(S("alpha")) / 3)


def test_no_formulas_without_complementary_constraints() -> None:
    assert multiplier_formulas(eom_of("simple_pendulum.toml")) is None


def test_a_row_that_repeats_one_row_of_a_vector_constraint_names_that_row_only() -> None:
    text = (EXAMPLES_DIR / "top_reaction.toml").read_text() + 'height = { holonomic = "zG - a*cos(theta)" }\n'
    with pytest.raises(ModelError) as exc:
        lagrangian.derive(lagrangian.parse_model(text, source="top.toml"))
    message = exc.value.message
    assert "row `height` is a combination of `pivot_z0` only" in message, message
    assert "pivot_x0" not in message and "pivot_y0" not in message
