"""Reference systems: the one source of example models for tests, examples and benchmarks."""

from __future__ import annotations

from importlib import resources

from ._toml import parse_model
from .spec import Model

__all__ = ["lagrange_top", "LAGRANGE_TOP_TOML"]


def _read(name: str) -> str:
    return resources.files("lagrangian.model").joinpath("data", name).read_text(encoding="utf-8")


#: The seed's heavy symmetric top as a model file (the default of `lagrangian derive`).
LAGRANGE_TOP_TOML = _read("lagrange_top.toml")


def lagrange_top() -> Model:
    """The seed's worked example: the heavy symmetric top with a fixed point O."""
    return parse_model(LAGRANGE_TOP_TOML, source="<lagrange_top>")
