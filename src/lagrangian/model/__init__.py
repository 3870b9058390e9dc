"""Stage 1 — the model: a frozen, checked description of the system (no derivation here)."""

from ._expr import FUNCTIONS as FUNCTIONS
from ._expr import ExpressionError as ExpressionError
from ._expr import parse_expression as parse_expression
from ._toml import load_model as load_model
from ._toml import parse_model as parse_model
from .vectors import Vector as Vector
from .build import ModelBuilder as ModelBuilder
from .urdf import load_urdf as load_urdf
from .urdf import parse_urdf as parse_urdf
from .spec import *  # noqa: F403
from .spec import __all__ as _spec_all

__all__ = ["FUNCTIONS", "ExpressionError", "parse_expression", "load_model", "parse_model", "Vector",
           "ModelBuilder", "load_urdf", "parse_urdf", *_spec_all]
