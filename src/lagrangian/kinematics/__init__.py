"""Stage 2 — kinematics: frames, Ω, positions, velocities, accelerations, virtual velocities."""

from ._frames import FrameTree as FrameTree
from ._frames import rotation_rate as rotation_rate
from ._kinematics import Kinematics as Kinematics
from ._time import TimeDerivative as TimeDerivative

__all__ = ["FrameTree", "Kinematics", "TimeDerivative", "rotation_rate"]
