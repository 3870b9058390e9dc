"""The ``jax`` export: one module of pure ``jax.numpy`` functions (`lagrangian.export`).

The same expressions as the ``numpy`` export (`targets.numpy`), printed by SymPy's
``JaxPrinter``; since JAX arrays are immutable, M and F are assembled with
``jax.numpy.stack`` instead of item assignment.  Every function is jit-able and vmap-able
(no Python control flow depends on array values), and works on leading batch axes as the
NumPy export does.  Double precision needs ``jax.config.update("jax_enable_x64", True)``
before the first call (JAX computes in float32 by default); the module does not change
that global setting itself.
"""

from __future__ import annotations

from typing import final

from .base import AbstractTarget, ExportedSymbols
from .numpy import constrained_functions, module_header, python_function

__all__ = ["JaxTarget", "jax_module"]

XP = "jax.numpy"


def _stacked(name: str, count: int, shape: str) -> list[str]:
    items = ", ".join(f"{XP}.broadcast_to(_o{k}, shape)" for k in range(count))
    return [f"    {name} = {XP}.stack([{items}], axis=-1).reshape(shape + {shape}).astype(q.dtype)",
            f"    return {name}"]


def jax_module(symbols: ExportedSymbols) -> str:
    """The text of the module (see the module docstring and docs/export.md)."""
    n = symbols.n
    from sympy.printing.numpy import JaxPrinter  # SymPy's printers load only when a target prints

    printer = JaxPrinter({"fully_qualified_modules": True})
    header = module_header(symbols, "jax",
                           "Needs only JAX; jit-able and vmap-able; enable jax_enable_x64 for double precision.",
                           "import jax\nimport jax.numpy", XP)
    mass = python_function(
        "def mass_matrix(q, p=None, t=0.0):",
        "M(q, t), shape (..., n, n), for q of shape (..., n).",
        [f"    q = {XP}.asarray(q, dtype=float)", "    p = parameter_array(p)",
         f"    shape = {XP}.broadcast_shapes(q.shape[:-1], p.shape[:-1], {XP}.shape(t))"],
        [f"_o{k}" for k in range(n * n)], symbols.M, symbols, _stacked("M", n * n, f"({n}, {n})"), printer)
    forcing = python_function(
        "def forcing(t, q, qd, p=None):",
        "F(q, q', t), shape (..., n), for q and qd of shape (..., n).",
        [f"    q = {XP}.asarray(q, dtype=float)", f"    qd = {XP}.asarray(qd, dtype=float)",
         "    p = parameter_array(p)",
         f"    shape = {XP}.broadcast_shapes(q.shape[:-1], qd.shape[:-1], p.shape[:-1], {XP}.shape(t))"],
        [f"_o{k}" for k in range(n)], symbols.F, symbols, _stacked("F", n, f"({n},)"), printer)
    if symbols.rows:
        return header + "\n" + mass + "\n\n" + forcing + "\n\n" + constrained_functions(symbols, XP, printer)
    rhs = f'''def rhs(t, y, p=None):
    """y' = (q', q'') with q'' solved from M q'' = F; y of shape (2n,) or (N, 2n), batched solve."""
    y = {XP}.asarray(y, dtype=float)
    p = parameter_array(p)
    q, qd = y[..., :{n}], y[..., {n}:]
    M = mass_matrix(q, p, t)
    F = forcing(t, q, qd, p)
    qdd = {XP}.linalg.solve(M, F[..., None])[..., 0]
    return {XP}.concatenate([{XP}.broadcast_to(qd, qdd.shape), qdd], axis=-1)
'''
    return header + "\n" + mass + "\n\n" + forcing + "\n\n" + rhs


@final
class JaxTarget(AbstractTarget):
    """One module ``<name>.py`` of jit-able, vmap-able ``jax.numpy`` functions (module docstring)."""

    name = "jax"

    def files(self, symbols: ExportedSymbols) -> dict[str, str]:
        return {f"{symbols.identifier}.py": jax_module(symbols)}
