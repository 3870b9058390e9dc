"""lagrangian — Lagrange's equations from a model of frames, bodies and loads.

The pipeline, one stage per subpackage (imports flow one way)::

    model  →  kinematics  →  dynamics  →  analysis  →  output  →  cli
    (spec)    (Ω, V, V*)     (T, U, Q,     (first       (text, LaTeX,
                              L(q_i), M,F)  integrals)    JSON)

Typical use::

    import lagrangian
    model = lagrangian.load_model("examples/lagrange_top.toml")
    eom = lagrangian.derive(model)
    print(lagrangian.render_text(eom))
"""

from __future__ import annotations

from .analysis import FirstIntegral, first_integrals
from .dynamics import EquationsOfMotion, LagrangeEquation, derive
from .errors import DerivationError, KinematicsError, LagrangianError, ModelError, OutputError, SimulationError
from .kinematics import Kinematics
from .model import ModelBuilder, load_model, parse_model
from .model.spec import Model
from .model.zoo import lagrange_top

__version__ = "0.1.0"

__all__ = [
    "__version__",
    "load_model",
    "parse_model",
    "ModelBuilder",
    "Model",
    "lagrange_top",
    "Kinematics",
    "derive",
    "EquationsOfMotion",
    "LagrangeEquation",
    "first_integrals",
    "FirstIntegral",
    "LagrangianError",
    "ModelError",
    "KinematicsError",
    "DerivationError",
    "SimulationError",
    "OutputError",
]


def __dir__() -> list[str]:
    return list(__all__)
