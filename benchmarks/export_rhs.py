"""The exported code against the package and against SymPy's ``lambdify``, same run.

For the top and the planar chains (n = 5, 10):

* **C export** — ``<name>_rhs_k`` of ``lagrangian export --to c`` (its constants computed once, as
  the package computes its own) called in a C loop over 10^4 states (a small driver compiled with
  the package's flags ``gcc -O2 -fno-math-errno``, timed in C with ``clock_gettime``), against
  the in-package compiled ``CompiledSystem.rhs`` on the same 10^4 states (one C call that
  loops inside: the same per-state work without Python between states).  Target: within 10 %.
* **NumPy export** — ``rhs(t, Y)`` of ``lagrangian export --to numpy`` on 10^4 states at once,
  against ``sympy.lambdify(..., cse=True)`` of the same M and F (SymPy form: ``eom.to_sympy()``)
  with the same batched ``numpy.linalg.solve``.
* **JAX export** — when JAX is installed: ``jax.jit(jax.vmap(rhs))`` on 10^5 states (CPU),
  after one warm-up call.

Before anything is timed, every variant's q̈ is compared with the package's (max relative
difference printed).  Times are the best of ``--repeat``.

Run:  .venv/bin/python benchmarks/export_rhs.py [--repeat 5] [--sizes 5 10]
"""

from __future__ import annotations

import argparse
import importlib.util
import shutil
import subprocess
import tempfile
import time
from pathlib import Path

import numpy as np
import sympy as sp

import lagrangian
from lagrangian.model import zoo

STATES = 10_000

DRIVER = r"""
#include <stdio.h>
#include <stdlib.h>
#include <time.h>
#include "NAME.h"
/* argv: count, then reads count*(2n) doubles of y and np of p from stdin; prints ns/state of
   NAME_rhs_k (constants once, as the package does) and of NAME_rhs (constants on every call), then
   every state's out. */
int main(int argc, char **argv) {
    int count = atoi(argv[1]), repeat = atoi(argv[2]), n2 = 2 * UPPER_N, i, r;
    double *y = malloc(sizeof(double) * count * n2), *out = malloc(sizeof(double) * count * n2);
    double p[UPPER_NP + 1], k[UPPER_NK + 1], best = 1e300, plain = 1e300;
    for (i = 0; i < count * n2; ++i) if (scanf("%lf", &y[i]) != 1) return 2;
    for (i = 0; i < UPPER_NP; ++i) if (scanf("%lf", &p[i]) != 1) return 2;
    for (r = 0; r < repeat; ++r) {
        struct timespec a, b;
        clock_gettime(CLOCK_MONOTONIC, &a);
        for (i = 0; i < count; ++i) NAME_rhs(0.0, y + i * n2, p, out + i * n2);
        clock_gettime(CLOCK_MONOTONIC, &b);
        double ns = (b.tv_sec - a.tv_sec) * 1e9 + (b.tv_nsec - a.tv_nsec);
        if (ns < plain) plain = ns;
        clock_gettime(CLOCK_MONOTONIC, &a);
        NAME_constants(p, k);
        for (i = 0; i < count; ++i) NAME_rhs_k(0.0, y + i * n2, p, k, out + i * n2);
        clock_gettime(CLOCK_MONOTONIC, &b);
        ns = (b.tv_sec - a.tv_sec) * 1e9 + (b.tv_nsec - a.tv_nsec);
        if (ns < best) best = ns;
    }
    printf("%.6f %.6f\n", best / count, plain / count);
    for (i = 0; i < count * n2; ++i) printf("%.17g\n", out[i]);
    return 0;
}
"""


def _best(fn, repeat: int) -> float:
    times = []
    for _ in range(repeat):
        start = time.perf_counter()
        fn()
        times.append(time.perf_counter() - start)
    return min(times)


def _rel(a: np.ndarray, b: np.ndarray) -> float:
    return float(np.max(np.abs(a - b)) / max(np.max(np.abs(b)), 1e-300))


