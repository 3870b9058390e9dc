"""Stage 2 — kinematics: frames, Ω, positions, velocities, accelerations, virtual velocities."""

from ._frames import FrameTree as FrameTree
from ._kinematics import Kinematics as Kinematics
from ._time import TimeDerivative as TimeDerivative

__all__ = ["FrameTree", "Kinematics", "TimeDerivative"]
