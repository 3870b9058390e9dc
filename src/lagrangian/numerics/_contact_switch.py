"""What happens at a contact event: the impact, the contacts that stay closed, and the accumulation of impacts.

At a touch-down the percussions are solved from Lagrange's equations in impulsive form with
Newton's law (`impact`, `_impact`); then — as at a lift-off, and at the start — the closed
contacts of the next smooth phase are those whose reactions solve the contact problem at
acceleration level (`decide`): among the touching contacts that do not move apart
(|g| and |ġ| within 10 atol), λ ≥ 0 and g̈ ≥ 0 with λ g̈ = 0, every solution being tried with the
most contacts closed first (a reaction that is exactly zero keeps two bodies that move together
in contact), except the contact that has just lifted off, tried open first.

An accumulation of impacts (a ball coming to rest, a rocking block settling) has infinitely many
impacts in a finite time (Zeno).  When the intervals between the last impacts form a geometric
series (the last three ratios within 1 % of each other, below 1) and the last approach speed has
fallen to ``rest`` (1e-6) times the first of the series, the remaining bounces are summed,
t_∞ = t_k + δ_k ρ/(1 − ρ) for the last interval δ_k and ratio ρ — for the bouncing ball ρ = e
and t_∞ = √(2h₀/g)(1 + e)/(1 − e) exactly — and the impact at t_k is made plastic (e = 0), so that
the contacts close: the motion goes on in persistent contact instead of stalling, and each
contact closed so gets an event ``rest_<contact>`` at t_∞.
"""

from __future__ import annotations

import itertools
from collections.abc import Collection, Sequence
from dataclasses import dataclass, field

import numpy as np

from ..errors import SimulationError
from ._contact_system import ContactSystem, Probe, solve_small
from ._impact import CLOSED, OPEN, SLIDE_NEG, SLIDE_POS, delassus, solve_lcp
from ._trajectory import Event

__all__ = ["RATIO_SPREAD", "REST", "ContactEvent", "ContactLaws", "accumulation"]

#: Last approach speed, relative to the first of the series, below which an accumulation is summed.
REST = 1e-6
#: Relative spread allowed between the last three ratios of impact intervals of a geometric series.
RATIO_SPREAD = 1e-2
#: Relative feasibility tolerance of the contact problems (of the scale of their right-hand side).
LCP_RTOL = 1e-9
#: A closed contact lifts off when its reaction falls below −LIFTOFF_RTOL times the scale of the reactions:
#: far above the round-off of a reaction that is exactly zero, and a negligible delay for one that crosses 0.
LIFTOFF_RTOL = 1e-12


@dataclass(frozen=True)
class ContactEvent(Event):
    """An event of a contact: an impact, a lift-off, a touchdown or the rest after impacts.

    Parameters
    ----------
    name : str
        The event's name.
    t : float
        Its time.
    q : ndarray of shape (n,)
        The coordinates there.
    qd : ndarray of shape (n,)
        The rates there (q̇⁻ for an impact).
    kind : str
        ``"impact"``, ``"liftoff"``, ``"touchdown"`` (closing without bounce at zero speed) or
        ``"rest"`` (the accumulation point of impacts).
    contact : str
        The contact's name.
    percussion : float
        For an impact, the normal percussion P = ∫λ dt over the impact (the multiplier's unit times
        a time).
    tangential : float
        For an impact, the friction's percussion.
    speed : float
        For an impact, the normal velocity ġ⁻ before it.
    qd_after : ndarray, optional
        For an impact, q̇⁺.
    energy_before : float
        E = T + U before an impact.
    energy_after : float
        E = T + U after it.
    reaction : float
        For a lift-off, λ there (0 to the tolerance).
    """

    kind: str = ""
    contact: str = ""
    percussion: float = float("nan")
    tangential: float = float("nan")
    speed: float = float("nan")
    qd_after: np.ndarray | None = None
    energy_before: float = float("nan")
    energy_after: float = float("nan")
    reaction: float = float("nan")

    def as_dict(self) -> dict:
        """Plain values for JSON (the trajectory's metadata).

        Returns
        -------
        dict
            Plain values for JSON (the trajectory's metadata).
        """
        out: dict = {"name": self.name, "t": self.t, "kind": self.kind, "contact": self.contact}
        for key in ("percussion", "tangential", "speed", "energy_before", "energy_after", "reaction"):
            value = getattr(self, key)
            if np.isfinite(value):
                out[key] = float(value)
        return out


