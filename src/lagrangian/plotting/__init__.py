"""Stage 7 — plots of a simulated motion, with matplotlib (the optional extra ``lagrangian[plot]``).

``save_plots(trajectory, eom, directory)`` writes every figure that applies:

* ``time_series`` — q_i(t) and q̇_i(t), one row per coordinate;
* ``phase`` — phase portraits (q_i, q̇_i);
* ``apex_sphere`` — the tip of a body axis (the top's z) on the unit sphere, with the θ1, θ2 circles;
* ``nutation`` — the same tip seen from above z0, and θ against ψ;
* ``drift`` — T, U, E and the relative drift of every first integral;
* ``reaction_O`` — R_O(t) = Σ m γ(G) − Σ F_given, the reaction at the fixed point (``reaction``
  when the ground holds the system otherwise, e.g. a cart's rail);
* ``animation.gif`` — the bodies and particles moving (2D for a planar motion).

matplotlib is imported only when a figure is made; without it a `MissingPlotDependency`
(an `OutputError`) says how to install it.
"""

from ._animation import animate as animate
from ._apex import TurningAngles as TurningAngles
from ._apex import plot_apex_sphere as plot_apex_sphere
from ._apex import plot_nutation as plot_nutation
from ._apex import turning_angles as turning_angles
from ._ensemble import plot_ensemble as plot_ensemble
from ._geometry import apex_path as apex_path
from ._geometry import axis_angles as axis_angles

# Shared with the command line: figures of optimized inputs, matplotlib on demand.
from ._inputs import save_inputs_figure as save_inputs_figure
from ._mode_figures import plot_bifurcation as plot_bifurcation
from ._mode_figures import plot_eigenvalue_sweep as plot_eigenvalue_sweep
from ._mode_figures import plot_mode_shapes as plot_mode_shapes
from ._modes import mode_trajectory as mode_trajectory
from ._mpl import MissingPlotDependency as MissingPlotDependency
from ._mpl import new_figure as new_figure
from ._mpl import require_matplotlib as require_matplotlib
from ._reaction import plot_reaction as plot_reaction
from ._reaction import reactions_along as reactions_along
from ._save import KINDS as KINDS
from ._save import applicable_kinds as applicable_kinds
from ._save import figure_caption as figure_caption
from ._save import plot_trajectory as plot_trajectory
from ._save import save_figure as save_figure
from ._save import save_plots as save_plots
from ._series import plot_drift as plot_drift
from ._series import plot_phase as plot_phase
from ._series import plot_time_series as plot_time_series
from ._series import relative_drift as relative_drift

__all__ = ["plot_bifurcation", "mode_trajectory", "save_plots", "plot_trajectory", "applicable_kinds", "figure_caption", "KINDS", "animate", "save_figure",
           "plot_time_series", "plot_phase", "plot_drift", "relative_drift", "plot_apex_sphere", "plot_nutation",
           "apex_path", "axis_angles", "turning_angles", "TurningAngles", "plot_reaction", "reactions_along",
           "MissingPlotDependency", "plot_eigenvalue_sweep", "plot_mode_shapes", "plot_ensemble",
           "save_inputs_figure", "new_figure", "require_matplotlib"]
