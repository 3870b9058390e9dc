"""Code export: the equations M(q, t) q̈ = F(q, q̇, t) as source files that stand on their own.

``export(eom, target, directory)`` writes, for ``target`` (each an `AbstractTarget` of `targets`):

- ``"numpy"``: one module ``<name>.py`` that needs only NumPy (`targets.numpy`);
- ``"c"``: ``<name>.h`` and ``<name>.c`` that need only libm (`targets.c`);
- ``"jax"``: one module ``<name>.py`` of jit-able, vmap-able ``jax.numpy`` functions (`targets.jax`);
- ``"octave"``: ``.m`` function files for GNU Octave and MATLAB (`targets.octave`).

This module is the dispatcher: it derives the symbols every target prints (`exported_symbols`),
hands them to the target, and writes the files; the targets import nothing from it.

Every file names the model, the ``lagrangian`` version, the parameters with their default
values and the state order y = (q_1..q_n, q̇_1..q̇_n).  The expressions are the derivation's
M and F, rewritten only by exact identities (M's terms grouped, angle sums expanded, as in
`_rewrite`), each function's common subexpressions shared (SymEngine's ``cse``); q̈
is solved from M q̈ = F (never M⁻¹ formed symbolically).

The C export also carries the first integrals (`lagrangian.first_integrals`) and, for a model
with complementary constraints, their rows A q̇ + b = 0, A q̈ + c = 0 and the augmented solve
of M q̈ = F + Aᵀλ for q̈ and λ; its M and F are the in-package library's form
(`_rewrite.mass_forces_form`: each body's bias shared, parameter-only coefficients
computed once per parameter set).

The NumPy, JAX and Octave files also carry the complementary rows (``constraint_rows``) and
solve the augmented system [M −Aᵀ; A 0] [q̈; λ] = [F; −c − 2α g − β² f] (``rhs_multipliers``;
``rhs`` is it with α = β = 0).

What is not exported: every target refuses a model with an exact Coulomb contact (stick/slip
needs the event machinery of `lagrangian.simulate`): an `ExportError` names the fix.

The directory is written atomically: the files are built in a temporary sibling
directory that is then renamed into place, so a failure leaves nothing half-written.
"""

from __future__ import annotations

import os
import re
import shutil
import tempfile
from collections.abc import Callable
from pathlib import Path
from typing import Any

import symengine as se

from .._abs_derivative import settled
from ..dynamics import EquationsOfMotion
from ..errors import ExportError, OutputError
from ..model.spec import CoulombFriction
from ._rewrite import MassForcesForm, collect_by_state, expand_angle_sums, mass_forces_form, smaller
from .targets.base import AbstractTarget, ExportedRow, ExportedSymbols
from .targets.c import CTarget
from .targets.jax import JaxTarget
from .targets.numpy import NumpyTarget
from .targets.octave import OctaveTarget

__all__ = ["EXPORT_TARGETS", "check_target", "export", "export_files", "exported_symbols", "model_identifier",
           "validate_exportable"]


def _version() -> str:
    from .. import __version__  # late: the package's __init__ imports this stage

    return __version__


def _comment_safe(text: str) -> str:
    """The model name as it may appear inside a comment: printable, one line, no ``*/``."""
    clean = "".join(ch if ch.isprintable() else "?" for ch in text)
    return clean.replace("*/", "* /").replace("/*", "/ *")


def model_identifier(name: str) -> str:
    """Make an identifier of a model's name: ``double pendulum`` → ``double_pendulum``.

    Parameters
    ----------
    name : str
        The model's name.

    Returns
    -------
    str
        ASCII letters, digits and ``_``, not starting with a digit.
    """
    ident = re.sub(r"[^0-9A-Za-z]+", "_", name).strip("_").lower() or "model"
    return ident if not ident[0].isdigit() else "m_" + ident


def validate_exportable(eom: EquationsOfMotion, target: str = "numpy") -> None:
    """Refuse what the exported ``rhs`` of ``target`` could not express (module docstring)."""
    exact = [load.name for load in eom.model.loads if isinstance(load, CoulombFriction) and load.exact]
    if exact:
        raise ExportError(
            f"`{eom.model.name}` has the exact Coulomb contact `{exact[0]}` (regularization = 0): its stick/slip "
            "phases need the event machinery of `lagrangian.simulate`, so nothing is exported.",
            fix=f"give `{exact[0]}` a positive regularization (e.g. 1e-3) to export the smooth model")


