"""Rows chosen by the engine: a vector constraint written in any frame.

`no_slip` written in the disk's own frame (or the lean frame) gives three rows of rank two;
the engine keeps an independent set by itself and says which.  Truth: the formulation
that worked before, rolling written in the heading frame R1 (itself checked against
SymPy's KanesMethod for the coin in test_constraints.py): the same accelerations q̈ and
the same reaction's generalized force Aᵀλ at random consistent states, from the full
system [M −Aᵀ; A 0][q̈; λ] = [F; −c].
"""

from __future__ import annotations

import numpy as np
import pytest
import symengine as se
from lagrangian_test_support import EXAMPLES_DIR, plain

import lagrangian
from lagrangian.errors import ModelError

RNG_SEED = 20261125

LEANING_DISK = """
[parameters]
m = 1.0
r = 0.3
g = 9.81
[coordinates]
x = { initial = 0.0, rate = 0.0 }
y = { initial = 0.0, rate = 0.0 }
psi = { initial = 0.0, rate = 0.0 }
theta = { initial = 0.2, rate = 0.0 }
phi = { initial = 0.0, rate = 0.0 }
[frames]
R1 = { from = "R0", rotation = ["psi", "z"] }
R2 = { from = "R1", rotation = ["theta", "x"] }
R3 = { from = "R2", rotation = ["phi", "y"] }
[points]
I = "x*R0.x + y*R0.y"
[bodies.S]
frame = "R3"
mass = "m"
center = "x*R0.x + y*R0.y + r*R2.z"
inertia = { at = "G", frame = "R3", diagonal = ["m*r^2/4", "m*r^2/2", "m*r^2/4"] }
[loads]
weight = { gravity = "-g*R0.z" }
[constraints]
"""


def derive(text: str) -> lagrangian.EquationsOfMotion:
    return lagrangian.derive(lagrangian.parse_model(text, source="model.toml"))


def example(name: str, frame: str) -> lagrangian.EquationsOfMotion:
    text = (EXAMPLES_DIR / name).read_text(encoding="utf-8")
    assert 'frame = "R1", description' in text
    return derive(text.replace('frame = "R1", description', f'frame = "{frame}", description'))


def _numeric(e: se.Basic, values: dict[se.Basic, float]) -> float:
    return float(e.xreplace({k: se.RealDouble(v) for k, v in values.items()}))


