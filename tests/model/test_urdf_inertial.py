"""load_urdf(..., inertial_parameters=True): each body's ten standard parameters, checked against Pinocchio.

Pinocchio's ``Inertia.toDynamicParameters()`` gives, for the body of each joint (its child link with
the links welded to it), m, m c and the inertia about the joint frame's origin, in that frame: the
values our parameters must take.  The motion must be the one of the file's numbers.
"""

import warnings

import numpy as np
import pytest
from lagrangian_test_support import EXAMPLES_DIR
from urdf_robots import DOUBLE_PENDULUM, SPATIAL_ARM, Ours

import lagrangian
from lagrangian.model.urdf import INERTIAL_PARAMETERS, inertial_parameter_names, parse_urdf

pin = pytest.importorskip("pinocchio", reason="Pinocchio (`pip install pin`) is the referee of these tests")

RRR_ARM = (EXAMPLES_DIR / "rrr_arm.urdf").read_text(encoding="utf-8")
#: Pinocchio's order of the ten parameters, as our names' prefixes.
PIN_ORDER = ("m", "mx", "my", "mz", "Ixx", "Ixy", "Iyy", "Ixz", "Iyz", "Izz")


def _load(text, **options):
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return parse_urdf(text, **options)


@pytest.mark.parametrize("text, bodies", [
    (RRR_ARM, ["column", "upper_arm", "forearm"]),
    (DOUBLE_PENDULUM, ["rod1", "rod2"]),
    (SPATIAL_ARM, ["l1", "l2", "l4"]),  # l3 turns about a general axis: its frame is not the link's
], ids=["rrr_arm", "double_pendulum", "spatial_arm"])
def test_inertial_parameters_are_pinocchios_dynamic_parameters(text, bodies):
    model = _load(text, inertial_parameters=True)
    names = inertial_parameter_names(model)
    peer = pin.buildModelFromXML(text)
    for body in bodies:
        joint = next(j for j in range(1, peer.njoints) if peer.frames[peer.getFrameId(body)].parentJoint == j)
        expected = dict(zip(PIN_ORDER, peer.inertias[joint].toDynamicParameters(), strict=True))
        values = {prefix: model.parameter_values[name] for prefix, name in zip(INERTIAL_PARAMETERS, names[body], strict=True)}
        for prefix in INERTIAL_PARAMETERS:
            assert values[prefix] == pytest.approx(expected[prefix], abs=1e-12), (body, prefix)


def test_the_motion_is_that_of_the_files_numbers():
    symbolic, plain = Ours(_load(SPATIAL_ARM, inertial_parameters=True)), Ours(_load(SPATIAL_ARM))
    rng = np.random.default_rng(0)
    for _ in range(3):
        q, v = rng.uniform(-1, 1, 4), rng.uniform(-1, 1, 4)
        np.testing.assert_allclose(symbolic.mass(q), plain.mass(q), atol=1e-12)
        np.testing.assert_allclose(symbolic.acceleration(q, v), plain.acceleration(q, v), atol=1e-10)


def test_a_name_taken_by_a_joint_is_refused():
    text = DOUBLE_PENDULUM.replace('name="elbow"', 'name="m_rod2"').replace('joint="elbow"', 'joint="m_rod2"')
    with pytest.raises(lagrangian.ModelError, match="cannot be named"):
        _load(text, inertial_parameters=True)
