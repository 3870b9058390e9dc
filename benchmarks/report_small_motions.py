"""Time and memory of the Whipple bicycle's report with its small-motion section (`report --small-motions`).

The target: under a minute and under 1 GB (it ran past 13 minutes and 6 GB when the symbolic
linearization expanded and factored its 10⁵-character entries).  Each variant runs in a child
process, so that its peak resident memory is its own; the peer is the same report without the
section, in the same run.  Run by hand:

    PYTHONPATH=src python benchmarks/report_small_motions.py [--repeats 2]
"""

from __future__ import annotations

import argparse
import subprocess
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
CHILD = """
import resource, sys, time
import lagrangian
eom = lagrangian.derive(lagrangian.load_model(sys.argv[1]))
t0 = time.perf_counter()
text = lagrangian.report(eom, lang="fr", small_motions=sys.argv[2] == "yes").markdown()
print(time.perf_counter() - t0, resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024, len(text))
"""


def run(small_motions: bool) -> tuple[float, float, float]:
    """(seconds of the report, peak MiB of the child, wall seconds of the child with imports and derive)."""
    t0 = time.perf_counter()
    out = subprocess.run([sys.executable, "-c", CHILD, str(ROOT / "examples" / "whipple_bicycle.toml"),
                          "yes" if small_motions else "no"], check=True, capture_output=True, text=True,
                         env={"PYTHONPATH": str(ROOT / "src"), "PATH": "/usr/bin:/bin"})
    seconds, mib, _ = out.stdout.split()
    return float(seconds), float(mib), time.perf_counter() - t0


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeats", type=int, default=2)
    args = parser.parse_args()
    rows: dict[str, list[tuple[float, float, float]]] = {"with --small-motions": [], "without": []}
    for _ in range(args.repeats):
        rows["without"].append(run(False))
        rows["with --small-motions"].append(run(True))
    for label, values in rows.items():
        print(f"Whipple bicycle, French report, {label}: "
              + ", ".join(f"{s:.1f} s (process {w:.1f} s, peak {m:.0f} MiB)" for s, m, w in values))
    best = {k: min(v) for k, v in rows.items()}
    print(f"ratio (best with / best without): {best['with --small-motions'][0] / best['without'][0]:.2f}; "
          f"peak with: {max(m for _, m, _ in rows['with --small-motions']):.0f} MiB (target: < 60 s, < 1024 MiB)")


if __name__ == "__main__":
    main()
