"""`lagrangian.output.verification_text` and `verification_failure`: the Newton–Euler check as text.

The simple pendulum, P = −l z1 with R1 turned by θ about x0, by hand: V(P) = l θ̇ y1,
γ(P/R0) = l θ̈ y1 + l θ̇² z1 and z0 = sinθ y1 + cosθ z1, so the moment theorem at O on x0 is
m l² θ̈ = −m g l sinθ and the rod's action R = m γ(P/R0) + m g z0 =
(m l θ̈ + m g sinθ) y1 + (m l θ̇² + m g cosθ) z1.  A Lagrange equation with its right side's sign
flipped is written ✗ with what the theorems give instead.
"""

from __future__ import annotations

import dataclasses

import pytest
from lagrangian_test_support import EXAMPLES_DIR

import lagrangian
from lagrangian.analysis import check_trajectory, reactions, verify
from lagrangian.errors import ModelError
from lagrangian.output import verification_failure, verification_text


@pytest.fixture(scope="module")
def pendulum():
    return lagrangian.derive(lagrangian.load_model(EXAMPLES_DIR / "simple_pendulum.toml"))


def test_the_pendulum_checked_and_its_reaction_are_the_hand_derivations(pendulum):
    v = verify(pendulum)
    lines = verification_text(v, reactions(v)).splitlines()
    assert lines[0] == "Newton–Euler check of Simple pendulum (R0 Galilean)"
    assert "  P (particle): m γ(P/R0) = weight + R" in lines
    assert lines[lines.index("  L(θ) ⇔ moment theorem at O projected on x0:") + 1] == "      m l² θ̈ = −m l g sinθ ✓"
    assert "          = (m l θ̈ + m g sinθ) y1 + (m g cosθ + m l θ̇²) z1    (in R1: x0, y1, z1)" in lines
    assert lines[-1] == "The Lagrange equation agrees with the Newton–Euler theorems ✓"
    assert verification_failure(v) is None
    # Without reactions the section is left out; an error in their place is said as the reason.
    assert not any(line.startswith("Constraint reactions") for line in verification_text(v).splitlines())
    why = verification_text(v, ModelError("the reactions need the mass of body `B`", fix="give it a mass"))
    assert "\nConstraint reactions: not computed: the reactions need the mass of body `B`.\n  tip: give it a mass\n" \
        in why


def test_a_wrong_sign_is_marked_and_said_in_one_sentence(pendulum):
    flipped = tuple(dataclasses.replace(eq, rhs=-eq.rhs) for eq in pendulum.equations)
    v = verify(dataclasses.replace(pendulum, equations=flipped))
    lines = verification_text(v).splitlines()
    assert "      m l² θ̈ = −m l g sinθ ✗" in lines and "      ✗ but −∂U/∂θ + Q_θ = m l g sinθ" in lines
    assert lines[-1] == "The Lagrange equation disagrees with the Newton–Euler theorems ✗"
    assert verification_failure(v) == ("L(theta) does not agree with the moment theorem at O projected on x0: its "
                                       "right side is `m l g sinθ`, the theorems give `−m l g sinθ` (difference "
                                       "`−2 m l g sinθ`).")


def test_the_residuals_along_a_motion_are_judged_against_the_tolerance(pendulum):
    v = verify(pendulum)
    res = check_trajectory(v, lagrangian.simulate(pendulum, 1.0, n_out=11))
    text = verification_text(v, along=res)
    assert "Along a simulated motion (t from 0 to 1, 11 states, q̈ from the trajectory)" in text
    assert "\n  all within 1e-09 ✓\n" in text
    what, worst = res.worst()
    if worst > 0:  # rounding: a tolerance of 0 is exceeded
        assert f"\n  {what} is off by {worst:.3g}, more than 0 ✗\n" in verification_text(v, along=res, tolerance=0.0)
