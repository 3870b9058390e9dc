"""Inputs during a motion: what each declared input u (``[inputs]``) does, as one `InputLaw`.

``simulate(source, t_end, inputs={...})`` (and `ensemble`, ``simulate --input``) accepts, per
declared input:

* a number: the input held at that value (a parameter value, as ``parameters={"F": 2.0}``);
* an expression of t, the coordinates, their rates ``<q>_dot`` and the parameters, in the
  model grammar (``"2*sin(3*t)"``, ``"-k1*x - k2*x_dot"``; read by `parse_expression`, never
  evaluated), compiled into the C right-hand side;
* an `InputTable` (samples and an interpolation), read by the compiled code by binary search;
* a `Feedback` (``inputs=feedback``, or ``{"F": feedback}``): u = u* − K (x − x*), compiled in
  with K, x*, u* read from the parameter block, so one library serves any gains;
* a Python callable ``u(t, y) -> float``, y = (q, q̇): the slow path, one Python call per
  right-hand side evaluation, through a C callback (`_input_callback`; documented, for laws the
  grammar cannot say);
* a `Switch` of those sources in turn, at given times (`_input_switch`): a swing-up's table, then
  a feedback.

A model's ``[controls]`` table gives a law per input in the model grammar; it is used when
``inputs=`` does not name that input (``inputs={"F": 0}`` turns it off).

The law's numbers (gains, tables, the callback's address) follow the model's parameters and
the hoisted constants in the ``p`` array (`_input_code` lays them out), so changing them reuses
the compiled library: only the *structure* of the law (which inputs, which expressions, the
tables' kinds and lengths, the switches' numbers of sources) is in the C source.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from functools import cached_property
from typing import Any

import numpy as np
import symengine as se

from ..analysis import Feedback
from ..dynamics import EquationsOfMotion
from ..errors import SimulationError
from ..model import ExpressionError, parse_expression
from ._input_callback import Callback, call
from ._input_switch import Switch
from ._input_table import InputTable

__all__ = ["Callback", "InputLaw", "InputSource", "law_names", "resolve_inputs"]

#: The kinds of a source, in the order of the law's code.
KINDS = ("constant", "expression", "table", "feedback", "callable", "switch")


@dataclass(frozen=True, eq=False)
class InputSource:
    """What one input does: ``kind`` in `KINDS` and its ``value`` (a float, a SymEngine expression,
    an `InputTable`, a `Feedback`, a callable, or a `Switch` whose sources are `InputSource` values);
    ``text`` says it in messages."""

    name: str
    kind: str
    value: Any
    text: str


def law_names(eom: EquationsOfMotion) -> dict[str, se.Basic]:
    """The names an input's expression may use: t, the coordinates, their rates, the parameters
    that are not inputs (an input in terms of another would hide a loop)."""
    names: dict[str, se.Basic] = {"t": eom.t}
    for c, q, qd in zip(eom.model.coordinates, eom.q, eom.qd, strict=True):
        names[c.name] = q
        names[c.name + "_dot"] = qd
    for p in eom.model.parameters:
        if not p.input:
            names[p.name] = se.Symbol(p.name)
    return names


@dataclass(frozen=True, eq=False)
class InputLaw:
    """Every input given a source (module docstring), in the model's order of inputs.

    Attributes
    ----------
    sources : the sources of the inputs that have one (the others keep their parameter value).
    feedback : the `Feedback` that some inputs come from, or None.
    """

    sources: tuple[InputSource, ...] = ()
    feedback: Feedback | None = None
    _callback: Callback | None = field(default=None, repr=False)

    # -- what it does ----------------------------------------------------------------------------
    @property
    def driven(self) -> tuple[InputSource, ...]:
        """The sources the compiled law computes (all but the constants)."""
        return tuple(s for s in self.sources if s.kind != "constant")

    @property
    def constants(self) -> dict[str, float]:
        return {s.name: float(s.value) for s in self.sources if s.kind == "constant"}

    @cached_property
    def leaves(self) -> tuple[tuple[str, InputSource], ...]:
        """(key, source) of every source the compiled law evaluates, in the law's order: each driven
        input's own, or each source of a switch (keyed ``F#0``, ``F#1``, ...; the constants among them too)."""
        out: list[tuple[str, InputSource]] = []
        for s in self.driven:
            if s.kind == "switch":
                out += [(f"{s.name}#{k}", piece) for k, piece in enumerate(s.value.sources)]
            else:
                out.append((s.name, s))
        return tuple(out)

    @property
    def tables(self) -> tuple[InputSource, ...]:
        return tuple(s for _, s in self.leaves if s.kind == "table")

    @property
    def callables(self) -> tuple[InputSource, ...]:
        return tuple(s for _, s in self.leaves if s.kind == "callable")

    @property
    def switches(self) -> tuple[InputSource, ...]:
        return tuple(s for s in self.driven if s.kind == "switch")

    @property
    def _feeds_back(self) -> bool:
        return self.feedback is not None and any(s.kind == "feedback" for _, s in self.leaves)

    def __bool__(self) -> bool:
        return bool(self.sources)

    def regime(self, values: Mapping[str, float | None], inputs: tuple[str, ...]) -> dict[str, str]:
        """Each declared input's regime for `first_integrals`: driven inputs vary, the others are
        constant where their value (``values``) is not 0 and off where it is 0 or not given."""
        driven = {s.name for s in self.driven}
        return {u: "varying" if u in driven else ("constant" if values.get(u) else "off") for u in inputs}

    @cached_property
    def breakpoints(self) -> np.ndarray:
        """Every time where a table's value or a derivative jumps, and every switching time, sorted
        (the integrators restart there)."""
        times = [s.value.breakpoints for s in self.tables] + [np.array(s.value.at) for s in self.switches]
        return np.unique(np.concatenate(times)) if times else np.zeros(0)

    def structure(self) -> tuple:
        """What the compiled code depends on (two laws with equal structures share a library)."""
        def one(s: InputSource) -> tuple:
            if s.kind == "expression":
                return (s.name, s.kind, str(s.value))
            if s.kind == "table":
                return (s.name, s.kind, s.value.interpolation, len(s.value.t))
            if s.kind == "switch":
                return (s.name, s.kind, tuple(one(piece) for piece in s.value.sources))
            return (s.name, s.kind)

        fb = self.feedback
        shape = (fb.states, fb.inputs) if self._feeds_back and fb is not None else ()
        return (tuple(one(s) for s in self.driven), shape, len(self.breakpoints))

    # -- the numbers of the law, after the parameters ----------------------------------------------
    def layout(self) -> dict[str, int]:
        """Offsets in the law's block of ``p`` (`_input_code` documents it)."""
        offsets = {"hint": 0, "callback": 1}
        k = 2
        fb = self.feedback
        if fb is not None and self._feeds_back:
            m, nx = fb.K.shape
            offsets.update(K=k, x_star=k + m * nx, u_star=k + m * nx + nx, x_rate=k + m * nx + nx + m)
            k += m * nx + nx + m + nx
        for key, s in self.leaves:
            if s.kind == "table":
                offsets["table:" + key] = k
                k += len(s.value.data())
        for s in self.switches:
            offsets["switch:" + s.name] = k
            k += len(s.value.at)
        offsets["breaks"] = k
        offsets["size"] = k + len(self.breakpoints)
        return offsets

    def data(self, feedback: Feedback | None = None) -> np.ndarray:
        """The law's block of ``p``: NaN hint, the callback's address, K, x*, u*, the tables, the
        switching times, the breakpoints.  ``feedback``: another feedback of the same shape (an
        ensemble's member)."""
        lay = self.layout()
        out = np.zeros(lay["size"])
        out[lay["hint"]] = np.nan
        if self._callback is not None:
            out[lay["callback"]] = self._callback.address_as_double()
        fb = feedback if feedback is not None else self.feedback
        if "K" in lay and fb is not None:
            m, nx = fb.K.shape
            out[lay["K"]:lay["K"] + m * nx] = fb.K.ravel()
            out[lay["x_star"]:lay["x_star"] + nx] = fb.x_star
            out[lay["u_star"]:lay["u_star"] + m] = fb.u_star
            out[lay["x_rate"]:lay["x_rate"] + nx] = fb.x_star_rate
        for key, s in self.leaves:
            if s.kind == "table":
                a = lay["table:" + key]
                d = s.value.data()
                out[a:a + len(d)] = d
        for s in self.switches:
            a = lay["switch:" + s.name]
            out[a:a + len(s.value.at)] = s.value.at
        out[lay["breaks"]:] = self.breakpoints
        return out

    # -- the same law in Python (constrained models, no C compiler, tests) -----------------------------
    def evaluator(self, eom: EquationsOfMotion, parameters: tuple[str, ...]) -> Callable:
        """``f(t, Y, p, window=None) -> U`` (N, len(driven)): the driven inputs at each state, p the
        model's parameter values; ``window`` a time inside the current interval between breakpoints
        (as the hint): a table's piece and a switch's source are those of that interval."""
        args = [eom.t, *eom.q, *eom.qd, *(se.Symbol(name) for name in parameters)]
        exprs = [s for _, s in self.leaves if s.kind == "expression"]
        lam = se.Lambdify(args, [s.value for s in exprs], cse=True) if exprs else None
        index = _state_index(eom)
        fb = self.feedback

        def f(t: Any, Y: np.ndarray, p: np.ndarray, window: float | None = None) -> np.ndarray:
            Y = np.atleast_2d(np.asarray(Y, dtype=float))
            T = np.broadcast_to(np.asarray(t, dtype=float), (len(Y),))
            out = np.empty((len(Y), len(self.driven)))
            if lam is not None:
                table = np.column_stack([T, Y, np.broadcast_to(p[: len(parameters)], (len(Y), len(parameters)))])
                values = np.asarray(lam(table), dtype=float).reshape(len(Y), len(exprs))

            def leaf(s: InputSource) -> np.ndarray:
                if s.kind == "constant":
                    return np.full(len(Y), float(s.value))
                if s.kind == "expression":
                    return values[:, exprs.index(s)]
                if s.kind == "table":
                    return s.value(T, window)
                if s.kind == "feedback":
                    assert fb is not None
                    return fb(Y[:, [index[name] for name in fb.states]], T)[:, fb.inputs.index(s.name)]
                return np.array([call(s, float(T[i]), Y[i]) for i in range(len(Y))])

            for j, s in enumerate(self.driven):
                if s.kind == "switch":  # the source of the phase each time (or the window) is in
                    phase = np.searchsorted(s.value.at, T if window is None else np.full(len(Y), window),
                                            side="right")
                    pieces = np.array([leaf(piece) for piece in s.value.sources])
                    out[:, j] = pieces[phase, np.arange(len(Y))]
                else:
                    out[:, j] = leaf(s)
            return out

        return f