def exported_symbols(eom: EquationsOfMotion, target: str = "numpy") -> ExportedSymbols:
    """The equations over private symbols (`ExportedSymbols`), checked for stray symbols.

    M and F, and the constraint rows; for a ``target`` that prints the in-package form (``"c"``:
    `AbstractTarget.in_package_form`), also the first integrals and M, F in that form.

    Parameters
    ----------
    eom : EquationsOfMotion
        The equations.
    target : str, optional
        The export target.

    Returns
    -------
    ExportedSymbols
        What the target prints.
    """
    validate_exportable(eom, target)
    n = len(eom.q)
    params = tuple(p.name for p in eom.model.parameters)
    values = eom.model.parameter_values
    y = tuple(se.Symbol(f"_y{i}") for i in range(2 * n))
    p = tuple(se.Symbol(f"_p{k}") for k in range(len(params)))
    t = se.Symbol("_t")
    private: dict[se.Basic, se.Basic] = dict(zip((*eom.q, *eom.qd), y, strict=True))
    private.update({se.Symbol(name): sym for name, sym in zip(params, p, strict=True)})
    private[eom.t] = t

    def rename(expr: se.Basic, what: str) -> se.Basic:
        expr = expr if isinstance(expr, se.Basic) else se.Integer(0) + expr  # a Python number only
        unknown = sorted(str(s) for s in expr.free_symbols if s not in private)
        if unknown:
            raise ExportError(f"{what} contains `{unknown[0]}`, which is neither a coordinate, a rate, a parameter "
                              "nor t.", fix="declare it as a parameter of the model")
        return settled(expr).xreplace(private)  # d|u|/dx as sign(u) du/dx: SymPy's printers have no Derivative

    M = [rename(eom.M[i][j], f"M[{i}][{j}]") for i in range(n) for j in range(n)]
    F = [rename(eom.F[i], f"F[{i}]") for i in range(n)]
    # The compiled package's rewritings, exact identities that make the code cheaper
    # (`_rewrite`): M's entries grouped by their function of q, and sin/cos of
    # sums of coordinates by the addition formulas, so that cse shares 2n trigonometric calls.
    M = [smaller(e, collect_by_state([se.expand(e)], y)[0]) for e in M]
    flat = expand_angle_sums(M + F, list(y[:n]))
    M, F = flat[: n * n], flat[n * n:]
    coords = eom.coordinates
    extras: dict[str, Any] = {"rows": _rows(eom, rename)}
    if target in EXPORT_TARGETS and EXPORT_TARGETS[target].in_package_form:
        extras.update(_c_extras(eom, private, rename))
    return ExportedSymbols(
        name=_comment_safe(eom.model.name), identifier=model_identifier(eom.model.name), version=_version(),
        coordinates=coords, state=(*coords, *(c + "_dot" for c in coords)), parameters=params,
        defaults=tuple(None if values[k] is None else float(values[k]) for k in params),  # type: ignore[arg-type]
        M=tuple(M), F=tuple(F), y=y, p=p, t=t, **extras)


def _c_extras(eom: EquationsOfMotion, private: dict[se.Basic, se.Basic],
              rename: Callable[[se.Basic, str], se.Basic]) -> dict[str, Any]:
    """The C target's first integrals and M, F in the in-package form."""
    from ..analysis import first_integrals  # analysis precedes codegen; imported for the C target only

    integrals = tuple((fi.name, rename(fi.expression, f"the first integral `{fi.name}`"))
                      for fi in first_integrals(eom))
    form = mass_forces_form(eom)
    # The shared components become `_s<k>`, the hoisted constants keep their `_k<j>` names.
    local = dict(private)
    local.update({sym: se.Symbol(f"_s{k}") for k, (sym, _) in enumerate(form.shared)})
    local.update({sym: sym for sym, _ in form.constants})

    def own(expr: se.Basic) -> se.Basic:
        return expr.xreplace(local)

    fast = MassForcesForm(
        shared=tuple((local[sym], own(e)) for sym, e in form.shared), M=tuple(own(e) for e in form.M),
        F=tuple(own(e) for e in form.F), constants=tuple((sym, own(e)) for sym, e in form.constants))
    return {"integrals": integrals, "fast": fast}


def _rows(eom: EquationsOfMotion, rename: Callable[[se.Basic, str], se.Basic]) -> tuple[ExportedRow, ...]:
    """The complementary constraint rows over the private symbols."""
    return tuple(ExportedRow(
        name=row.name, kind=row.kind, multiplier=str(row.multiplier),
        A=tuple(rename(a, f"the constraint row `{row.name}`") for a in row.coefficients),
        b=rename(row.b, f"the constraint row `{row.name}`"), c=rename(row.bias, f"the constraint row `{row.name}`"),
        f=rename(row.expression, f"the constraint `{row.name}`") if row.kind == "holonomic" else se.Integer(0))
        for row in eom.constraints)


#: target name → the target (`AbstractTarget`): the files it writes.
EXPORT_TARGETS: dict[str, AbstractTarget] = {
    target.name: target for target in (NumpyTarget(), CTarget(), JaxTarget(), OctaveTarget())}