def accumulation(times: Sequence[float], speeds: Sequence[float], rest: float = REST,
                 gap_tol: float = 0.0) -> tuple[float, float] | None:
    """(t_∞, ρ) when the last impacts are a converging geometric series that has come to rest (module docstring).

    At rest: the last approach speed is at most ``rest`` times the largest of the series, or the last
    bounce, whose height is about |ġ⁻| δ/4 for the last interval δ, is below ``gap_tol``.
    """
    if len(times) < 5:
        return None
    last = times[-5:]
    d = [b - a for a, b in itertools.pairwise(last)]
    if min(d) <= 0 or (speeds[-1] > rest * max(speeds) and speeds[-1] * d[-1] / 4 > gap_tol):
        return None
    r = [b / a for a, b in itertools.pairwise(d)]
    rho = sum(r) / len(r)
    if not (0 < rho < 1 and max(r) < 1 and max(abs(x - rho) for x in r) <= RATIO_SPREAD * rho):
        return None
    return float(times[-1] + d[-1] * rho / (1 - rho)), rho


@dataclass
class ContactLaws:
    """The contact laws of one run: coefficients at the run's parameter values, tolerances, scales."""

    cs: ContactSystem
    p: np.ndarray
    e: np.ndarray
    mu: np.ndarray
    atol: float
    acc_scale: float = 0.0
    eps: np.ndarray = field(default_factory=lambda: np.zeros(0))

    def __post_init__(self) -> None:
        self.probe = Probe(self.cs.full, self.p)
        self.simple = not len(self.cs.bilateral)
        self.eps = np.zeros(len(self.cs.contacts))
        # Plain lists for the loops over a handful of contacts (NumPy's call costs more than their work).
        self.rows_n = [int(k) for k in self.cs.normal]
        self.frictional = [bool(self.cs.tangent[k] >= 0 and self.mu[k] > 0) for k in range(len(self.cs.contacts))]
        self._key: tuple = ()
        self._parts: tuple = ()

    def parts(self, t: float, y: np.ndarray) -> tuple[np.ndarray, ...]:
        """(M, F, A, c, g, f, gap_tol, v_tol) at one state, kept for the next call at the same state.

        The tolerances below which a gap counts as closed and its rate as zero are 10 atol max(‖A_k‖, 1).
        """
        key = (t, y.tobytes())
        if key != self._key:
            M, F, A, c, g, f = [a.copy() for a in self.probe.parts(t, y)]
            An = A[self.cs.normal]
            tol = 10 * self.atol * np.maximum(np.sqrt((An * An).sum(axis=1)), 1.0)
            self._key, self._parts = key, (M, F, A, c, g, f, tol, tol)
        return self._parts

    def _bilateral(self, A: np.ndarray) -> np.ndarray | None:
        return A[self.cs.bilateral] if len(self.cs.bilateral) else None

    def _frictional(self, k: int) -> bool:
        return self.frictional[k]

    def touching(self, f: np.ndarray, gap_tol: np.ndarray, also: int = -1) -> list[int]:
        """The contacts whose gap is 0 to the tolerance (and ``also``)."""
        return [k for k, r in enumerate(self.rows_n) if k == also or abs(f[r]) <= gap_tol[k]]

    # -- impacts -------------------------------------------------------------------------------------------
    def impact(self, t: float, y: np.ndarray, trigger: int, plastic: bool = False
               ) -> tuple[np.ndarray, list[ContactEvent]]:
        """(y⁺, events): the percussions at a touch-down of contact ``trigger`` (module docstring of `_impact`)."""
        cs, n = self.cs, self.cs.n
        M, _, A, _, g, f, gap_tol, v_tol = self.parts(t, y)
        near = self.touching(f, gap_tol, trigger)
        fr = [k for k in near if self.frictional[k]]
        if len(near) == 1 and not fr and self.simple:
            return self._single(t, y, near[0], M, A, g, 0.0 if plastic else float(self.e[near[0]]), v_tol)
        cand = np.array(near, dtype=int)
        rows = [int(cs.normal[k]) for k in cand] + [int(cs.tangent[k]) for k in fr]
        tangent = [len(cand) + fr.index(int(k)) if int(k) in fr else -1 for k in cand]
        W, X = delassus(M, A[rows], self._bilateral(A))
        before = g[rows]
        e = np.zeros(len(cand)) if plastic else self.e[cand]
        target = np.concatenate([-e * np.minimum(before[:len(cand)], 0.0), np.zeros(len(fr))])
        q = before - target
        scale = float(np.max(np.abs(q) / np.maximum(np.abs(np.diag(W)), 1e-300), initial=0.0))
        M_ = M

        def kinetic(z: np.ndarray) -> float:
            v = y[n:] + X @ z
            return float(v @ M_ @ v)

        names = ", ".join(f"`{cs.names[k]}`" for k in cand)
        solved = solve_lcp(W, q, mu=np.nan_to_num(self.mu[cand]), tangent=tangent,
                           tol_w=np.concatenate([v_tol[cand], v_tol[fr]]), tol_z=LCP_RTOL * scale + 1e-300,
                           choose=kinetic if fr else None, what=f"The impact at t = {t:.9g}")
        if solved is None:
            raise SimulationError(
                f"The simultaneous impact of the contacts {names} at t = {t:.9g} has no solution: no percussions "
                "P ≥ 0 give velocities that satisfy Newton's law ġ⁺ ≥ −e ġ⁻ at every contact (they ask for opposite "
                "velocities of the same motion, e.g. a body wedged between two surfaces with e > 0), together with "
                "the bilateral constraints.", fix="check the gaps and the restitution coefficients of these contacts "
                "(a wedged body needs e = 0), or start from a state where they do not close together",
                t=t, state=y.copy())
        z, modes = solved
        y_plus = y.copy()
        y_plus[n:] = y[n:] + X @ z
        E = self.probe.energy(t, y, y_plus)
        events = []
        for i, k in enumerate(cand):
            if modes[i] == OPEN and k != trigger:
                continue
            tz = z[tangent[i]] if tangent[i] >= 0 else float("nan")
            events.append(ContactEvent(f"impact_{cs.names[k]}", t, y[:n].copy(), y[n:].copy(), kind="impact",
                                       contact=cs.names[k], percussion=float(z[i]), tangential=float(tz),
                                       speed=float(before[i]), qd_after=y_plus[n:].copy(), energy_before=float(E[0]),
                                       energy_after=float(E[1])))
        return y_plus, events

    def _single(self, t: float, y: np.ndarray, k: int, M: np.ndarray, A: np.ndarray, g: np.ndarray, e: float,
                v_tol: np.ndarray) -> tuple[np.ndarray, list[ContactEvent]]:
        """One frictionless contact, no bilateral row: P = max(0, −(1 + e) ġ⁻ / (A M⁻¹ Aᵀ)) in closed form."""
        cs, n = self.cs, self.cs.n
        row = self.rows_n[k]
        a = A[row]
        x = solve_small(M, a)
        s = float(g[row])
        need = -s - e * min(s, 0.0)  # ġ⁺ − ġ⁻ asked for by Newton's law
        P = need / float(a @ x) if need > v_tol[k] else 0.0
        y_plus = y.copy()
        if P:
            y_plus[n:] += x * P
        E = self.probe.energy(t, y, y_plus)
        return y_plus, [ContactEvent(f"impact_{cs.names[k]}", t, y[:n].copy(), y[n:].copy(), kind="impact",
                                     contact=cs.names[k], percussion=P, speed=s, qd_after=y_plus[n:].copy(),
                                     energy_before=E[0], energy_after=E[1])]

    def settle(self, t: float, y: np.ndarray) -> tuple[np.ndarray, np.ndarray, tuple[float, float]]:
        """The end of an accumulation of impacts: q̇ projected, in the metric of M, onto ġ = 0 (and w = 0 with
        friction) at every touching contact — the sum of the impulses of the bounces left, which act along
        M⁻¹Aᵀ and leave the rest of the motion as it is.  Returns (y⁺, the touching contacts, (E⁻, E⁺))."""
        cs, n = self.cs, self.cs.n
        M, _, A, _, g, f, gap_tol, _ = self.parts(t, y)
        cand = np.flatnonzero(np.abs(f[cs.normal]) <= gap_tol)
        rows = [*cs.bilateral.tolist()] + [int(cs.normal[k]) for k in cand] + \
            [int(cs.tangent[k]) for k in cand if self._frictional(int(k))]
        As = A[rows]
        X = solve_small(M, As.T)
        mult = np.linalg.lstsq(As @ X, g[rows], rcond=None)[0]  # rows may be dependent: a flat block's four
        y_plus = y.copy()
        y_plus[n:] -= X @ mult
        return y_plus, cand, self.probe.energy(t, y, y_plus)

    # -- the contacts that stay closed ---------------------------------------------------------------------
    def decide(self, t: float, y: np.ndarray, prefer_open: Collection[int] = ()) -> np.ndarray:
        """Which contacts are closed in the smooth phase that starts at (t, y) (module docstring); sets ``eps``."""
        cs, n = self.cs, self.cs.n
        m = len(cs.contacts)
        M, F, A, c, g, f, gap_tol, v_tol = self.parts(t, y)
        closed = np.zeros(m, dtype=bool)
        resting = [k for k in self.touching(f, gap_tol) if abs(g[self.rows_n[k]]) <= v_tol[k]]
        if not resting:
            return closed
        cand = np.array(resting, dtype=int)
        qdd = cs.solve(M, F, A, c, y, cs.bilateral)[0][n:]
        a_all = A[cs.normal] @ qdd + c[cs.normal]
        self.acc_scale = max(self.acc_scale, float(np.max(np.abs(a_all), initial=0.0)))
        W_all, _ = delassus(M, A[cs.normal], self._bilateral(A))
        self.eps = LIFTOFF_RTOL * self.acc_scale / np.maximum(np.abs(np.diag(W_all)), 1e-300)
        sliding = {int(k) for k in cand if self._frictional(int(k)) and abs(g[cs.tangent[k]]) > v_tol[k]}
        stick = [int(k) for k in cand if self._frictional(int(k)) and int(k) not in sliding]
        rows = [int(cs.normal[k]) for k in cand] + [int(cs.tangent[k]) for k in stick]
        tangent = [len(cand) + stick.index(int(k)) if int(k) in stick else -1 for k in cand]
        W, _ = delassus(M, A[rows], self._bilateral(A))
        a = A[rows] @ qdd + c[rows]
        tol_w = np.full(len(rows), LCP_RTOL * self.acc_scale)
        lam_scale = float(np.max(np.abs(a) / np.maximum(np.abs(np.diag(W)), 1e-300), initial=0.0))
        prefer = [i for i, k in enumerate(cand) if int(k) in prefer_open]

        def order(modes: tuple[int, ...]) -> float:
            return sum(modes[i] != OPEN for i in prefer) * (len(modes) + 1) - sum(x != OPEN for x in modes)

        allowed = [(OPEN,) if int(k) in sliding else (OPEN, CLOSED) for k in cand]
        mu = np.nan_to_num(self.mu[cand])
        solved = solve_lcp(W, a, mu=mu, tangent=tangent, allowed=allowed, order=order, tol_w=tol_w,
                           tol_z=LCP_RTOL * lam_scale + 1e-300, what=f"The contact problem at t = {t:.9g}")
        if solved is None:
            self._refuse(t, y, cand, sliding, W, a, mu, tangent, tol_w, lam_scale)
        _, modes = solved  # type: ignore[misc]
        closed[cand[[x != OPEN for x in modes]]] = True
        return closed

    def _refuse(self, t: float, y: np.ndarray, cand: np.ndarray, sliding: set[int], W: np.ndarray, a: np.ndarray,
                mu: np.ndarray, tangent: list[int], tol_w: np.ndarray, lam_scale: float) -> None:
        """No closed set fits: a contact with friction that would have to slide, or no consistent reactions."""
        cs = self.cs
        names = ", ".join(f"`{cs.names[k]}`" for k in cand)
        slides = [(OPEN, CLOSED, SLIDE_POS, SLIDE_NEG) if tangent[i] >= 0 else (OPEN, CLOSED)
                  for i in range(len(cand))]
        if sliding or solve_lcp(W, a, mu=mu, tangent=tangent, allowed=slides, tol_w=tol_w,
                                tol_z=LCP_RTOL * lam_scale + 1e-300) is not None:
            which = ", ".join(f"`{cs.names[k]}`" for k in (sliding or cand))
            raise SimulationError(
                f"At t = {t:.9g} the contact {which} stays closed while sliding with friction (or would need more "
                "than μ λ to stick): a persistent contact that slides with Coulomb friction is not simulated.",
                fix="raise its friction coefficient so that it sticks, or make it frictionless (leave `friction` "
                    "out)", t=t, state=y.copy())
        raise SimulationError(
            f"At t = {t:.9g} no set of the touching contacts {names} has reactions λ ≥ 0 that keep every gap from "
            "closing further (the contact problem g̈ = a + W λ ≥ 0, λ ≥ 0, λ g̈ = 0 has no solution).",
            fix="check the contacts' gaps: two contacts that push against each other, or a gap a bilateral "
                "constraint already fixes", t=t, state=y.copy())
