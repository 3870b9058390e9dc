"""Stage 3 — dynamics: T and U, generalized forces by virtual power, Lagrange equations, M q̈ = F."""

# Shared with the later stages: constraints described, reactions, inertial efforts, recursive forms.
from ._constraints import FORMULA_MAX_SIZE as FORMULA_MAX_SIZE
from ._constraints import SLIDING_SUFFIX as SLIDING_SUFFIX
from ._constraints import admissible_integrals as admissible_integrals
from ._constraints import describe_constraints as describe_constraints
from ._constraints import multiplier_formulas as multiplier_formulas
from ._constraints import reaction_efforts as reaction_efforts
from ._energy import KineticEnergyTerm as KineticEnergyTerm
from ._energy import RigidInertia as RigidInertia
from ._energy import rigid_inertia as rigid_inertia
from ._floating import FloatingForm as FloatingForm
from ._floating import floating_form as floating_form
from ._forces import LoadForces as LoadForces
from ._forces import generalized_forces as generalized_forces
from ._friction import SlidingDirection as SlidingDirection
from ._friction import friction_efforts as friction_efforts
from ._friction import sliding_direction as sliding_direction
from ._inertia import mass_matrix_and_bias as mass_matrix_and_bias
from ._inertial import RelativeKinematics as RelativeKinematics
from ._inertial import inertial_torsors as inertial_torsors
from ._inertial import rotating_frame as rotating_frame
from ._lagrange import EquationsOfMotion as EquationsOfMotion
from ._lagrange import LagrangeEquation as LagrangeEquation
from ._lagrange import derive as derive
from ._recursive import RecursiveForm as RecursiveForm
from ._sympy_form import SympyEquations as SympyEquations

__all__ = ["KineticEnergyTerm", "RigidInertia", "LoadForces", "generalized_forces", "EquationsOfMotion",
           "LagrangeEquation", "derive", "multiplier_formulas",
           "FORMULA_MAX_SIZE", "SLIDING_SUFFIX", "admissible_integrals", "describe_constraints", "reaction_efforts",
           "rigid_inertia", "FloatingForm", "floating_form", "friction_efforts", "sliding_direction",
           "RelativeKinematics", "inertial_torsors", "rotating_frame", "RecursiveForm",
           "SlidingDirection", "mass_matrix_and_bias", "SympyEquations"]
