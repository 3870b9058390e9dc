"""Stage 3 — dynamics: T and U, generalized forces by virtual power, Lagrange equations, M q̈ = F."""

from ._constraints import multiplier_formulas as multiplier_formulas
from ._energy import KineticEnergyTerm as KineticEnergyTerm
from ._energy import RigidInertia as RigidInertia
from ._forces import LoadForces as LoadForces
from ._forces import generalized_forces as generalized_forces
from ._lagrange import EquationsOfMotion as EquationsOfMotion
from ._lagrange import LagrangeEquation as LagrangeEquation
from ._lagrange import derive as derive

__all__ = ["KineticEnergyTerm", "RigidInertia", "LoadForces", "generalized_forces", "EquationsOfMotion",
           "LagrangeEquation", "derive", "multiplier_formulas"]
