"""lagrangian — Lagrange's equations from a model of frames, bodies and loads.

The pipeline, one stage per subpackage (imports flow one way)::

    model → kinematics → dynamics → analysis → codegen → numerics → view3d → output/plotting/optimal → cli

    model        the description (spec)
    kinematics   Ω, V, V*
    dynamics     T, U, Q, L(q_i), M, F
    analysis     first integrals, Newton–Euler, the top's analysis
    codegen      the equations as code: C for the package, C/NumPy/JAX/Octave for export
    numerics     the C compiled, integrators, simulate
    view3d       3-D scene, page
    output, plotting, optimal   text, LaTeX, JSON, report, plots; optimal motions by collocation

Typical use::

    import lagrangian
    model = lagrangian.load_model("examples/lagrange_top.toml")
    eom = lagrangian.derive(model)
    traj = lagrangian.simulate(eom, 10.0)        # compiled C, DOP853
    print(traj.drift_summary())                  # K, H, E conservation
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from . import _display
from ._lazy import lazy_names
from ._version import __version__

# The one list of the package's public names: {module: names}, in the pipeline's order.  Each name is
# one of its stage's public names (the stage's ``__all__``); `__all__` and the lazy loading below are
# made from this table, and a test checks that the TYPE_CHECKING imports say the same.
#
# The names are imported on first use (PEP 562), not here: `import lagrangian` and the command
# line's first lines then cost milliseconds, not the 3 s of SymPy, SciPy and the whole pipeline,
# so that Ctrl-C while those load reaches the command line's handler (one line, exit 130), not a
# traceback from the middle of an import.
_WHERE = {
    ".model": ("load_model", "parse_model", "load_urdf", "ModelBuilder", "Model"),
    ".model.zoo": ("lagrange_top",),
    ".kinematics": ("Kinematics",),
    ".dynamics": ("derive", "EquationsOfMotion", "LagrangeEquation"),
    ".analysis": ("first_integrals", "FirstIntegral", "energy_balance", "EnergyBalance", "verify", "Verification",
                  "analyse_top", "TopAnalysis", "linearize", "holding_inputs", "LinearModel", "LinearizationError",
                  "modes", "Modes", "stability", "Stability", "Sweep", "Equilibrium", "routh_reduction",
                  "steady_motions", "equilibria", "lqr", "Feedback", "ControlError"),
    ".numerics": ("compile_system", "CompiledSystem", "compile_free_system", "FreeBodySystem", "simulate",
                  "Sensitivities", "ensemble", "grid", "open_ensemble", "EventSpec", "InputTable", "Switch",
                  "ContactEvent", "sweep", "impact_sweep", "ImpactSweep", "Trajectory", "save_trajectory", "load_trajectory"),
    ".identification": ("identify", "Identification"),
    ".optimal": ("optimize", "load_problem", "Problem", "Objective", "OptimalTrajectory"),
    ".codegen": ("export",),
    ".output": ("report", "Report", "sympy_equations"),
    ".view3d": ("view", "View"),
    ".errors": ("LagrangianError", "ModelError", "KinematicsError", "DerivationError", "SimulationError",
                "OutputError", "ExportError", "VerificationError", "IdentificationError", "ProblemError",
                "OptimizationError"),
}
__getattr__ = lazy_names(__name__, _WHERE)[0]  # `__dir__` below: the public names only

__all__ = ["__version__"] + [name for names in _WHERE.values() for name in names]

if TYPE_CHECKING:  # what static tools see: the same names, imported eagerly (tests/test_public_api.py checks)
    from .analysis import ControlError as ControlError
    from .analysis import EnergyBalance as EnergyBalance
    from .analysis import Equilibrium as Equilibrium
    from .analysis import Feedback as Feedback
    from .analysis import FirstIntegral as FirstIntegral
    from .analysis import LinearizationError as LinearizationError
    from .analysis import LinearModel as LinearModel
    from .analysis import Modes as Modes
    from .analysis import Stability as Stability
    from .analysis import Sweep as Sweep
    from .analysis import TopAnalysis as TopAnalysis
    from .analysis import Verification as Verification
    from .analysis import analyse_top as analyse_top
    from .analysis import energy_balance as energy_balance
    from .analysis import equilibria as equilibria
    from .analysis import first_integrals as first_integrals
    from .analysis import holding_inputs as holding_inputs
    from .analysis import linearize as linearize
    from .analysis import lqr as lqr
    from .analysis import modes as modes
    from .analysis import routh_reduction as routh_reduction
    from .analysis import stability as stability
    from .analysis import steady_motions as steady_motions
    from .analysis import verify as verify
    from .codegen import export as export
    from .dynamics import EquationsOfMotion as EquationsOfMotion
    from .dynamics import LagrangeEquation as LagrangeEquation
    from .dynamics import derive as derive
    from .errors import DerivationError as DerivationError
    from .errors import ExportError as ExportError
    from .errors import IdentificationError as IdentificationError
    from .errors import KinematicsError as KinematicsError
    from .errors import LagrangianError as LagrangianError
    from .errors import ModelError as ModelError
    from .errors import OptimizationError as OptimizationError
    from .errors import OutputError as OutputError
    from .errors import ProblemError as ProblemError
    from .errors import SimulationError as SimulationError
    from .errors import VerificationError as VerificationError
    from .identification import Identification as Identification
    from .identification import identify as identify
    from .kinematics import Kinematics as Kinematics
    from .model import Model as Model
    from .model import ModelBuilder as ModelBuilder
    from .model import load_model as load_model
    from .model import load_urdf as load_urdf
    from .model import parse_model as parse_model
    from .model.zoo import lagrange_top as lagrange_top
    from .numerics import CompiledSystem as CompiledSystem
    from .numerics import ContactEvent as ContactEvent
    from .numerics import EventSpec as EventSpec
    from .numerics import FreeBodySystem as FreeBodySystem
    from .numerics import ImpactSweep as ImpactSweep
    from .numerics import InputTable as InputTable
    from .numerics import Sensitivities as Sensitivities
    from .numerics import Switch as Switch
    from .numerics import Trajectory as Trajectory
    from .numerics import compile_free_system as compile_free_system
    from .numerics import compile_system as compile_system
    from .numerics import ensemble as ensemble
    from .numerics import grid as grid
    from .numerics import impact_sweep as impact_sweep
    from .numerics import load_trajectory as load_trajectory
    from .numerics import open_ensemble as open_ensemble
    from .numerics import save_trajectory as save_trajectory
    from .numerics import simulate as simulate
    from .numerics import sweep as sweep
    from .optimal import Objective as Objective
    from .optimal import OptimalTrajectory as OptimalTrajectory
    from .optimal import Problem as Problem
    from .optimal import load_problem as load_problem
    from .optimal import optimize as optimize
    from .output import Report as Report
    from .output import report as report
    from .output import sympy_equations as sympy_equations
    from .view3d import View as View
    from .view3d import view as view


def __dir__() -> list[str]:
    return list(__all__)


def _draw(value: object, form: str) -> str:
    """Jupyter's display of a value of an early stage: output's `jupyter_repr`, loaded on the first display.

    The values' display methods (dynamics, analysis, numerics) may not import output, a later stage;
    the face, above every stage, lends them this drawer (`lagrangian._display`).
    """
    from .output import jupyter_repr

    return jupyter_repr(value, form)


_display.install(_draw)
