"""Exact Coulomb friction in simulation: sliding and sticking phases switched by events.

A `CoulombFriction` load declared with ``regularization = 0`` is the exact law
(Coulomb; e.g. Pfeiffer & Glocker, *Multibody Dynamics with Unilateral Contacts*, ch. 7):

* **slip** with direction s = ±1: v_s = w e with s w > 0, and T = −s f N e (exact, constant
  direction during the phase);
* **stick**: w = 0 is added as a complementary nonholonomic constraint (A q̇ + b = 0 with
  A_i = ∂w/∂q̇_i = e·∂V(P)/∂q̇_i); its multiplier λ is the tangential reaction along e, and the
  contact stays stuck while |λ| ≤ f_s N.

e is an axis of one of the model's frames along which the sliding velocity always lies
(`lagrangian.dynamics._friction.sliding_direction`); a contact without one is refused.  Each
mode is a model of its own — `dataclasses.replace` of the frozen `Model`, the friction load
replaced by the force −s f N e at the contact point or by the constraint — derived and
compiled once, then integrated by `simulate` (slip) or the DAE route `_dae_run.run_dae` (stick) up to a
terminal event:

* in slip, s w falling through 0: the contact stops sliding.  The stuck model's λ at that
  state decides: |λ| ≤ f_s N sticks, otherwise it slides on in the direction s = −sign λ
  (a block launched up a steep incline slides back down);
* in stick, λ − f_s N rising through 0 (slip with s = −1) or λ + f_s N falling through 0
  (s = +1): the reaction needed exceeds what dry friction can give.  λ(q, q̇, t) is the
  closed form of `multiplier_formulas` (models with n + m ≤ 6).

The segments are joined into one `Trajectory` on the requested output grid, with the
extra columns ``mode_<load>`` (s = ±1 sliding, 0 stuck), ``friction_<load>`` (T·e: −s f N
or λ), ``sliding_<load>`` (w); the switches are events named ``stick_<load>`` and
``slip_<load>``.  The monitors T, U (U without friction) are those of the stuck model,
and the first integrals kept are the momenta that hold in every mode (friction does
no work on a coordinate with A_i ≡ 0).  N stays a given expression.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import replace
from pathlib import Path

import numpy as np
import symengine as se

from ..analysis import first_integrals
from ..dynamics import EquationsOfMotion, SlidingDirection, derive, multiplier_formulas, sliding_direction
from ..errors import ModelError, SimulationError
from ..model import CoulombFriction, load_model
from ..model.spec import Constraint, Model, PointForce, ReactionSpec
from ._dae import ConstrainedSystem
from ._dae_run import run_dae
from ._input_run import constant_inputs_only
from ._options import SimulationOptions
from ._progress import progress_bar
from ._setup import EventSpec, initial_state, output_times
from ._setup import momenta as momentum_index
from ._trajectory import Event, Trajectory, conservation

__all__ = ["PhaseRunner", "StickSlipSystem", "check_stick_slip_options", "exact_contact", "exact_contact_model",
           "run_stick_slip"]

#: The name of the terminal event that ends a phase (never a user's: not an identifier).
SWITCH = "~switch"
#: Consecutive phases shorter than this (relative to max(1, |t|)) before the run is refused.
ZENO_LENGTH, ZENO_COUNT = 1e-12, 20
#: |w| at or below this at the start counts as not sliding (model velocity units).
REST_SPEED = 1e-12


def exact_contact(model: Model) -> CoulombFriction | None:
    """The model's exact Coulomb contact (``regularization = 0``), or None.

    Raises
    ------
    ModelError
        When the model has more than one.
    """
    exact = [load for load in model.loads if isinstance(load, CoulombFriction) and load.exact]
    if len(exact) > 1:
        raise ModelError(f"The model has {len(exact)} exact Coulomb contacts ("
                         + ", ".join(f"`{c.name}`" for c in exact) + "); stick/slip simulation handles one.",
                         symbol=exact[1].name,
                         fix="give the other contacts a positive regularization (e.g. 1e-3)")
    return exact[0] if exact else None


def exact_contact_model(source) -> Model | None:
    """The `Model` of ``source`` (a path, `Model`, equations or compiled system) when it has an exact contact."""
    if isinstance(source, (str, Path)):
        model = load_model(source)
    elif isinstance(source, Model):
        model = source
    elif isinstance(getattr(source, "eom", None), EquationsOfMotion):
        model = source.eom.model
    elif isinstance(source, EquationsOfMotion):
        model = source.model
    else:
        return None
    return model if exact_contact(model) is not None else None


class StickSlipSystem:
    """The three modes of a model with one exact Coulomb contact, each derived and compiled once.

    Attributes
    ----------
    model : the model; ``load`` : its exact contact; ``direction`` : e and w (`SlidingDirection`).
    stuck : the `ConstrainedSystem` of the stuck mode (row ``row``).
    """

    def __init__(self, model: Model, *, backend: str = "auto") -> None:
        load = exact_contact(model)
        if load is None:
            raise ModelError("The model has no exact Coulomb contact (regularization = 0).",
                             fix="use lagrangian.simulate")
        self.model, self.load, self.backend = model, load, backend
        eom = derive(model)
        self.direction: SlidingDirection = sliding_direction(eom.kinematics, load)
        self.row = f"stick_{load.name}"
        others = tuple(x for x in model.loads if x is not load)
        stuck = replace(model, loads=others, constraints=model.constraints + (
            Constraint(self.row, "nonholonomic", self.direction.speed, reaction=ReactionSpec(force_at=load.at, frame=self.direction.frame),
                       description=f"the contact `{load.name}` sticks: v_s·{self.direction.label} = 0"),))
        self.stuck_eom = derive(stuck)
        self.stuck = ConstrainedSystem(self.stuck_eom, backend=backend)
        self.k_row = self.stuck.rows.index(self.row)
        lam = multiplier_formulas(self.stuck_eom)
        if lam is None:
            raise SimulationError(f"The stuck contact `{load.name}` makes a system too large ({self.stuck.n} "
                                  f"coordinates, {self.stuck.m} constraint rows) for the closed-form multiplier "
                                  "that the stick/slip events need.",
                                  fix="use the regularised law (a positive regularization) for this model")
        eq = self.stuck_eom
        params = [se.Symbol(name) for name in self.stuck.parameters]
        f_s = load.static_coefficient if load.static_coefficient is not None else load.coefficient
        self.args = [eq.t, *eq.q, *eq.qd, *params]
        self.symbols = {"lam": lam[self.k_row], "f": load.coefficient, "f_s": f_s, "N": load.normal_force}
        self._numeric = se.Lambdify(self.args, [load.coefficient, f_s, load.normal_force], cse=True)
        self._slip: dict[int, EquationsOfMotion] = {}
        self._slip_models = {s: replace(model, loads=others + (
            PointForce(load.name, self.direction.vector * (-s * load.coefficient * load.normal_force), load.at),))
            for s in (1, -1)}

    def slip_eom(self, s: int) -> EquationsOfMotion:
        """The equations while sliding in direction s e (T = −s f N e), derived once."""
        if s not in self._slip:
            self._slip[s] = derive(self._slip_models[s])
        return self._slip[s]

    def coefficients(self, t: float, y: np.ndarray, p: np.ndarray) -> tuple[float, float, float]:
        """(f, f_s, N) at a state."""
        f, f_s, N = np.asarray(self._numeric(np.concatenate([[t], y, p])), dtype=float).ravel()
        return float(f), float(f_s), float(N)

    def speed(self, t: float, y: np.ndarray, p: np.ndarray) -> float:
        """w = v_s·e at a state."""
        return float(self.stuck.parts(t, y, p)[4][self.k_row])

    def reaction(self, t: float, y: np.ndarray, p: np.ndarray) -> float:
        """λ: the tangential reaction along e that keeps the contact stuck at this state."""
        return float(self.stuck.rhs(t, y, p)[1][self.k_row])

    def onto_stick(self, t: float, y: np.ndarray, p: np.ndarray) -> np.ndarray:
        """q̇ moved onto A q̇ + b = 0 (every row) along the metric of M: Δq̇ = −M⁻¹Aᵀ(A M⁻¹ Aᵀ)⁻¹ g."""
        n = self.stuck.n
        M, _, A, _, g, _ = self.stuck.parts(t, y, p)
        X = np.linalg.solve(M, A.T)
        out = y.copy()
        out[n:] -= X @ np.linalg.solve(A @ X, g)
        return out

    def decide(self, t: float, y: np.ndarray, p: np.ndarray) -> int:
        """The mode at a state: s = ±1 sliding, 0 stuck (module docstring)."""
        f, f_s, N = self.coefficients(t, y, p)
        if not (np.isfinite(N) and N >= 0):
            raise SimulationError(f"The normal force of the contact `{self.load.name}` is N = {N:.6g} at "
                                  f"t = {t:.9g}: it must be a finite value ≥ 0 (a negative N would pull).",
                                  fix="check the normal_force expression, or stop the run before contact is lost",
                                  t=t, state=y.copy())
        if not 0 <= f <= f_s:
            raise SimulationError(f"The friction coefficients of `{self.load.name}` are f = {f:.6g}, "
                                  f"f_s = {f_s:.6g}: 0 ≤ f ≤ f_s is needed.",
                                  fix="give static_coefficient at least the (kinetic) coefficient")
        w = self.speed(t, y, p)
        if abs(w) > REST_SPEED:
            return 1 if w > 0 else -1
        lam = self.reaction(t, y, p)
        if abs(lam) <= f_s * N:
            return 0
        return -1 if lam > 0 else 1


_SYSTEMS: dict[int, tuple[Model, str, StickSlipSystem]] = {}


def _system(model: Model, backend: str) -> StickSlipSystem:
    """One `StickSlipSystem` per model object and backend (its modes derived and compiled once)."""
    hit = _SYSTEMS.get(id(model))
    if hit is not None and hit[0] is model and hit[1] == backend:
        return hit[2]
    system = StickSlipSystem(model, backend=backend)
    if len(_SYSTEMS) > 16:
        _SYSTEMS.clear()
    _SYSTEMS[id(model)] = (model, backend, system)
    return system


def check_stick_slip_options(options: SimulationOptions) -> None:
    """Refuse fixed steps: the phases end at events, not on a grid."""
    if options.dt is not None or options.method == "gauss-legendre":
        raise SimulationError("Stick/slip phases end at events, so fixed steps (dt, gauss-legendre) are not available.",
                              fix="use an adaptive method such as method='dop853', bounded with max_step if needed")


#: How one smooth phase of a sliding mode is run: `simulate`'s whole pipeline, handed in by it
#: (`_methods`), so that this module never imports the dispatcher that imports it.
PhaseRunner = Callable[[object, SimulationOptions], Trajectory]


def run_stick_slip(source, options: SimulationOptions, simulate: PhaseRunner) -> Trajectory:
    """Integrate a model with one exact Coulomb contact, switching between slip and stick (module docstring).

    Parameters
    ----------
    source : a model file, a `Model`, or its equations, whose contact has ``regularization = 0``.
    options : `simulate`'s options (``dt`` and ``gauss-legendre`` are refused: the phases end at events);
        ``stabilization``, ``baumgarte`` control the drift of the stuck phases (`_dae_run`);
        ``max_switches`` is the most phases a run may have (default 100 000).  Constant inputs only.
    simulate : runs a sliding phase (`simulate`'s pipeline on the sliding model's equations).

    Returns
    -------
    Trajectory
        On the requested grid, with the extra columns ``mode_<load>``, ``friction_<load>``,
        ``sliding_<load>`` and the switching events ``stick_<load>``, ``slip_<load>``.

    Raises
    ------
    ModelError
        No single exact contact, or no fixed sliding direction.
    SimulationError
        As `simulate`; also a negative N, f > f_s, an endless chattering of short phases.
    """
    options = options.but(parameters=constant_inputs_only(source, options.inputs, options.parameters), inputs=None)
    model = exact_contact_model(source) if not isinstance(source, Model) else source
    if model is None or exact_contact(model) is None:
        raise ModelError("The model has no exact Coulomb contact (regularization = 0).", fix="use lagrangian.simulate")
    check_stick_slip_options(options)
    system = _system(model, options.backend)
    grid = output_times(float(options.t_start), float(options.t_end), options.n_out, options.t_eval)
    p = system.stuck.parameter_vector(options.parameters)
    y = initial_state(system.stuck_eom, options.initial)
    phases = _Phases(system, options, simulate, p, grid)
    pieces, switches, user_events, status = phases.run(float(options.t_start), y)
    return _join(system, p, grid, pieces, switches, user_events, status, options.method, options.tolerance)


class _Phases:
    """The phases of one run: each from a switch to the next terminal event (module docstring)."""

    def __init__(self, system: StickSlipSystem, options: SimulationOptions, simulate: PhaseRunner,
                 p: np.ndarray, grid: np.ndarray) -> None:
        self.system, self.options, self.simulate, self.p, self.grid = system, options, simulate, p, grid
        self.user = [EventSpec(e, e) if isinstance(e, str) else e for e in options.events]
        # What every phase shares with the run: the rest (the start, the grid, the events) is the phase's.
        self.common = SimulationOptions(options.t_end, parameters=options.parameters, method=options.method,
                                        rtol=options.rtol, atol=options.atol, max_step=options.max_step,
                                        tolerance=options.tolerance, max_steps=options.max_steps,
                                        backend=options.backend)

    def piece(self, mode: int, t: float, y: np.ndarray) -> Trajectory:
        """One phase in ``mode`` (0 stuck, ±1 sliding) from (t, y) to its terminal event or t_end."""
        system, options = self.system, self.options
        coords = system.stuck.coordinates
        n = len(coords)
        start = {c: float(v) for c, v in zip(coords, y[:n], strict=True)} | {c + "_dot": float(v) for c, v in zip(coords, y[n:], strict=True)}
        t_seg = np.concatenate([[t], self.grid[self.grid > t]])
        if mode == 0:
            lam, f_s, N = system.symbols["lam"], system.symbols["f_s"], system.symbols["N"]
            ends = [EventSpec(SWITCH + "-", lam - f_s * N, 1, True), EventSpec(SWITCH + "+", lam + f_s * N, -1, True)]
            return run_dae(system.stuck, self.common.but(t_start=t, initial=start, t_eval=t_seg, events=ends + self.user,
                                                         stabilization=options.stabilization,
                                                         baumgarte=options.baumgarte))
        ends = [EventSpec(SWITCH, mode * system.direction.speed, -1, True)]
        return self.simulate(system.slip_eom(mode), self.common.but(t_start=t, initial=start, t_eval=t_seg,
                                                                     events=ends + self.user,
                                                                     stiffness_check=options.stiffness_check))

    def run(self, t: float, y: np.ndarray) -> tuple[list[tuple[int, Trajectory]], list[Event], list[Event], str]:
        """(phases, switches, the user's events, status) from (t, y) to the end."""
        system, options, p = self.system, self.options, self.p
        t_start, t_end, progress = float(options.t_start), float(options.t_end), options.progress
        max_switches = 100_000 if options.max_switches is None else options.max_switches
        n, name = len(system.stuck.coordinates), system.load.name
        mode = system.decide(t, y, p)
        pieces: list[tuple[int, Trajectory]] = []
        switches: list[Event] = []
        user_events: list[Event] = []
        status, short = "completed", 0
        while True:
            if mode == 0:
                y = system.onto_stick(t, y, p)
            piece = self.piece(mode, t, y)
            pieces.append((mode, piece))
            if progress:
                (_bar if progress is True else progress)(min(1.0, (piece.t[-1] - t_start) / (t_end - t_start)),
                                                         float(piece.t[-1]))
            user_events += [e for e in piece.events if not e.name.startswith(SWITCH)]
            stop = [e for e in piece.events if e.name.startswith(SWITCH)]
            if piece.status == "completed" or not stop:
                status = piece.status
                break
            event = stop[-1]
            t_new, y = float(event.t), np.concatenate([event.q, event.qd])
            if mode == 0:  # the reaction needed left [−f_s N, f_s N]: it slides against it
                mode = 1 if event.name.endswith("+") else -1
            else:  # w = 0 (to a few ulp): the stuck model's reaction decides
                y = system.onto_stick(t_new, y, p)
                mode = system.decide(t_new, y, p)
            short = short + 1 if t_new - t <= ZENO_LENGTH * max(1.0, abs(t)) else 0
            if short >= ZENO_COUNT or len(pieces) >= max_switches:
                raise SimulationError(f"The contact `{name}` switched between sticking and sliding {len(pieces)} "
                                      f"times, the last {short} within {ZENO_LENGTH:g} s of each other, by "
                                      f"t = {t_new:.9g}.", fix="check the friction coefficients and N, or raise "
                                                               "max_switches", t=t_new, state=y.copy())
            switches.append(Event(("stick_" if mode == 0 else "slip_") + name, t_new, y[:n].copy(), y[n:].copy()))
            t = t_new
            if t >= t_end:
                break
        return pieces, switches, user_events, status


def _bar(fraction: float, t: float) -> None:
    progress_bar(fraction, t)


def _join(system: StickSlipSystem, p: np.ndarray, grid: np.ndarray, pieces: list[tuple[int, Trajectory]],
          switches: list[Event], user_events: list[Event], status: str, method: str,
          tolerance: float | None) -> Trajectory:
    """One trajectory on ``grid`` from the phases (module docstring)."""
    wanted = set(grid.tolist())
    T, Q, QD, QDD, MODE, FRIC = [], [], [], [], [], []
    last = -np.inf
    warnings: list[str] = []
    for mode, piece in pieces:
        keep = np.array([t > last and t in wanted for t in piece.t], dtype=bool)
        if keep.any():
            last = float(piece.t[keep][-1])
        T.append(piece.t[keep])
        Q.append(piece.q[keep])
        QD.append(piece.qd[keep])
        QDD.append(piece.qdd[keep])
        MODE.append(np.full(int(keep.sum()), float(mode)))
        if mode == 0:
            FRIC.append(piece.extra[f"lambda_{system.row}"][keep])
        else:
            Y = np.column_stack([piece.q[keep], piece.qd[keep]])
            values = [system.coefficients(t, yy, p) for t, yy in zip(piece.t[keep], Y, strict=True)]
            FRIC.append(np.array([-mode * f * N for f, _, N in values]))
        warnings += [w for w in piece.warnings if " drifted by " not in w and w not in warnings]
    t = np.concatenate(T)
    q, qd, qdd = np.concatenate(Q), np.concatenate(QD), np.concatenate(QDD)
    Y = np.column_stack([q, qd])
    stuck = system.stuck
    values = stuck.monitor_values(t, Y, p) if len(t) else np.zeros((0, len(stuck.monitors)))
    n = len(stuck.coordinates)
    M, g = stuck.parts(t, Y, p)[0::4] if len(t) else (None, np.zeros((0, stuck.m)))
    momenta = {fi.name for fi in first_integrals(system.stuck_eom) if fi.kind == "momentum"}
    monitors = {k: values[:, i].copy() for i, k in enumerate(stuck.monitors)
                if not k.startswith("drift_") and (k in momenta or k in ("T", "U"))}
    integrals = tuple(k for k in stuck.integrals if k in momenta)
    # The same drift as every other run (`_trajectory.conservation`): relative to a physical scale.
    drift, scales = conservation(monitors, integrals, momenta=momentum_index(system.stuck_eom, integrals),
                                 M=None if M is None else np.asarray(M).reshape(len(t), n, n), qd=qd)
    mode = np.concatenate(MODE)
    name = system.load.name
    for i, row in enumerate(stuck.rows):
        series = g[:, i] if row != system.row else g[mode == 0, i]
        drift[f"drift_{row}_dot"] = float(np.max(np.abs(series), initial=0.0))
    warnings += [f"{k} drifted by {drift[k]:.2e} (relative), more than the tolerance {tolerance:.1e}"
                 for k in integrals if tolerance is not None and drift[k] > tolerance]
    extra = {f"mode_{name}": mode, f"friction_{name}": np.concatenate(FRIC), f"sliding_{name}": g[:, system.k_row].copy()}
    first = pieces[0][1]
    return Trajectory(
        model_name=system.model.name, coordinates=tuple(stuck.coordinates), parameters=dict(first.parameters),
        t=t, q=q, qd=qd, qdd=qdd, monitors=monitors, integrals=integrals, drift=drift,
        method=f"{first.method.split(' + ')[0]} + stick/slip", steps=sum(x.steps for _, x in pieces),
        rhs_calls=sum(x.rhs_calls for _, x in pieces), tolerance=tolerance, warnings=tuple(warnings),
        events=tuple(sorted(switches + user_events, key=lambda e: e.t)), status=status,
        conditioning=min(x.conditioning for _, x in pieces), extra=extra, scales=scales,
    )
