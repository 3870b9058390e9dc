"""The slow path of the inputs: Python functions u(t, y) called from the compiled right-hand side.

`Callback` is the one C function pointer through which the compiled law (`_input_code`) calls them;
`call` calls one, turning its failures (an exception, a value that is not a finite number) into a
`SimulationError` that names the input and the time.
"""

from __future__ import annotations

import ctypes
import math
from typing import TYPE_CHECKING, Any

import numpy as np

from ..errors import SimulationError

if TYPE_CHECKING:  # pragma: no cover
    from ._inputs import InputSource

__all__ = ["Callback", "call"]


def call(source: InputSource, t: float, y: np.ndarray) -> float:
    """``source.value(t, y)`` as a finite float, or the `SimulationError` that says why not."""
    try:
        value = source.value(t, y.copy())
        value = float(value)
    except Exception as exc:
        raise SimulationError(f"The input function of `{source.name}` failed at t = {t:.9g}: "
                              f"{type(exc).__name__}: {exc}.",
                              fix=f"make `{source.text}` return a number for every (t, y) of the run") from exc
    if not math.isfinite(value):
        raise SimulationError(f"The input function of `{source.name}` returned {value} at t = {t:.9g}.",
                              fix="return a finite number") from None
    return value


# -- the C callback of the slow path ------------------------------------------------------------------
_CALLBACK = ctypes.CFUNCTYPE(None, ctypes.c_double, ctypes.POINTER(ctypes.c_double),
                             ctypes.POINTER(ctypes.c_double))


class Callback:
    """The one C function pointer through which compiled code calls the Python input functions.

    ``lg_inputs`` calls it with (t, y, u); it fills u with each callable's value.  A Python
    exception cannot cross C: the first one is kept in ``error``, u gets NaN and the run is
    asked to stop (``stop``, the control block's stop request), and `simulate` raises it.
    """

    def __init__(self, sources: tuple[InputSource, ...], n_state: int) -> None:
        self.sources = sources
        self.n_state = n_state
        self.error: SimulationError | None = None
        self.stop: np.ndarray | None = None
        self.calls = 0
        self._function = _CALLBACK(self._call)

    def _call(self, t: float, y_ptr: Any, u_ptr: Any) -> None:
        self.calls += 1
        if self.error is not None:
            for k in range(len(self.sources)):
                u_ptr[k] = math.nan
            return
        y = np.ctypeslib.as_array(y_ptr, shape=(self.n_state,))
        for k, source in enumerate(self.sources):
            try:
                u_ptr[k] = call(source, t, y)
            except SimulationError as exc:
                self.error = exc
                u_ptr[k] = math.nan
                if self.stop is not None:
                    self.stop[0] = 1.0

    def address_as_double(self) -> float:
        """The function's address, its 64 bits read as a double (the C side reads them back)."""
        address = ctypes.cast(self._function, ctypes.c_void_p).value or 0
        return float(np.array([address], dtype=np.uint64).view(np.float64)[0])
