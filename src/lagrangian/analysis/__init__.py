"""Stage 4 — analysis of the equations: first integrals."""

from ._integrals import FirstIntegral as FirstIntegral
from ._integrals import first_integrals as first_integrals

__all__ = ["FirstIntegral", "first_integrals"]
