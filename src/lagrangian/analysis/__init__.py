"""Stage 4 — analysis of the equations: first integrals, the energy balance, the Newton–Euler cross-check,
reactions, small motions (linearization, modes, stability)."""

from ._bifurcation import BifurcationDiagram as BifurcationDiagram
from ._bifurcation import Branch as Branch
from ._bifurcation import bifurcation as bifurcation
from ._effective_potential import AnalysisError as AnalysisError
from ._effective_potential import CyclicReduction as CyclicReduction
from ._effective_potential import StructureError as StructureError
from ._effective_potential import reduce_cyclic as reduce_cyclic
from ._energy_balance import EnergyBalance as EnergyBalance
from ._energy_balance import PowerTerm as PowerTerm
from ._energy_balance import energy_balance as energy_balance
from ._equilibria import Equilibria as Equilibria
from ._equilibria import Equilibrium as Equilibrium
from ._equilibria import EquilibriumSearch as EquilibriumSearch
from ._equilibria import SearchRegion as SearchRegion
from ._equilibria import EquilibriumError as EquilibriumError
from ._equilibria import equilibria as equilibria
from ._feedback import ControlError as ControlError
from ._feedback import Feedback as Feedback
from ._integrals import FirstIntegral as FirstIntegral
from ._integrals import first_integrals as first_integrals
from ._newton_euler import CoordinateCheck as CoordinateCheck
from ._newton_euler import ElementTheorems as ElementTheorems
from ._newton_euler import Verification as Verification
from ._newton_euler import verify as verify
from ._reactions import Reaction as Reaction
from ._reactions import ReactionHistory as ReactionHistory
from ._reactions import TrajectoryResiduals as TrajectoryResiduals
from ._reactions import check_trajectory as check_trajectory
from ._reactions import reaction_history as reaction_history
from ._reactions import reactions as reactions
from ._linear_model import LinearizationError as LinearizationError
from ._linear_model import LinearModel as LinearModel
from ._linear_model import SecondOrderForm as SecondOrderForm
from ._linearize import linearize as linearize
from ._linearize import holding_inputs as holding_inputs
from ._lqr import lqr as lqr
from ._modes import Mode as Mode
from ._modes import Modes as Modes
from ._modes import Stability as Stability
from ._modes import StabilityChange as StabilityChange
from ._modes import Sweep as Sweep
from ._modes import modes as modes
from ._modes import stability as stability
from ._modes import sweep as sweep
from ._steady import RouthReduction as RouthReduction
from ._steady import SteadyMotion as SteadyMotion
from ._steady import routh_reduction as routh_reduction
from ._steady import steady_motions as steady_motions
from ._top import TopAnalysis as TopAnalysis
from ._top import analyse_top as analyse_top

__all__ = ["FirstIntegral", "first_integrals", "CoordinateCheck", "ElementTheorems", "Verification", "verify",
           "Reaction", "ReactionHistory", "TrajectoryResiduals", "check_trajectory", "reaction_history",
           "reactions", "analyse_top", "TopAnalysis", "reduce_cyclic", "CyclicReduction", "AnalysisError",
           "StructureError", "EnergyBalance", "PowerTerm", "energy_balance", "linearize", "holding_inputs", "LinearModel",
           "SecondOrderForm", "LinearizationError", "Mode", "Modes", "Stability", "StabilityChange", "Sweep", "modes",
           "stability", "sweep", "Equilibria", "Equilibrium", "EquilibriumError", "EquilibriumSearch", "SearchRegion",
           "equilibria", "bifurcation",
           "BifurcationDiagram", "Branch", "routh_reduction", "RouthReduction", "steady_motions",
           "SteadyMotion", "Feedback", "ControlError", "lqr"]
