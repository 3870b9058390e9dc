"""``lagrangian optimize``: its arguments (its work: `lagrangian.cli._optimize`)."""

from __future__ import annotations

import argparse

from .common import command, number_argument

__all__ = ["SUMMARY", "register"]

SUMMARY = "an optimal motion by direct collocation (CasADi, IPOPT) from a problem file:\n" \
          "swing-ups, minimum-time slews; the optimum replayed to check it"

#: What `--json` prints (docs/optimal-control.md).
SCHEMA = "lagrangian.optimize/1"


def register(sub: argparse._SubParsersAction) -> None:
    p = sub.add_parser(
        "optimize", help="an optimal motion by direct collocation",
        description="Solve the optimal-control problem of PROBLEM.toml (model, boundary conditions, bounds, "
                    "objective, nodes, method; docs/optimal-control.md) by direct collocation: the dynamics "
                    "M q'' - F(q, q', u) = 0 at every collocation point, exact derivatives from CasADi, IPOPT. "
                    "The optimized inputs are then replayed through an integrator to check the motion.")
    p.add_argument("problem", help="the problem file (TOML), e.g. examples/optimal/cart_pole_swing_up.toml")
    p.add_argument("--nodes", type=int, default=None, metavar="N", help="mesh nodes (overrides the file's)")
    p.add_argument("--method", choices=("hermite-simpson", "trapezoidal", "backward-euler"), default=None,
                   help="the transcription (overrides the file's; default hermite-simpson)")
    p.add_argument("--set", dest="set", action="append", default=[], metavar="NAME=VALUE",
                   help="override a parameter value (m=0.3); repeat for several")
    p.add_argument("--guess", choices=("interpolate", "simulate"), default=None,
                   help="where IPOPT starts: a line between the boundary values (default) or the motion with "
                        "the inputs off")
    p.add_argument("--hessian", choices=("exact", "limited-memory"), default=None,
                   help="exact second derivatives (default) or IPOPT's quasi-Newton approximation")
    p.add_argument("--tolerance", type=number_argument, default=None, help="IPOPT's tol (default 1e-8)")
    p.add_argument("--max-iterations", type=int, default=None, metavar="K", help="IPOPT's max_iter (default 3000)")
    p.add_argument("--verify", action=argparse.BooleanOptionalAction, default=True,
                   help="replay the optimized inputs through an integrator and report the difference (default on)")
    p.add_argument("--json", action="store_true", help=f"print the JSON document ({SCHEMA})")
    p.add_argument("-o", "--out", metavar="FILE", help="write the motion to FILE (.csv or .npz), atomically")
    p.add_argument("--plot", metavar="DIR", nargs="?", const="",
                   help="write the figures (q, q', the inputs) and an animation into DIR (default: the problem "
                        "file's stem + _plots)")
    p.add_argument("--animation", choices=("gif", "mp4", "none"), default="gif", help="the animation --plot writes")
    p.add_argument("--verbose", action="store_true", help="let IPOPT print its iterations (on standard error)")
    p.set_defaults(run=command("optimize"))
