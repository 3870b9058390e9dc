"""Every command takes a robot's URDF file: derive, simulate and linearize on a small one."""

from __future__ import annotations

import pytest
from urdf_robots import DOUBLE_PENDULUM

from lagrangian.cli.main import main


@pytest.fixture
def urdf(tmp_path):
    path = tmp_path / "pendulum.urdf"
    transmission = ('  <transmission name="drive"><type>transmission_interface/SimpleTransmission</type>'
                    '</transmission>\n</robot>')
    path.write_text(DOUBLE_PENDULUM.replace("</robot>", transmission))
    return path


@pytest.mark.slow
def test_derive_prints_the_course_view_of_a_urdf_and_notes_what_it_skipped(urdf, capsys):
    assert main(["derive", str(urdf)]) == 0
    captured = capsys.readouterr()
    assert "Principal parameters (n = 2, hence 2 Lagrange equations): shoulder, elbow" in captured.out
    assert "weight: " in captured.out and "actuators (generalized force" in captured.out
    assert "F[elbow] = −8/25 g sin(shoulder + elbow) + tau_elbow − 1/5 elbo" in captured.out  # damping 0.2
    line = urdf.read_text().split("<transmission")[0].count("\n") + 1
    assert f"pendulum.urdf:{line}: note: 1 <transmission> element skipped" in captured.err


def test_simulate_and_linearize_take_a_urdf(urdf, capsys):
    assert main(["simulate", str(urdf), "--t-end", "0.2"]) == 0
    assert main(["linearize", str(urdf), "--at", "shoulder=0", "--at", "elbow=0"]) == 0
    out = capsys.readouterr().out
    assert "inputs u = (tau_shoulder, tau_elbow)" in out and "asymptotically stable" in out
