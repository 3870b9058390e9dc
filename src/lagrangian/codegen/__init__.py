"""Stage 5 — code generation: the equations of motion as code, for the package and for export.

Between `analysis` and `numerics`: symbols in, source text out, nothing compiled or run here.

- ``generate_c(eom, integrals, events)`` → `GeneratedSource`: the C of M q̈ = F (never M⁻¹), the
  monitors and the events, with the C runtime after it (`_codegen`); ``generate_dae_c`` for
  complementary constraints (`_codegen_dae`) and ``generate_free_c`` for free bodies
  (`_free_codegen`);
- ``mass_forces_form(eom)`` → `MassForcesForm`: the exact rewritings of M and F that make the code
  cheaper (`_rewrite`);
- ``c_block``, ``c_sequence``, ``c_expression``, ``c_function``: the C printer, common
  subexpressions shared (`_cprint`, `_cfunction`); long functions are cut into parts compiled in
  parallel (`_cparts`), the units of cold parts marked by ``COLD_UNIT``;
- ``runtime_source(name)``: the C runtime, plain files in ``runtime/`` copied whole (`_runtime`);
- ``export(eom, target, directory)``: standalone code in C, NumPy, JAX or Octave (`_export`, one
  module per target in `targets`).

`numerics` compiles and runs what this stage prints; `output` and the command line re-export
``export``.  This stage imports only the stages before it (model, kinematics, dynamics, analysis).
"""

from __future__ import annotations

from typing import TYPE_CHECKING

from .._lazy import lazy_names

# Each name is imported from its module on first use (`lagrangian._lazy`): the compiled simulation
# does not load the export targets, nor SymPy's printers that they use.
_WHERE = {
    "._cfunction": ("c_function",),
    "._cparts": ("COLD_UNIT",),
    "._codegen": ("GeneratedSource", "generate_c", "monitor_expressions"),
    "._codegen_dae": ("GeneratedDAE", "generate_dae_c"),
    "._cprint": ("c_block", "c_expression", "c_sequence"),
    "._free_codegen": ("FreeSource", "generate_free_c"),
    "._rewrite": ("MassForcesForm", "mass_forces_form"),
    "._runtime": ("RUNTIME_FILES", "runtime_source"),
    "._export": ("EXPORT_TARGETS", "check_target", "export", "export_files", "exported_symbols",
                 "model_identifier"),
    ".targets.base": ("AbstractTarget", "ExportedSymbols"),
}
__getattr__, __dir__ = lazy_names(__name__, _WHERE)

if TYPE_CHECKING:  # what static tools see: the same names, imported eagerly
    from ._cfunction import c_function as c_function
    from ._codegen import GeneratedSource as GeneratedSource
    from ._codegen import generate_c as generate_c
    from ._codegen import monitor_expressions as monitor_expressions
    from ._codegen_dae import GeneratedDAE as GeneratedDAE
    from ._codegen_dae import generate_dae_c as generate_dae_c
    from ._cparts import COLD_UNIT as COLD_UNIT
    from ._cprint import c_block as c_block
    from ._cprint import c_expression as c_expression
    from ._cprint import c_sequence as c_sequence
    from ._export import EXPORT_TARGETS as EXPORT_TARGETS
    from ._export import check_target as check_target
    from ._export import export as export
    from ._export import export_files as export_files
    from ._export import exported_symbols as exported_symbols
    from ._export import model_identifier as model_identifier
    from ._free_codegen import FreeSource as FreeSource
    from ._free_codegen import generate_free_c as generate_free_c
    from ._rewrite import MassForcesForm as MassForcesForm
    from ._rewrite import mass_forces_form as mass_forces_form
    from ._runtime import RUNTIME_FILES as RUNTIME_FILES
    from ._runtime import runtime_source as runtime_source
    from .targets.base import AbstractTarget as AbstractTarget
    from .targets.base import ExportedSymbols as ExportedSymbols

__all__ = [
    "COLD_UNIT",
    "EXPORT_TARGETS",
    "RUNTIME_FILES",
    "AbstractTarget",
    "ExportedSymbols",
    "FreeSource",
    "GeneratedDAE",
    "GeneratedSource",
    "MassForcesForm",
    "c_block",
    "c_expression",
    "c_function",
    "c_sequence",
    "check_target",
    "export",
    "export_files",
    "exported_symbols",
    "generate_c",
    "generate_dae_c",
    "generate_free_c",
    "mass_forces_form",
    "model_identifier",
    "monitor_expressions",
    "runtime_source",
]