def check_target(target: str) -> None:
    """Raise `ExportError` unless ``target`` is one of `EXPORT_TARGETS`.

    Parameters
    ----------
    target : str
        The name asked for.
    """
    if target not in EXPORT_TARGETS:
        raise ExportError(f"`{target}` is not an export target.",
                          fix="use one of " + ", ".join(f"`{k}`" for k in EXPORT_TARGETS))


def export_files(eom: EquationsOfMotion, target: str) -> dict[str, str]:
    """The files of ``target`` as {file name: text}, nothing written (see `export`).

    Parameters
    ----------
    eom : EquationsOfMotion
        The equations.
    target : str
        The export target.

    Returns
    -------
    dict of str to str
        {file name: text}.
    """
    check_target(target)
    return EXPORT_TARGETS[target].files(exported_symbols(eom, target))


def _write_directory(directory: Path, files: dict[str, str]) -> None:
    """Write ``files`` into ``directory`` atomically (a temporary sibling, then a rename).

    An existing ``directory`` is replaced only when it holds nothing but files of the same
    names (an earlier export); anything else in it is never touched.
    """
    directory = directory.absolute()
    if directory.exists():
        if not directory.is_dir():
            raise OutputError(f"`{directory}` exists and is not a directory.", fix="choose another output directory")
        others = sorted(p.name for p in directory.iterdir() if p.name not in files or not p.is_file())
        if others:
            raise OutputError(f"`{directory}` already holds `{others[0]}`, which this export does not write; "
                              "it is left untouched.", fix="choose a new or empty output directory")
    parent = directory.parent
    tmp = old = None
    try:
        tmp = Path(tempfile.mkdtemp(prefix=f".{directory.name}.", suffix=".tmp", dir=parent))
        for name, text in files.items():
            (tmp / name).write_text(text, encoding="utf-8")
        os.chmod(tmp, 0o777 & ~_umask())
        if directory.exists():
            old = Path(tempfile.mkdtemp(prefix=f".{directory.name}.", suffix=".old", dir=parent))
            os.replace(directory, old / "previous")  # rename(2): the old export set aside whole
        try:
            os.replace(tmp, directory)
        except OSError:
            if old is not None:
                os.replace(old / "previous", directory)
            raise
        tmp = None
    except OSError as exc:
        raise OutputError(f"Cannot write the export directory `{directory}`: {exc.strerror or exc}.",
                          fix="check that its parent folder exists and is writable; nothing was written") from exc
    finally:
        for leftover in (tmp, old):
            if leftover is not None:
                shutil.rmtree(leftover, ignore_errors=True)


def _umask() -> int:
    mask = os.umask(0o022)
    os.umask(mask)
    return mask


def export(eom: EquationsOfMotion, target: str, directory: str | os.PathLike[str]) -> tuple[Path, ...]:
    """Write ``eom``'s M, F and q̇, q̈ = M⁻¹F as standalone code for ``target`` into ``directory``.

    Parameters
    ----------
    eom : EquationsOfMotion
        The equations of motion (`lagrangian.derive`).
    target : str
        ``"numpy"`` (one module, NumPy only: ``PARAMETERS``, ``STATE``, ``mass_matrix``, ``forcing``,
        ``rhs`` batched over leading axes and, with constraints, ``CONSTRAINTS``, ``constraint_rows``
        and ``rhs_multipliers``) or ``"c"`` (``<name>.h`` and ``<name>.c``, libm only:
        ``<name>_rhs``, ``_rhs_k``, ``_constants``, ``_mass_matrix``, ``_forcing``,
        ``_first_integrals``, ``_constraint_rows`` and, with constraints, ``_rhs_multipliers``) or
        ``"jax"`` (the NumPy module's interface in ``jax.numpy``, jit-able and vmap-able) or
        ``"octave"`` (``.m`` function files: ``<name>_parameters``, ``_mass_matrix``, ``_forcing``,
        ``_rhs``); docs/export.md.
    directory : str or PathLike
        Created (with the files) atomically; if it exists, it may hold only the files of an earlier
        export of the same name, which are replaced.

    Returns
    -------
    tuple of Path
        The paths of the written files.

    Raises
    ------
    ExportError
        An unknown ``target``; a model with an exact Coulomb contact (what is not exported is named); a symbol that is not a coordinate, rate,
        parameter nor t.  Nothing is written.
    OutputError
        ``directory`` cannot be written or holds other files.  Nothing is written.

    Examples
    --------
    >>> import lagrangian, tempfile, pathlib
    >>> eom = lagrangian.derive(lagrangian.lagrange_top())
    >>> out = pathlib.Path(tempfile.mkdtemp()) / "top"
    >>> [p.name for p in lagrangian.export(eom, "c", out)]
    ['lagrange_top.h', 'lagrange_top.c']
    """
    files = export_files(eom, target)
    directory = Path(directory)
    _write_directory(directory, files)
    return tuple(directory / name for name in files)