def _state_index(eom: EquationsOfMotion) -> dict[str, int]:
    n = len(eom.q)
    index = {c: i for i, c in enumerate(eom.coordinates)}
    index.update({c + "_dot": n + i for i, c in enumerate(eom.coordinates)})
    return index


# -- resolving what the user gave -------------------------------------------------------------------
def resolve_inputs(eom: EquationsOfMotion, inputs: Any = None) -> InputLaw:
    """The `InputLaw` of ``inputs`` (module docstring) over the model's ``[controls]``.

    Raises
    ------
    SimulationError
        A name that is not a declared input, an expression that cannot be read or uses a name
        it may not, a value of an unknown kind, a feedback made for other states or inputs,
        a table's own errors.
    """
    model = eom.model
    declared = tuple(model.inputs)
    given: dict[str, Any] = {}
    if isinstance(inputs, Feedback):
        given = {u: inputs for u in inputs.inputs}
    elif isinstance(inputs, Mapping):
        given = dict(inputs)
    elif inputs is not None:
        raise SimulationError(f"inputs= must be a dict by input name or a Feedback, not {type(inputs).__name__}.",
                              fix="e.g. inputs={'F': '2*sin(3*t)'} or inputs=lagrangian.lqr(...)")
    params = {p.name for p in model.parameters if not p.input}
    for name in given:
        if name not in declared:
            if name in params:
                raise SimulationError(f"`{name}` is a parameter of `{model.name}`, not an input.",
                                      fix=f"set parameters with parameters={{'{name}': ...}} (--set {name}=...); "
                                          "inputs are declared under [inputs]")
            raise SimulationError(f"`{name}` is not an input of `{model.name}` (its inputs: "
                                  f"{', '.join(declared) or 'none'}).",
                                  fix="declare it under [inputs] and use it in a load" if not declared else
                                  "give inputs by their declared names")
    controls = dict(getattr(model, "controls", ()) or ())
    names = law_names(eom)
    sources: list[InputSource] = []
    feedback: Feedback | None = None
    for u in declared:
        if u in given:
            source = _source(u, given[u], names, model.name)
        elif u in controls:
            source = InputSource(u, "expression", controls[u], f"[controls] {u}")
            source = _simplified(source)
        else:
            continue
        for part in _parts(source):
            if part.kind == "feedback":
                if feedback is not None and part.value is not feedback:
                    raise SimulationError("Two different feedbacks were given; one law feeds back all its inputs.",
                                          fix="design one feedback with all the inputs (lqr(..., inputs=[...]))")
                feedback = part.value
        sources.append(source)
    if feedback is not None:
        _check_feedback(eom, feedback, {s.name for s in sources if any(p.kind == "feedback" for p in _parts(s))})
    callables = InputLaw(tuple(sources)).callables  # in the law's order, a switch's among them
    callback = Callback(callables, 2 * len(eom.q)) if callables else None
    return InputLaw(tuple(sources), feedback, callback)


