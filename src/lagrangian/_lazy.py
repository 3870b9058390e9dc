"""A package's public names, each imported from its module on first use (PEP 562).

A package face that imports all its modules makes every user of one of them pay for the
others: ``lagrangian simulate`` needs the first integrals, not the equilibria's SciPy or the
bifurcations' SymPy.  With `lazy_names`, ``from lagrangian.analysis import first_integrals``
imports ``analysis/_integrals.py`` (and what it imports) only.
"""

from __future__ import annotations

import importlib
import sys
from collections.abc import Callable, Mapping, Sequence
from typing import Any

__all__ = ["lazy_names"]


def lazy_names(package: str, where: Mapping[str, Sequence[str]]
               ) -> tuple[Callable[[str], Any], Callable[[], list[str]]]:
    """The ``__getattr__`` and ``__dir__`` of ``package``, whose names are ``where``: {module: names}.

    ``module`` is relative to ``package`` (``"._integrals"``).  A name is imported on first use and
    then kept in the package, so later uses are plain attribute reads; an unknown name raises
    `AttributeError`, as a missing attribute does (``from package import _module`` then imports the
    module, as usual).
    """
    module_of = {name: module for module, names in where.items() for name in names}

    def __getattr__(name: str) -> Any:
        module = module_of.get(name)
        if module is None:
            raise AttributeError(f"module {package!r} has no attribute {name!r}")
        value = getattr(importlib.import_module(module, package), name)
        setattr(sys.modules[package], name, value)
        return value

    def __dir__() -> list[str]:
        return sorted(set(vars(sys.modules[package])) | set(module_of))

    return __getattr__, __dir__