def _import(path: Path):
    spec = importlib.util.spec_from_file_location(path.stem, path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def bench(title: str, eom: lagrangian.EquationsOfMotion, repeat: int, work: Path) -> None:
    n = len(eom.q)
    system = lagrangian.CompiledSystem(eom, integrals=())
    p_pkg = system.parameter_vector()
    p = np.array([float(v) for v in eom.model.parameter_values.values()])
    rng = np.random.default_rng(0)
    Y = np.column_stack([rng.uniform(0.3, 2.8, (STATES, n)), rng.uniform(-3.0, 3.0, (STATES, n))])
    reference = system.rhs(0.0, Y, p_pkg)
    t_pkg = _best(lambda: system.rhs(0.0, Y, p_pkg), repeat) / STATES * 1e9
    print(f"{title} ({n} coordinates), {STATES} states")
    print(f"  in-package C, one batched call                 {t_pkg:9.1f} ns/state")

    if shutil.which("gcc"):
        (header, source) = lagrangian.export(eom, "c", work / f"c{n}")
        ident = header.stem
        driver = work / f"c{n}" / "driver.c"
        driver.write_text(DRIVER.replace("UPPER", ident.upper()).replace("NAME", ident))
        exe = work / f"c{n}" / "driver"
        # The package's own flags (numerics._compile.FLAGS): -fno-math-errno lets sqrt be inlined.
        subprocess.run(["gcc", "-O2", "-fno-math-errno", "-o", str(exe), str(driver), str(source), "-lm"],
                       check=True)
        text = "\n".join(repr(float(v)) for v in (*Y.ravel(), *p))
        # Rounds interleaved with the package's timing, the best of each kept: on a loaded machine a
        # slow spell then hits both sides rather than one.
        ns = plain = float("inf")
        for _ in range(repeat):
            t_pkg = min(t_pkg, _best(lambda: system.rhs(0.0, Y, p_pkg), 1) / STATES * 1e9)
            out = subprocess.run([str(exe), str(STATES), "3"], input=text, capture_output=True, text=True,
                                 check=True).stdout.split()
            ns, plain = min(ns, float(out[0])), min(plain, float(out[1]))
        values = np.array([float(v) for v in out[2:]]).reshape(STATES, 2 * n)
        print(f"  in-package C, best with the export's rounds    {t_pkg:9.1f} ns/state")
        print(f"  C export, rhs_k in a C loop                    {ns:9.1f} ns/state   ratio {ns / t_pkg:5.2f}"
              f"   max rel. diff {_rel(values, reference):.1e}")
        print(f"  C export, rhs (constants on each call)         {plain:9.1f} ns/state   ratio {plain / t_pkg:5.2f}")

    (path,) = lagrangian.export(eom, "numpy", work / f"np{n}")
    module = _import(path)
    values = module.rhs(0.0, Y, p)
    t_np = _best(lambda: module.rhs(0.0, Y, p), repeat) / STATES * 1e9
    s = eom.to_sympy()
    args = [s.t, *s.q, *s.qd, *s.parameters]
    fM = sp.lambdify(args, list(s.M), modules="numpy", cse=True)  # a list: entries may be constants
    fF = sp.lambdify(args, list(s.F), modules="numpy", cse=True)

    def lambdified():
        cols = [np.zeros(STATES), *Y.T, *(np.full(STATES, v) for v in p)]
        M = _stack(fM(*cols)).T.reshape(STATES, n, n)
        F = _stack(fF(*cols)).T
        return np.concatenate([Y[:, n:], np.linalg.solve(M, F[..., None])[..., 0]], axis=1)

    lam = lambdified()
    t_lam = _best(lambdified, repeat) / STATES * 1e9
    print(f"  NumPy export, one batched call                 {t_np:9.1f} ns/state   "
          f"max rel. diff {_rel(values, reference):.1e}")
    print(f"  sympy.lambdify(cse=True) of M, F + solve       {t_lam:9.1f} ns/state   ratio export/lambdify "
          f"{t_np / t_lam:5.2f}   max rel. diff {_rel(lam, reference):.1e}")

    if importlib.util.find_spec("jax") is not None:
        import jax

        jax.config.update("jax_enable_x64", True)
        (path,) = lagrangian.export(eom, "jax", work / f"jax{n}")
        jm = _import(path)
        big = np.tile(Y, (10, 1))
        f = jax.jit(jax.vmap(jm.rhs, in_axes=(None, 0, None)))
        values = np.asarray(f(0.0, big, p))[:STATES]
        t_jax = _best(lambda: f(0.0, big, p).block_until_ready(), repeat) / len(big) * 1e9
        print(f"  JAX export, jit(vmap), 10^5 states (CPU)       {t_jax:9.1f} ns/state   "
              f"max rel. diff {_rel(values, reference):.1e}")


def _stack(value) -> np.ndarray:
    """A lambdified list of per-state arrays and constants → (len, N)."""
    return np.array([np.broadcast_to(np.asarray(v, dtype=float), (STATES,)) for v in value])


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=5)
    parser.add_argument("--sizes", type=int, nargs="*", default=[5, 10])
    args = parser.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        work = Path(tmp)
        bench("Lagrange top", lagrangian.derive(lagrangian.lagrange_top()), args.repeat, work)
        for size in args.sizes:
            bench(f"planar chain {size}", lagrangian.derive(zoo.planar_chain(size)), args.repeat, work)


if __name__ == "__main__":
    main()
