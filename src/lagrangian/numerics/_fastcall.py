"""The one-state right-hand side without ctypes' per-call cost (`_fastcall.c`).

`rhs_caller(function, n_state, n_params)` wraps a compiled model's ``lg_eval_rhs`` (a ctypes
function) in a small CPython extension type (built against NumPy's headers) called with the vectorcall protocol: one state
then costs the C evaluation plus ~0.1 µs, instead of ~4 µs through ctypes (see
``benchmarks/rhs_vs_peers.py``).  The extension is built once per Python version and
compiler, cached and checked like the models (`_compile.load_verified`).  Where it cannot be built (no
``Python.h``, as with some distributions' Python without its -dev package), `rhs_caller`
returns None and the caller keeps ctypes.
"""

from __future__ import annotations

import _ctypes
import ctypes
import importlib.util
import sysconfig
from functools import lru_cache
from importlib import resources
from pathlib import Path
from types import ModuleType

from ..errors import SimulationError
from ._compile import load_verified

__all__ = ["rhs_caller"]

_MODULE = "lagrangian_fastcall"


@lru_cache(maxsize=1)
def _module() -> ModuleType | None:
    include = sysconfig.get_paths().get("include")
    if not include or not (Path(include) / "Python.h").exists():
        return None
    source = resources.files(__package__).joinpath("_fastcall.c").read_text(encoding="utf-8")
    suffix = sysconfig.get_config_var("EXT_SUFFIX") or ".so"
    import numpy  # its headers: the wrapper reads arrays with NumPy's C API

    flags = (f"-I{include}", f"-I{numpy.get_include()}")
    try:
        return load_verified(source, source + suffix + numpy.__version__, _import, flags=flags,
                             name=_MODULE + suffix)
    except SimulationError:
        return None


def _import(path: Path) -> ModuleType:
    spec = importlib.util.spec_from_file_location(_MODULE, path)
    if spec is None or spec.loader is None:
        raise ImportError(f"cannot import {path}")
    module = importlib.util.module_from_spec(spec)  # the dlopen: `load_verified` has checked the file
    spec.loader.exec_module(module)
    return module


def rhs_caller(function: _ctypes.CFuncPtr, n_state: int, n_params: int, library: object):
    """``caller(t, y, p, out) -> status`` running ``function`` on one state, or None.

    ``library`` (the ctypes library ``function`` comes from) is kept alive by the caller,
    so the code it points to stays loaded as long as the caller exists.
    """
    module = _module()
    if module is None:
        return None
    address = ctypes.cast(function, ctypes.c_void_p).value
    return module.RhsCaller(address, n_state, n_params, library)
