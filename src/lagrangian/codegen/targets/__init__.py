"""The export targets (`lagrangian.export`): one module per language, each an `AbstractTarget` (`base`).

``c`` (C99 and libm), ``numpy``, ``jax`` and ``octave``; the dispatcher, `lagrangian.codegen._export`,
chooses among them by name.  Importing a target loads no SymPy: its printer is imported when it prints.
"""

from .base import AbstractTarget as AbstractTarget
from .base import ExportedRow as ExportedRow
from .base import ExportedSymbols as ExportedSymbols
from .c import CTarget as CTarget
from .jax import JaxTarget as JaxTarget
from .numpy import NumpyTarget as NumpyTarget
from .octave import OctaveTarget as OctaveTarget

__all__ = ["AbstractTarget", "CTarget", "ExportedRow", "ExportedSymbols", "JaxTarget", "NumpyTarget", "OctaveTarget"]
