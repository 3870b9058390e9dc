"""Stage 4 — analysis of the equations: first integrals, the energy balance, the Newton–Euler cross-check,
reactions, small motions (linearization, modes, stability)."""

from __future__ import annotations

from typing import TYPE_CHECKING

from .._lazy import lazy_names

# Each name is imported from its module on first use (`lagrangian._lazy`): a command that needs one
# module of this stage does not load the others (nor SymPy, SciPy and what they import).
_WHERE = {
    "._bifurcation": ("BifurcationDiagram", "Branch", "bifurcation"),
    "..errors": ("AnalysisError",),  # defined with the package's other errors; kept here, where it was
    "._effective_potential": ("CyclicReduction", "StructureError", "reduce_cyclic"),
    "._energy_balance": ("EnergyBalance", "PowerTerm", "energy_balance"),
    "._equilibria": ("Equilibria", "Equilibrium", "EquilibriumError", "EquilibriumSearch", "SearchRegion", "equilibria"),
    "._feedback": ("ControlError", "Feedback"),
    "._integrals": ("FirstIntegral", "first_integrals"),
    "._newton_euler": ("CoordinateCheck", "ElementTheorems", "Verification", "verify", "given_efforts"),
    "._reactions": ("Reaction", "ReactionHistory", "TrajectoryResiduals", "check_trajectory", "reaction_history",
        "reactions"),
    "._linear_model": ("LinearizationError", "LinearModel", "SecondOrderForm", "to_numpy"),
    "._linearize": ("linearize", "holding_inputs"),
    "._lqr": ("lqr",),
    "._modes": ("Mode", "Modes", "Stability", "StabilityChange", "Sweep", "eigenvalue_sweep", "modes", "stability"),
    "._steady": ("RouthReduction", "SteadyMotion", "routh_reduction", "steady_motions"),
    "._top": ("TopAnalysis", "analyse_top"),
    "._tree_integrals": ("tree_integrals",),
    "._closed_small_motions": ("closed_point", "pulsations_squared"),
}
__getattr__, __dir__ = lazy_names(__name__, _WHERE)

if TYPE_CHECKING:  # what static tools see: the same names, imported eagerly
    from ..errors import AnalysisError as AnalysisError
    from ._bifurcation import BifurcationDiagram as BifurcationDiagram
    from ._bifurcation import Branch as Branch
    from ._bifurcation import bifurcation as bifurcation
    from ._closed_small_motions import closed_point as closed_point
    from ._closed_small_motions import pulsations_squared as pulsations_squared
    from ._effective_potential import CyclicReduction as CyclicReduction
    from ._effective_potential import StructureError as StructureError
    from ._effective_potential import reduce_cyclic as reduce_cyclic
    from ._energy_balance import EnergyBalance as EnergyBalance
    from ._energy_balance import PowerTerm as PowerTerm
    from ._energy_balance import energy_balance as energy_balance
    from ._equilibria import Equilibria as Equilibria
    from ._equilibria import Equilibrium as Equilibrium
    from ._equilibria import EquilibriumError as EquilibriumError
    from ._equilibria import EquilibriumSearch as EquilibriumSearch
    from ._equilibria import SearchRegion as SearchRegion
    from ._equilibria import equilibria as equilibria
    from ._feedback import ControlError as ControlError
    from ._feedback import Feedback as Feedback
    from ._integrals import FirstIntegral as FirstIntegral
    from ._integrals import first_integrals as first_integrals
    from ._linear_model import LinearizationError as LinearizationError
    from ._linear_model import LinearModel as LinearModel
    from ._linear_model import SecondOrderForm as SecondOrderForm
    from ._linear_model import to_numpy as to_numpy
    from ._linearize import holding_inputs as holding_inputs
    from ._linearize import linearize as linearize
    from ._lqr import lqr as lqr
    from ._modes import Mode as Mode
    from ._modes import Modes as Modes
    from ._modes import Stability as Stability
    from ._modes import StabilityChange as StabilityChange
    from ._modes import Sweep as Sweep
    from ._modes import eigenvalue_sweep as eigenvalue_sweep
    from ._modes import modes as modes
    from ._modes import stability as stability
    from ._newton_euler import CoordinateCheck as CoordinateCheck
    from ._newton_euler import ElementTheorems as ElementTheorems
    from ._newton_euler import Verification as Verification
    from ._newton_euler import given_efforts as given_efforts
    from ._newton_euler import verify as verify
    from ._reactions import Reaction as Reaction
    from ._reactions import ReactionHistory as ReactionHistory
    from ._reactions import TrajectoryResiduals as TrajectoryResiduals
    from ._reactions import check_trajectory as check_trajectory
    from ._reactions import reaction_history as reaction_history
    from ._reactions import reactions as reactions
    from ._steady import RouthReduction as RouthReduction
    from ._steady import SteadyMotion as SteadyMotion
    from ._steady import routh_reduction as routh_reduction
    from ._steady import steady_motions as steady_motions
    from ._top import TopAnalysis as TopAnalysis
    from ._top import analyse_top as analyse_top
    from ._tree_integrals import tree_integrals as tree_integrals

__all__ = [
    "AnalysisError",
    "BifurcationDiagram",
    "Branch",
    "ControlError",
    "CoordinateCheck",
    "CyclicReduction",
    "ElementTheorems",
    "EnergyBalance",
    "Equilibria",
    "Equilibrium",
    "EquilibriumSearch",
    "EquilibriumError",
    "Feedback",
    "FirstIntegral",
    "LinearModel",
    "LinearizationError",
    "Mode",
    "Modes",
    "PowerTerm",
    "Reaction",
    "ReactionHistory",
    "RouthReduction",
    "SearchRegion",
    "SecondOrderForm",
    "Stability",
    "StabilityChange",
    "SteadyMotion",
    "StructureError",
    "Sweep",
    "TopAnalysis",
    "TrajectoryResiduals",
    "Verification",
    "analyse_top",
    "bifurcation",
    "check_trajectory",
    "eigenvalue_sweep",
    "energy_balance",
    "equilibria",
    "first_integrals",
    "holding_inputs",
    "linearize",
    "lqr",
    "modes",
    "reaction_history",
    "reactions",
    "reduce_cyclic",
    "routh_reduction",
    "stability",
    "steady_motions",
    "verify",
    "to_numpy",
    "given_efforts",
    "tree_integrals",
    "closed_point",
    "pulsations_squared",
]
