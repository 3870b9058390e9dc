"""Stage 6 — numerics: the generated code (`lagrangian.codegen`) compiled and run, simulation results.

``compile_system(eom)`` → `CompiledSystem` (M, F, q̈, monitors, events; C or SymEngine);
``compile_free_system(model)`` → `FreeBodySystem`: a model with free bodies on unit quaternions (C);
``simulate(model_or_eom, t_end, ...)`` → `Trajectory`;
``ensemble(model_or_eom, t_end, initial=grid(...), ...)`` → many motions as an ``xarray.Dataset``;
``simulate`` picks the route a model needs from one registry (`_methods.ROUTES`): free bodies, unilateral
contacts (phases between impacts; `simulate_contact` names that route), exact Coulomb friction
(`simulate_stick_slip`), complementary constraints, plain M q̈ = F; ``impact_sweep`` maps what a model's
contacts do against a parameter; ``sweep``, the one verb, follows a linearization's eigenvalues or a contact
model's impacts.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from .._lazy import lazy_names

# Each name is imported from its module on first use (`lagrangian._lazy`): a command that needs one
# module of this stage does not load the others (nor SymPy, SciPy and what they import).
_WHERE = {
    "._contact": ("contact_model",),
    "._contact_switch": ("ContactEvent",),
    "._control": ("control_block",),
    "._dae": ("ConstrainedSystem",),
    "._projection": ("project",),
    "._options": ("STABILIZATIONS", "SimulationOptions"),
    "._ensemble": ("ensemble", "flip_events", "connect_scheduler"),
    "._ensemble_store": ("open_ensemble",),
    "._members": ("Grid", "grid"),
    "._files": ("check_output_path", "load_trajectory", "save_trajectory"),
    "._free_system": ("FreeBodySystem", "compile_free_system"),
    "._impact_sweep": ("ImpactSweep", "impact_sweep", "OUTCOMES"),
    "._input_switch": ("Switch",),
    "._input_table": ("InputTable",),
    "._simulate": ("METHODS", "EventSpec", "default_tolerance", "initial_state", "simulate", "simulate_contact",
                   "simulate_stick_slip"),
    "._sensitivity": ("Sensitivities", "SensitivityColumn", "SensitivitySystem", "inverse_dynamics", "sensitivity_system"),
    "._sweep": ("sweep",),
    "._system": ("CompiledSystem", "compile_system"),
    "._phases": ("check_trajectory_along", "reaction_history_along"),
    "._reaction_columns": ("reaction_columns_along",),
    "._top_check": ("SimulationCheck", "simulation_check"),
    "._trajectory": ("Event", "Trajectory"),
    "._batch": ("STATUS",),
    "._compile": ("load_verified",),
    "._forward": ("forward_jacobian",),
}
__getattr__, __dir__ = lazy_names(__name__, _WHERE)

if TYPE_CHECKING:  # what static tools see: the same names, imported eagerly
    from ._batch import STATUS as STATUS
    from ._compile import load_verified as load_verified
    from ._contact import contact_model as contact_model
    from ._contact_switch import ContactEvent as ContactEvent
    from ._control import control_block as control_block
    from ._dae import ConstrainedSystem as ConstrainedSystem
    from ._ensemble import connect_scheduler as connect_scheduler
    from ._ensemble import ensemble as ensemble
    from ._ensemble import flip_events as flip_events
    from ._ensemble_store import open_ensemble as open_ensemble
    from ._files import check_output_path as check_output_path
    from ._files import load_trajectory as load_trajectory
    from ._files import save_trajectory as save_trajectory
    from ._forward import forward_jacobian as forward_jacobian
    from ._free_system import FreeBodySystem as FreeBodySystem
    from ._free_system import compile_free_system as compile_free_system
    from ._impact_sweep import OUTCOMES as OUTCOMES
    from ._impact_sweep import ImpactSweep as ImpactSweep
    from ._impact_sweep import impact_sweep as impact_sweep
    from ._input_switch import Switch as Switch
    from ._input_table import InputTable as InputTable
    from ._members import Grid as Grid
    from ._members import grid as grid
    from ._options import STABILIZATIONS as STABILIZATIONS
    from ._options import SimulationOptions as SimulationOptions
    from ._phases import check_trajectory_along as check_trajectory_along
    from ._phases import reaction_history_along as reaction_history_along
    from ._projection import project as project
    from ._reaction_columns import reaction_columns_along as reaction_columns_along
    from ._sensitivity import Sensitivities as Sensitivities
    from ._sensitivity import SensitivityColumn as SensitivityColumn
    from ._sensitivity import SensitivitySystem as SensitivitySystem
    from ._sensitivity import inverse_dynamics as inverse_dynamics
    from ._sensitivity import sensitivity_system as sensitivity_system
    from ._simulate import METHODS as METHODS
    from ._simulate import EventSpec as EventSpec
    from ._simulate import default_tolerance as default_tolerance
    from ._simulate import initial_state as initial_state
    from ._simulate import simulate as simulate
    from ._simulate import simulate_contact as simulate_contact
    from ._simulate import simulate_stick_slip as simulate_stick_slip
    from ._sweep import sweep as sweep
    from ._system import CompiledSystem as CompiledSystem
    from ._system import compile_system as compile_system
    from ._top_check import SimulationCheck as SimulationCheck
    from ._top_check import simulation_check as simulation_check
    from ._trajectory import Event as Event
    from ._trajectory import Trajectory as Trajectory

__all__ = [
    "METHODS",
    "OUTCOMES",
    "STABILIZATIONS",
    "STATUS",
    "CompiledSystem",
    "ContactEvent",
    "ConstrainedSystem",
    "Event",
    "EventSpec",
    "FreeBodySystem",
    "Grid",
    "ImpactSweep",
    "InputTable",
    "Sensitivities",
    "SensitivityColumn",
    "SensitivitySystem",
    "SimulationCheck",
    "SimulationOptions",
    "Switch",
    "Trajectory",
    "check_output_path",
    "control_block",
    "project",
    "check_trajectory_along",
    "compile_free_system",
    "compile_system",
    "connect_scheduler",
    "contact_model",
    "default_tolerance",
    "ensemble",
    "flip_events",
    "forward_jacobian",
    "grid",
    "impact_sweep",
    "initial_state",
    "inverse_dynamics",
    "load_trajectory",
    "load_verified",
    "open_ensemble",
    "reaction_columns_along",
    "reaction_history_along",
    "save_trajectory",
    "sensitivity_system",
    "simulate",
    "simulate_contact",
    "simulate_stick_slip",
    "simulation_check",
    "sweep",
]
