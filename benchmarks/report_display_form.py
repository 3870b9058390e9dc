"""Cost of the report's display simplifier (`lagrangian.output._display_form`) on the 40-link chain.

Builds the French report of `planar_chain(40)` with and without `display_form` (its cache cleared before each
run), a few times each, and prints the times and the ratio of the best runs.  Run by hand:

    PYTHONPATH=src python benchmarks/report_display_form.py
"""

from __future__ import annotations

import time

import lagrangian
from lagrangian.model.zoo import planar_chain
from lagrangian.output import report
from lagrangian.output._display_form import _display_form
from lagrangian.output._report import build


def main(repeats: int = 3) -> None:
    eom = lagrangian.derive(planar_chain(40))
    report(lagrangian.derive(planar_chain(3)), lang="fr")  # imports and first-use caches
    simplifier = build.display_form
    times: dict[str, list[float]] = {"with display_form": [], "without": []}
    for _ in range(repeats):
        for label, rewrite in (("without", lambda e, parameters=(): e), ("with display_form", simplifier)):
            build.display_form = rewrite
            _display_form.cache_clear()
            t0 = time.perf_counter()
            report(eom, lang="fr")
            times[label].append(time.perf_counter() - t0)
    build.display_form = simplifier
    for label, ts in times.items():
        print(f"40-link chain, French report, {label}: " + ", ".join(f"{t:.2f} s" for t in ts))
    print(f"ratio (best with / best without): {min(times['with display_form']) / min(times['without']):.2f}")


if __name__ == "__main__":
    main()
