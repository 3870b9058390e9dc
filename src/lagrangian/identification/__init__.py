"""Stage 7 — identification: a model's parameters fitted to a measured motion.

``identify(model, data, ["m", "l"])`` → `Identification` (estimates, standard errors, the
identifiable combinations, the residuals), by the inverse-dynamics regressor when the equations
are linear in the parameters, else by single or multiple shooting with forward sensitivities.
See docs/identification.md.
"""

from ._base import BaseParameters as BaseParameters
from ._base import base_parameters as base_parameters
from ._data import Measurements as Measurements
from ._data import read_measurements as read_measurements
from ._filter import SavitzkyGolay as SavitzkyGolay
from ._identify import identify as identify
from ._regressor import Regressor as Regressor
from ._result import BaseEstimate as BaseEstimate
from ._result import Identification as Identification
from ._shooting import Shooting as Shooting

__all__ = [
           "BaseEstimate",
           "BaseParameters",
           "Identification",
           "Measurements",
           "Regressor",
           "SavitzkyGolay",
           "Shooting",
           "base_parameters",
           "identify",
           "read_measurements",
]
