"""A body declared free (`lagrangian.model._free`): what the declaration must say, and the errors when it does not."""

from __future__ import annotations

from pathlib import Path

import pytest

import lagrangian
from lagrangian.errors import ModelError
from lagrangian.model._free import free_joints

EXAMPLE = Path(__file__).resolve().parents[2] / "examples" / "tumbling_body.toml"

FREE = """
[parameters]
m = 1.0
A = 1.0
B = 2.0
C = 3.0
[coordinates]
x = { initial = 0.0, rate = 0.0 }
y = { initial = 0.0, rate = 0.0 }
z = { initial = 0.0, rate = 0.0 }
psi = { initial = 0.0, rate = 0.0 }
theta = { initial = 0.5, rate = 0.0 }
phi = { initial = 0.0, rate = 1.0 }
[frames]
R = { from = "R0", rotation = [["psi", "z"], ["theta", "x"], ["phi", "z"]] }
[bodies.S]
frame = "R"
free = true
mass = "m"
center = "x*R0.x + y*R0.y + z*R0.z"
inertia = { frame = "R", diagonal = ["A", "B", "C"] }
"""


def _error(text: str) -> ModelError:
    with pytest.raises(ModelError) as info:
        lagrangian.parse_model(text, source="free.toml")
    return info.value


def test_the_example_declares_one_free_body_with_its_six_coordinates() -> None:
    (joint,) = free_joints(lagrangian.load_model(EXAMPLE))
    assert (joint.body, joint.translation, joint.angles, joint.sequence) == (
        "S", ("x", "y", "z"), ("psi", "theta", "phi"), "zxz")
    assert joint.proper and joint.frame == "R"


def test_cardan_angles_and_an_offset_centre_are_a_free_body_too() -> None:
    text = FREE.replace('[["psi", "z"], ["theta", "x"], ["phi", "z"]]', '[["psi", "z"], ["theta", "y"], ["phi", "x"]]')
    text = text.replace('center = "x*R0.x + y*R0.y + z*R0.z"', 'center = "x*R0.x + y*R0.y + z*R0.z + 0.1*R.z"')
    (joint,) = free_joints(lagrangian.parse_model(text))
    assert joint.sequence == "zyx" and not joint.proper


#: A particle that keeps a coordinate in use when a mutation takes it from the free body.
USING = '\n[particles.P]\nmass = "m"\nposition = "{q}*R0.x"\n'


@pytest.mark.parametrize(("old", "new", "words", "using"), [
    ('diagonal = ["A", "B", "C"]', 'diagonal = ["0", "0", "0"]', "its inertia at G is zero", None),
    ('diagonal = ["A", "B", "C"]', 'diagonal = ["A", "B", "0"]', "the one about some axis is zero", None),
    ('R = { from = "R0", ', 'W = { from = "R0", rotation = ["0.1", "y"] }\nR = { from = "W", ', "is 4 rotations from R0", None),
    ('["theta", "x"]', '["theta", "z"]', "two successive rotations of its frame turn about the same axis", None),
    ('["theta", "x"]', '["0.3", "x"]', "each of the three rotations of a free body is", "theta"),
    ('center = "x*R0.x + y*R0.y + z*R0.z"', 'center = "x*R0.x + y*R0.y"', "the z component of its position", "z"),
    ('center = "x*R0.x + y*R0.y + z*R0.z"', 'center = "x*R0.x + y*R0.y + z*R0.z + x*R.z"', "moves in its own frame", None),
    ('center = "x*R0.x + y*R0.y + z*R0.z"', 'center = "x*R0.x + y*R0.y + psi*R0.z"', "serves twice", "z"),
    ('free = true', 'free = "yes"', "must be true or false", None),
    ('mass = "m"\n', '', "has no `mass`", None),
])
def test_a_free_body_that_is_not_one_is_refused_with_its_line(old: str, new: str, words: str, using: str | None
                                                              ) -> None:
    assert old in FREE
    error = _error(FREE.replace(old, new) + (USING.format(q=using) if using else ""))
    assert words in error.message, error.message
    assert error.file == "free.toml" and error.line is not None and error.symbol == "S"
    assert error.fix


@pytest.mark.slow
def test_a_free_body_without_its_inertia_values_is_checked_when_simulated() -> None:
    model = lagrangian.parse_model(FREE.replace("C = 3.0", "C = {}"))  # no value: nothing to check yet
    with pytest.raises(lagrangian.SimulationError, match="principal moment") as info:
        lagrangian.simulate(model, 1.0, parameters={"C": 0.0})
    assert "Free body `S`" in info.value.message
