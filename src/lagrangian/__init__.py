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

import importlib
from typing import TYPE_CHECKING

# The names are imported on first use (PEP 562), not here: `import lagrangian` and the command
# line's first lines then cost milliseconds, not the 3 s of SymPy, SciPy and the whole pipeline,
# so that Ctrl-C while those load reaches the command line's handler (one line, exit 130), not a
# traceback from the middle of an import.
_WHERE = {
    **dict.fromkeys(("ControlError", "EnergyBalance", "Equilibrium", "Feedback", "FirstIntegral", "LinearizationError",
                     "LinearModel", "Modes", "Stability", "Sweep", "TopAnalysis", "Verification", "analyse_top",
                     "energy_balance", "equilibria", "first_integrals", "holding_inputs", "linearize", "lqr", "modes",
                     "routh_reduction", "stability", "steady_motions", "sweep", "verify"), ".analysis"),
    **dict.fromkeys(("EquationsOfMotion", "LagrangeEquation", "derive"), ".dynamics"),
    **dict.fromkeys(("DerivationError", "ExportError", "IdentificationError", "KinematicsError", "LagrangianError",
                     "ModelError", "OptimizationError", "OutputError", "ProblemError", "SimulationError",
                     "VerificationError"), ".errors"),
    **dict.fromkeys(("Identification", "identify"), ".identification"),
    "Kinematics": ".kinematics",
    **dict.fromkeys(("ModelBuilder", "load_model", "load_urdf", "parse_model"), ".model"),
    "Model": ".model.spec",
    "lagrange_top": ".model.zoo",
    "export": ".codegen",
    **dict.fromkeys(("Report", "report"), ".output"),
    **dict.fromkeys(("optimize", "load_problem", "OptimalTrajectory", "Objective", "Problem"), ".optimal"),
    **dict.fromkeys(("CompiledSystem", "ContactEvent", "EventSpec", "FreeBodySystem", "ImpactSweep", "InputTable", "Sensitivities", "Switch", "Trajectory",
                     "compile_free_system", "compile_system", "ensemble", "grid", "impact_sweep", "load_trajectory", "open_ensemble", "save_trajectory", "simulate"), ".numerics"),
    **dict.fromkeys(("View", "view"), ".view3d"),
}

if TYPE_CHECKING:  # what static tools see: the same names, imported eagerly
    from .analysis import (ControlError, EnergyBalance, Equilibrium, Feedback, FirstIntegral, LinearizationError,
                           LinearModel, Modes, Stability, Sweep, TopAnalysis, Verification, analyse_top,
                           energy_balance, equilibria, first_integrals, holding_inputs, linearize, lqr, modes,
                           routh_reduction, stability, steady_motions, sweep, verify)
    from .dynamics import EquationsOfMotion, LagrangeEquation, derive
    from .errors import (DerivationError, ExportError, IdentificationError, KinematicsError, LagrangianError,
                         ModelError, OptimizationError, OutputError, ProblemError, SimulationError, VerificationError)
    from .identification import Identification, identify
    from .kinematics import Kinematics
    from .model import ModelBuilder, load_model, load_urdf, parse_model
    from .model.spec import Model
    from .model.zoo import lagrange_top
    from .numerics import (CompiledSystem, ContactEvent, EventSpec, FreeBodySystem, ImpactSweep, InputTable, Sensitivities, Switch, Trajectory, compile_free_system,
                           compile_system, ensemble, grid, impact_sweep, load_trajectory, open_ensemble, save_trajectory, simulate)
    from .optimal import Objective, OptimalTrajectory, Problem, load_problem, optimize
    from .codegen import export
    from .output import Report, report
    from .view3d import View, view

__version__ = "0.1.0"

__all__ = [
    "__version__",
    "load_model",
    "parse_model",
    "load_urdf",
    "ModelBuilder",
    "Model",
    "lagrange_top",
    "Kinematics",
    "derive",
    "EquationsOfMotion",
    "LagrangeEquation",
    "first_integrals",
    "FirstIntegral",
    "energy_balance",
    "EnergyBalance",
    "verify",
    "Verification",
    "analyse_top",
    "TopAnalysis",
    "linearize",
    "holding_inputs",
    "LinearModel",
    "LinearizationError",
    "modes",
    "Modes",
    "stability",
    "Stability",
    "sweep",
    "Sweep",
    "Equilibrium",
    "routh_reduction",
    "steady_motions",
    "equilibria",
    "lqr",
    "Feedback",
    "ControlError",
    "compile_system",
    "CompiledSystem",
    "compile_free_system",
    "FreeBodySystem",
    "simulate",
    "Sensitivities",
    "identify",
    "Identification",
    "ensemble",
    "grid",
    "open_ensemble",
    "EventSpec",
    "InputTable",
    "Switch",
    "ContactEvent",
    "impact_sweep",
    "ImpactSweep",
    "Trajectory",
    "save_trajectory",
    "load_trajectory",
    "optimize",
    "load_problem",
    "Problem",
    "Objective",
    "OptimalTrajectory",
    "report",
    "Report",
    "export",
    "view",
    "View",
    "LagrangianError",
    "ModelError",
    "KinematicsError",
    "DerivationError",
    "SimulationError",
    "OutputError",
    "ExportError",
    "VerificationError",
    "IdentificationError",
    "ProblemError",
    "OptimizationError",
]


def __getattr__(name: str):
    """A public name, imported from its subpackage on first use (and kept)."""
    where = _WHERE.get(name)
    if where is None:
        raise AttributeError(f"module 'lagrangian' has no attribute {name!r}")
    value = getattr(importlib.import_module(where, __name__), name)
    globals()[name] = value
    return value


def __dir__() -> list[str]:
    return list(__all__)
