"""``lagrangian verify [MODEL.toml] [--simulate T_END] [--set NAME=VALUE ...] [-o FILE]``.

Checks every Lagrange equation L(q_i) against the Newton–Euler theorems projected on the
directions of q_i, prints the reactions of the constraints, and with ``--simulate``
evaluates the same theorems along a simulated motion.  A failed check raises
`VerificationError` (exit code 5) with the failing equation in the message.  The text is
`lagrangian.output.verification_text`'s.
"""

from __future__ import annotations

import argparse

from ..analysis import Reaction, TrajectoryResiduals, Verification, check_trajectory, reactions, verify
from ..dynamics import derive
from ..errors import ModelError, VerificationError
from ..output import verification_failure, verification_text
from ._settings import SettingError, parse_settings
from ._source import load_source

__all__ = ["TOLERANCE", "run"]

#: Largest relative residual accepted along a trajectory: the theorems hold exactly, so
#: what is left is rounding in the evaluation (about 1e-15 relative).
TOLERANCE = 1e-9


def _along(v: Verification, args: argparse.Namespace) -> TrajectoryResiduals:
    """The theorems' residuals along the motion asked for, refused above `TOLERANCE`."""
    from ..numerics import check_trajectory_along, simulate  # numerics only when asked for (it compiles C)

    parameters, initial = parse_settings(args.set, v.eom.model)
    traj = simulate(v.eom, args.simulate, initial=initial, parameters=parameters, n_out=args.n_out)
    res = check_trajectory_along(v.eom, traj, check=lambda eom, rows: check_trajectory(v if eom is v.eom else eom, rows))
    what, worst = res.worst()
    if not worst <= TOLERANCE:
        raise VerificationError(
            f"Along the simulated motion, {what} is off by {worst:.3g} (relative), more than {TOLERANCE:g}.",
            fix="the Lagrange equations and the Newton–Euler theorems disagree numerically; check the model's "
                "loads and inertia, and report it if the model is right")
    return res


def run(args: argparse.Namespace) -> str:
    model = load_source(args.model)
    parse_settings(args.set, model)  # bad names and values are reported before any work
    if args.set and args.simulate is None:
        raise SettingError("`--set` gives values for a simulation, and none was asked for.",
                           fix="add `--simulate T_END`, or leave out `--set`")
    v = verify(derive(model))
    failure = verification_failure(v)
    if failure is not None:
        raise VerificationError(failure, fix="the derivation or the model's loads are inconsistent; report it with "
                                             "the model file")
    try:
        found: tuple[Reaction, ...] | ModelError = reactions(v)
    except ModelError as exc:  # a body without its mass: the equations are checked, the reactions cannot be
        found = exc
    along = _along(v, args) if args.simulate is not None else None
    return verification_text(v, found, along, tolerance=TOLERANCE)
