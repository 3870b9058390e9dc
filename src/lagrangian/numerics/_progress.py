"""Progress of a run: a bar on standard error, or a user's callback(fraction, t).

A run in compiled C is one call, so its progress is read by a second thread (`Watch`) from
the time the integrator has reached, which the C writes into its control block; SciPy's
methods report from their step loop.  Either way the reports (`Reporter`) come at most
every 0.1 s and once at the end, and reading them never changes the run.
"""

from __future__ import annotations

import math
import sys
import threading
import time
from collections.abc import Callable

import numpy as np

__all__ = ["Reporter", "Watch", "make_reporter", "progress_bar"]


class Reporter:
    """Progress reports at most every ``period`` seconds, and one at the end (fraction 1 when done)."""

    def __init__(self, report: Callable[[float, float], None], t_start: float, t_end: float,
                 period: float = 0.1) -> None:
        self.report, self.t_start, self.span, self.period = report, t_start, t_end - t_start, period
        self.last = -math.inf
        self.fraction = -1.0

    def fraction_at(self, t: float) -> float:
        return min(1.0, max(0.0, (t - self.t_start) / self.span))

    def update(self, t: float) -> None:
        now = time.monotonic()
        fraction = self.fraction_at(t)
        if now - self.last >= self.period and fraction > self.fraction and fraction < 1.0:
            self.last, self.fraction = now, fraction
            self.report(fraction, t)

    def finish(self, t: float, completed: bool) -> None:
        fraction = 1.0 if completed else self.fraction_at(t)
        if fraction >= self.fraction:
            self.report(fraction, t)
        if fraction < 1.0 and self.report is progress_bar:
            sys.stderr.write("\n")


class Watch:
    """Polls the time a C run has reached (``ctl[0]``), from a second thread, for the progress."""

    def __init__(self, reporter: Reporter | None, ctl: np.ndarray) -> None:
        self.reporter, self.ctl = reporter, ctl
        self.stop = threading.Event()
        self.thread: threading.Thread | None = None

    def __enter__(self) -> Watch:
        if self.reporter is not None:
            self.thread = threading.Thread(target=self._poll, daemon=True)
            self.thread.start()
        return self

    def _poll(self) -> None:
        reporter = self.reporter
        if reporter is None:  # started by __enter__ only with a reporter
            return
        while not self.stop.wait(reporter.period):
            reporter.update(float(self.ctl[0]))

    def __exit__(self, *exc) -> None:
        self.stop.set()
        if self.thread is not None:
            self.thread.join()


def make_reporter(progress, t_start: float, t_end: float) -> Reporter | None:
    if not progress:
        return None
    return Reporter(progress_bar if progress is True else progress, t_start, t_end)


def progress_bar(fraction: float, t: float) -> None:
    width = 30
    done = int(width * fraction)
    sys.stderr.write(f"\r  [{'#' * done}{'.' * (width - done)}] {100 * fraction:5.1f} %  t = {t:.6g}")
    if fraction >= 1.0:
        sys.stderr.write("\n")
    sys.stderr.flush()