def _parts(source: InputSource) -> tuple[InputSource, ...]:
    """A switch's sources, or the source itself."""
    return source.value.sources if source.kind == "switch" else (source,)


def _source(name: str, value: Any, names: Mapping[str, se.Basic], model: str) -> InputSource:
    if isinstance(value, bool) or value is None:
        raise SimulationError(f"The input `{name}` = {value!r}: give a number, an expression, an InputTable, a "
                              "Feedback, a function u(t, y) or a Switch of those.", fix=f"e.g. inputs={{'{name}': 0.5}}")
    if isinstance(value, (int, float, np.integer, np.floating)):
        v = float(value)
        if not math.isfinite(v):
            raise SimulationError(f"The input `{name}` = {v} is not a finite number.", fix=f"give `{name}` a finite value")
        return InputSource(name, "constant", v, repr(v))
    if isinstance(value, str):
        try:
            expr = parse_expression(value, names)
        except ExpressionError as exc:
            raise SimulationError(f"In the input `{name}` = `{value}`: {exc.message}",
                                  fix=exc.fix or "write an expression of t, the coordinates, their rates (`x_dot`) "
                                                 "and the parameters") from None
        if not isinstance(expr, se.Basic) or hasattr(expr, "components"):
            raise SimulationError(f"The input `{name}` = `{value}` is a vector; an input is a scalar.",
                                  fix="remove the basis vectors (R0.x, ...)")
        return _simplified(InputSource(name, "expression", expr, value))
    if isinstance(value, se.Basic):
        unknown = sorted(str(s) for s in value.free_symbols if str(s) not in names)
        if unknown:
            raise SimulationError(f"The input `{name}` uses `{unknown[0]}`, which is neither t, a coordinate, a rate "
                                  "nor a parameter (an input may not name another input).",
                                  fix="write it with t, the coordinates, `<coordinate>_dot` and the parameters")
        return _simplified(InputSource(name, "expression", value, str(value)))
    if isinstance(value, InputTable):
        return InputSource(name, "table", value, repr(value))
    if isinstance(value, Feedback):
        if name not in value.inputs:
            raise SimulationError(f"The feedback given for `{name}` computes {', '.join(value.inputs)}, not `{name}`.",
                                  fix="give each input the feedback that computes it, or inputs=feedback")
        return InputSource(name, "feedback", value, "feedback")
    if isinstance(value, Switch):  # each source resolved as the input's own (none is a Switch: `Switch` says so)
        pieces = tuple(_source(name, piece, names, model) for piece in value.sources)
        text = " then ".join(f"{piece.text} from t = {a:g}" if k else piece.text
                             for k, (piece, a) in enumerate(zip(pieces, (0.0, *value.at), strict=True)))
        return InputSource(name, "switch", Switch(*pieces, at=value.at), text)
    if callable(value):
        return InputSource(name, "callable", value, getattr(value, "__name__", "a function"))
    raise SimulationError(f"The input `{name}` is a {type(value).__name__}; give a number, an expression (text), an "
                          "InputTable, a Feedback, a function u(t, y) or a Switch of those.",
                          fix=f"e.g. inputs={{'{name}': '2*sin(3*t)'}}")


