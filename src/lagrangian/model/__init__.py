"""Stage 1 — the model: a frozen, checked description of the system (no derivation here).

`lagrangian.model.vectors` is the package's vector toolkit (`Vector`, and the 3-component algebra
that kinematics and the recursive dynamics share).
"""

# Shared with the later stages: sign assumptions, size limits, free bodies, texts, checks.
from ._assumptions import SIGN_RELATIONS as SIGN_RELATIONS
from ._assumptions import Assumptions as Assumptions
from ._assumptions import SignFact as SignFact
from ._assumptions import check_sign as check_sign
from ._assumptions import range_text as range_text
from ._assumptions import sign_problem as sign_problem
from ._expr import FUNCTIONS as FUNCTIONS
from ._expr import ExpressionError as ExpressionError
from ._expr import parse_expression as parse_expression
from ._free import FreeJoint as FreeJoint
from ._free import free_joints as free_joints
from ._free import inertia_problem as inertia_problem
from ._limits import MAX_OPS_VARIABLE as MAX_OPS_VARIABLE
from ._limits import NotFinite as NotFinite
from ._limits import equations_size as equations_size
from ._limits import max_ops as max_ops
from ._limits import real_value as real_value
from ._reference import INERTIAL_LOAD_NAMES as INERTIAL_LOAD_NAMES
from ._shapes import rotation_to as rotation_to
from ._texts import in_language as in_language
from ._toml import load_model as load_model
from ._toml import parse_model as parse_model
from ._toml_guard import check_nesting as check_nesting
from ._unilateral import coefficient_values_error as coefficient_values_error
from .build import ModelBuilder as ModelBuilder
from .spec import *  # noqa: F403
from .spec import __all__ as _spec_all
from .urdf import load_urdf as load_urdf
from .urdf import parse_urdf as parse_urdf
from .vectors import Vector as Vector

__all__ = ["FUNCTIONS", "ExpressionError", "parse_expression", "load_model", "parse_model", "Vector",
           "ModelBuilder", "load_urdf", "parse_urdf", *_spec_all,
           "SIGN_RELATIONS", "Assumptions", "SignFact", "range_text", "sign_problem", "FreeJoint", "free_joints",
           "inertia_problem", "MAX_OPS_VARIABLE", "NotFinite", "equations_size", "max_ops", "real_value",
           "INERTIAL_LOAD_NAMES", "rotation_to", "in_language", "check_nesting", "coefficient_values_error",
           "check_sign"]
