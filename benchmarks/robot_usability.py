"""Robot usability: what `lagrangian simulate` and `lagrangian derive` cost on a URDF robot and a zoo arm.

* simulate: the reaction columns (the ground's wrench on the arm), the former path (the symbolic
  check of every L(q_i) + the shortest-frame display + the numbers) against the present one
  (the vector theorems in R0 + the numbers), in the same run; and the whole command with its
  default (no reactions for a recursive-form tree) against ``--reactions``.
* derive: the text output, the default (the course's view, long expressions summarized) and
  ``--intermediates`` against ``--expanded`` (every expression in full, as before).

Run: ``PYTHONPATH=src .venv/bin/python benchmarks/robot_usability.py [--skip-expanded]``.
Wall seconds on whatever the machine is doing: compare the ratios, not the seconds.
"""

from __future__ import annotations

import argparse
import subprocess
import sys
import time
from importlib import metadata
from pathlib import Path

import lagrangian
from lagrangian.analysis import reaction_history, reactions
from lagrangian.analysis._newton_euler import verify
from lagrangian.cli._source import load_source
from lagrangian.numerics import reaction_columns_along


def panda() -> str | None:
    try:
        dist = metadata.distribution("example-robot-data")
    except metadata.PackageNotFoundError:
        return None
    path = Path(dist.locate_file("cmeel.prefix/share/example-robot-data/robots/panda_description/urdf/panda.urdf"))
    return str(path) if path.is_file() else None


def _timed(f):
    start = time.perf_counter()
    out = f()
    return time.perf_counter() - start, out


def _cli(*argv: str) -> float:
    start = time.perf_counter()
    subprocess.run([sys.executable, "-m", "lagrangian.cli.main", *argv], check=True,
                   stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    return time.perf_counter() - start


def reactions_row(source: str) -> None:
    eom = lagrangian.derive(load_source(source))
    traj = lagrangian.simulate(eom, 1.0)
    before, _ = _timed(lambda: (lambda v: (reactions(v), reaction_history(v, traj)))(verify(eom)))
    after, _ = _timed(lambda: reaction_columns_along(eom, traj))
    print(f"{Path(source).name:>20}: reaction columns {before:6.2f} s before, {after:6.2f} s now "
          f"(ratio {after / before:.2f})")
    cheap = _cli("simulate", source, "--t-end", "1", "-o", "/tmp/robot_usability.npz")
    full = _cli("simulate", source, "--t-end", "1", "--reactions", "-o", "/tmp/robot_usability.npz")
    print(f"{'':>20}  `simulate --t-end 1` {cheap:6.2f} s (default), {full:6.2f} s (--reactions)")


def derive_row(source: str, expanded: bool) -> None:
    short = _cli("derive", source)
    listing = _cli("derive", source, "--intermediates")
    line = f"{Path(source).name:>20}: `derive` {short:6.2f} s (default), {listing:6.2f} s (--intermediates)"
    if expanded:
        line += f", {_cli('derive', source, '--expanded'):6.2f} s (--expanded)"
    print(line)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--skip-expanded", action="store_true", help="do not time `derive --expanded`")
    args = parser.parse_args()
    robots = [s for s in (panda(), "zoo:serial_arm:8") if s]
    _cli("simulate", robots[0], "--t-end", "0.01", "--no-reactions", "-o", "/tmp/robot_usability.npz")  # warm
    for source in robots:
        reactions_row(source)
    for source in [s for s in (panda(), "zoo:serial_arm:7") if s]:
        # the Panda's expanded form takes more than 5 minutes: timed for the 7-joint arm only
        derive_row(source, not args.skip_expanded and source.startswith("zoo:"))


if __name__ == "__main__":
    main()