def _simplified(source: InputSource) -> InputSource:
    """An expression without any free symbol is the constant it is (``"2*pi"``)."""
    expr = source.value
    if not expr.free_symbols:
        try:
            v = float(expr)
        except (TypeError, RuntimeError):
            raise SimulationError(f"The input `{source.name}` = `{source.text}` is not a real number.",
                                  fix="write a real expression") from None
        if not math.isfinite(v):
            raise SimulationError(f"The input `{source.name}` = `{source.text}` is not finite.",
                                  fix="write a finite expression")
        return InputSource(source.name, "constant", v, source.text)
    return source


def _check_feedback(eom: EquationsOfMotion, fb: Feedback, used: set[str]) -> None:
    index = _state_index(eom)
    unknown = [s for s in fb.states if s not in index]
    if unknown:
        raise SimulationError(f"The feedback's state `{unknown[0]}` is not a coordinate or a rate of "
                              f"`{eom.model.name}` (it was designed for `{fb.model}`).",
                              fix="design the feedback on this model (lagrangian.lqr)")
    missing = [u for u in fb.inputs if u not in used]
    if missing:
        raise SimulationError(f"The feedback computes `{missing[0]}` too, which was given another source.",
                              fix="let the feedback compute all its inputs, or design one for fewer inputs")