def accelerations(eom: lagrangian.EquationsOfMotion, q: np.ndarray, qd: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """q̈ and Aᵀλ from [M −Aᵀ; A 0][q̈; λ] = [F; −c] at the state (q, q̇), parameters at their values."""
    values = {p.symbol: p.value for p in eom.model.parameters}
    values |= dict(zip(eom.q, q, strict=True)) | dict(zip(eom.qd, qd, strict=True)) | {eom.t: 0.0}
    n, m = len(eom.q), len(eom.constraints)
    M = np.array([[_numeric(e, values) for e in row] for row in eom.M])
    F = np.array([_numeric(e, values) for e in eom.F])
    A = np.array([[_numeric(e, values) for e in r.coefficients] for r in eom.constraints])
    c = np.array([_numeric(r.bias, values) for r in eom.constraints])
    K = np.block([[M, -A.T], [A, np.zeros((m, m))]])
    x = np.linalg.solve(K, np.concatenate([F, -c]))
    return x[:n], A.T @ x[n:]


def same_motion(reference: lagrangian.EquationsOfMotion, other: lagrangian.EquationsOfMotion, states: int = 3) -> None:
    assert [str(s) for s in other.q] == [str(s) for s in reference.q]
    rng = np.random.default_rng(RNG_SEED)
    values = {p.symbol: p.value for p in reference.model.parameters}
    n = len(reference.q)
    for _ in range(states):
        q = rng.uniform(-1.5, 1.5, n)
        qd = rng.uniform(-2.0, 2.0, n)
        # Velocities that satisfy the reference's rows: q̇ projected on the null space of A (b = 0 here).
        point = values | dict(zip(reference.q, q, strict=True)) | {reference.t: 0.0}
        A = np.array([[_numeric(e, point) for e in r.coefficients] for r in reference.constraints])
        qd = qd - np.linalg.pinv(A) @ (A @ qd)
        qdd_ref, reaction_ref = accelerations(reference, q, qd)
        qdd, reaction = accelerations(other, q, qd)
        assert np.allclose(qdd, qdd_ref, rtol=1e-9, atol=1e-10), (qdd, qdd_ref)
        assert np.allclose(reaction, reaction_ref, rtol=1e-9, atol=1e-10), (reaction, reaction_ref)


@pytest.mark.parametrize("frame", ["R2", "R0"])
def test_upright_coin_rolling_written_in_any_frame(frame: str) -> None:
    reference = example("rolling_coin.toml", "R1")
    eom = example("rolling_coin.toml", frame)
    same_motion(reference, eom)
    if frame == "R2":  # the coin's own frame: rows x2, y1, z2 of rank 2, written in R1 instead
        assert [r.name for r in eom.constraints] == ["rolling_x1", "rolling_y1"]
        choice = eom.reactions[0].row_choice
        assert choice is not None and choice.declared_frame == "R2" and choice.rank == 2 and choice.frame == "R1"
        assert choice.declared_rows == ("rolling_x2", "rolling_y1", "rolling_z2")
        assert "rows chosen by the engine" in eom.reactions[0].note
    else:  # R0: two independent rows already, nothing chosen
        assert [r.name for r in eom.constraints] == ["rolling_x0", "rolling_y0"]
        assert eom.reactions[0].row_choice is None


def test_disk_on_an_incline_rolling_in_its_own_frame() -> None:
    reference = example("rolling_disk_incline.toml", "R1")
    eom = example("rolling_disk_incline.toml", "R2")
    same_motion(reference, eom)
    assert [r.name for r in eom.constraints] == ["rolling_x1"]
    # The closed form still holds: friction −⅓ m g sin α along x1.
    m, g, alpha = 1.0, 9.81, 0.3
    qdd, _ = accelerations(eom, np.zeros(2), np.zeros(2))
    assert qdd[0] == pytest.approx(2 / 3 * g * np.sin(alpha), rel=1e-12)
    lam = [p for p in eom.reactions[0].force_components]
    assert str(lam[0]) == "lambda_rolling_x1"
    del m


@pytest.mark.parametrize("frame", ["R3", "R2"])
def test_leaning_disk_rolling_in_the_disk_or_the_lean_frame(frame: str) -> None:
    reference = derive(LEANING_DISK + 'rolling = { no_slip = "I", on = "S", frame = "R1" }\n')
    assert [r.name for r in reference.constraints] == ["rolling_x1", "rolling_y1"]
    eom = derive(LEANING_DISK + f'rolling = {{ no_slip = "I", on = "S", frame = "{frame}" }}\n')
    choice = eom.reactions[0].row_choice
    assert choice is not None and choice.rank == 2 and len(choice.declared_rows) == 3
    assert choice.frame == "R1"  # the nearest ancestor where the vertical component vanishes identically
    same_motion(reference, eom)


def test_rows_chosen_by_pivoted_qr_when_no_frame_has_that_many_rows() -> None:
    base = """
[parameters]
k = 2.0
[coordinates]
x = { initial = 0.1, rate = 0.0 }
y = { initial = 0.1, rate = 0.0 }
[particles.P]
mass = "1"
position = "x*R0.x + y*R0.y"
[loads]
spring = { potential = "1/2*k*(x^2 + 3*y^2)" }
[constraints]
"""
    reference = derive(base + 'tie = { holonomic = "x - 2*y" }\n')
    eom = derive(base + 'tie = { holonomic = "(x - 2*y)*R0.x + 3*(x - 2*y)*R0.y" }\n')
    choice = eom.reactions[0].row_choice
    assert choice is not None and choice.frame is None and choice.rank == 1 and len(choice.kept) == 1
    assert "pivot" in choice.text
    same_motion(reference, eom)


def test_inconsistent_rows_are_refused() -> None:
    text = """
[coordinates]
x = { initial = 0.0, rate = 1.0 }
y = 0.0
[particles.P]
mass = "1"
position = "x*R0.x + y*R0.y"
[constraints]
drive = { holonomic = "(x - t)*R0.x + (x - 2*t)*R0.y" }
"""
    with pytest.raises(ModelError, match=r"rows of constraint `drive` .* are inconsistent") as exc:
        derive(text)
    assert exc.value.line == 9 and exc.value.fix


def test_rows_redundant_between_two_constraints_are_still_refused() -> None:
    text = LEANING_DISK.replace('[constraints]', '[constraints]\nroll1 = { no_slip = "I", on = "S", frame = "R1" }')
    text += 'roll2 = { no_slip = "I", on = "S", frame = "R3" }\n'
    with pytest.raises(ModelError, match=r"redundant: row `roll2_x1` is a combination of `roll1_x1`") as exc:
        derive(text)
    assert "axes" in exc.value.fix


def test_explicit_axes_are_kept_as_given() -> None:
    text = LEANING_DISK + 'rolling = { no_slip = "I", on = "S", frame = "R3", axes = ["x", "y", "z"] }\n'
    with pytest.raises(ModelError, match="the rows of constraint `rolling` kept by its `axes` are redundant") as exc:
        derive(text)
    assert "leave `axes` out" in exc.value.fix


@pytest.mark.slow
@pytest.mark.parametrize(("lang", "words"), [
    ("en", "Written in R2, the constraint “rolling without slipping at I” gives 3 rows of rank 2 only; the same "
           "vector is written along the axes of R1"),
    ("fr", "Écrite dans R2, la liaison « roulement sans glissement en I » donne 3 équations de rang 2 seulement"),
])
def test_the_report_says_which_rows_were_kept(tmp_path, lang: str, words: str) -> None:
    from lagrangian.cli.main import main

    text = (EXAMPLES_DIR / "rolling_coin.toml").read_text(encoding="utf-8")
    model = tmp_path / "coin.toml"
    model.write_text(text.replace('frame = "R1", description', 'frame = "R2", description'), encoding="utf-8")
    out = tmp_path / "coin.md"
    assert main(["report", str(model), "--format", "md", "--no-verify", "--lang", lang, "-o", str(out)]) == 0
    written = plain(out.read_text(encoding="utf-8"))  # French typography undone: the words are pinned here
    assert words in written and "rolling_x1" not in written  # the kept rows by their axes, not their identifiers
