"""The figures of docs/control.md: the cart-pole swung up and caught, its LQR closed loop, its basin of attraction.

Run from the repository root:  .venv/bin/python docs/figures/control_figures.py
Writes docs/figures/control_swing_up.png, control_closed_loop.png and control_basin.png, and prints the
figures the page quotes.
"""

from __future__ import annotations

from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

import lagrangian

HERE = Path(__file__).resolve().parent
CART_POLE = HERE.parents[1] / "examples" / "inverted_pendulum_cart.toml"


def closed_loop(eom, fb) -> None:  # type: ignore[no-untyped-def]
    traj = lagrangian.simulate(eom, 8.0, inputs=fb, initial={"theta": 0.2}, n_out=801)
    table = lagrangian.InputTable([0.0, 0.5, 1.0, 1.5, 2.0], [0.0, 2.0, -2.0, 1.0, 0.0], interpolation="zoh")
    pushed = lagrangian.simulate(eom, 2.0, inputs={"F": table}, initial={"theta": 0.0}, n_out=401)
    fig, axes = plt.subplots(1, 2, figsize=(10, 3.6), constrained_layout=True)
    ax = axes[0]
    ax.plot(traj.t, traj.column("theta"), label="θ (rad)")
    ax.plot(traj.t, traj.column("x"), label="x (m)")
    ax.plot(traj.t, traj.column("F") / 10, label="F / 10 (N)")
    ax.axhline(0, color="0.7", lw=0.8)
    ax.set_xlabel("t (s)")
    ax.set_title("LQR closed loop from θ = 0.2 rad (compiled)")
    ax.legend(frameon=False)
    ax = axes[1]
    ax.plot(pushed.t, pushed.column("theta"), label="θ (rad)")
    ax.step(pushed.t, pushed.column("F") / 10, where="post", label="F / 10 (N), zero-order hold")
    ax.set_xlabel("t (s)")
    ax.set_title("Open loop, F from a table: the pendulum falls")
    ax.legend(frameon=False)
    fig.savefig(HERE / "control_closed_loop.png", dpi=110)
    plt.close(fig)


def basin(eom, fb) -> None:  # type: ignore[no-untyped-def]
    thetas, rates = np.linspace(-1.4, 1.4, 141), np.linspace(-5.0, 5.0, 141)
    fell = lagrangian.EventSpec("fell", "abs(theta) - 1.5", direction=1, terminal=True)
    ds = lagrangian.ensemble(eom, 6.0, inputs=fb, initial=lagrangian.grid(theta=thetas, theta_dot=rates),
                             events=[fell], n_out=61)
    caught = (ds.status.values == 0) & (np.abs(ds.state_final.sel(state="theta").values) < 1e-2)
    fig, ax = plt.subplots(figsize=(5.6, 4.4), constrained_layout=True)
    ax.pcolormesh(rates, thetas, caught, cmap="Greens", vmin=-0.3, vmax=1.2, shading="nearest")
    ax.contour(rates, thetas, caught.astype(float), levels=[0.5], colors="k", linewidths=0.8)
    ax.set_xlabel("θ̇(0) (rad/s)")
    ax.set_ylabel("θ(0) (rad)")
    ax.set_title(f"Basin of attraction of the LQR cart-pole\n{caught.size} members, one ensemble call "
                 f"(green: caught, {caught.mean():.0%})")
    fig.savefig(HERE / "control_basin.png", dpi=110)
    plt.close(fig)


#: The swing-up of the walk-through: hanging at rest to upright at rest in 2 s, |F| ≤ 20 N on a 4 m rail.
HANGING = {"x": 0, "theta": np.pi, "x_dot": 0, "theta_dot": 0}
SWING_UP = {"t_end": 2.0, "initial": HANGING, "final": {"x": 0, "theta": 0, "x_dot": 0, "theta_dot": 0},
            "bounds": {"F": (-20, 20), "x": (-2, 2)}, "nodes": 100}
#: The bob of the cart-pole the plan is flown on in the second half of the walk-through (the file says 0.2 kg).
TRUE_M = 0.22


def swing_up(eom) -> None:  # type: ignore[no-untyped-def]
    """Plan (optimize), replay, catch (Switch to LQR); then the same plan on a heavier bob, the bob's mass
    identified from a noisy record, and the plan made again."""
    best = lagrangian.optimize(eom, **SWING_UP)
    print(best.summary())
    fb = lagrangian.lqr(eom, at={"x": 0, "theta": 0}, Q={"theta": 10}, R=0.5)
    swing = best.input_table("F")
    open_loop = lagrangian.simulate(eom, 6.0, initial=HANGING, inputs={"F": lagrangian.Switch(swing, 0.0, at=2.0)},
                                    n_out=601)
    held = lagrangian.simulate(eom, 6.0, initial=HANGING, inputs={"F": lagrangian.Switch(swing, fb, at=2.0)},
                               n_out=601)
    print(f"open loop after the plan: theta(3 s) = {open_loop.q[300, 1]:.2e}, theta(6 s) = {open_loop.q[-1, 1]:.2f}; "
          f"caught: |theta| over [4, 6] s <= {np.abs(held.q[400:, 1]).max():.1e}, "
          f"|x| <= {np.abs(held.q[400:, 0]).max():.1e}")

    # The same plan on a bob 10 % heavier than the file says: it ends far from upright, out of reach of the LQR.
    missed = lagrangian.simulate(eom, 6.0, initial=HANGING, parameters={"m": TRUE_M},
                                 inputs={"F": lagrangian.Switch(swing, fb, at=2.0)}, n_out=601,
                                 events=[lagrangian.EventSpec("off the rail", "abs(x) - 2", direction=1, terminal=True)])
    # A record of the real cart, hanging, pushed by a known force; x and theta measured with noise 1e-3.
    rng = np.random.default_rng(1)
    run = lagrangian.simulate(eom, 3.0, initial={"theta": np.pi}, parameters={"m": TRUE_M},
                              inputs={"F": "3*sin(2*t) + 2*sin(5*t)"}, n_out=151)
    record = {"t": run.t, "F": run.column("F"),
              "x": run.q[:, 0] + 1e-3 * rng.standard_normal(len(run.t)),
              "theta": run.q[:, 1] + 1e-3 * rng.standard_normal(len(run.t))}
    fit = lagrangian.identify(eom, record, ["m"], route="shooting")
    replanned = lagrangian.optimize(eom, **SWING_UP, parameters={"m": fit["m"]}, warm_start=best)
    fb_fit = lagrangian.lqr(eom, at={"x": 0, "theta": 0}, Q={"theta": 10}, R=0.5, parameters={"m": fit["m"]})
    caught = lagrangian.simulate(eom, 6.0, initial=HANGING, parameters={"m": TRUE_M}, n_out=601,
                                 inputs={"F": lagrangian.Switch(replanned.input_table("F"), fb_fit, at=2.0)})
    print(f"true m = {TRUE_M}: the plan for 0.2 kg ends at theta(2 s) = {missed.q[200, 1]:.2f} rad, "
          f"{missed.status} at t = {missed.t[-1]:.2f} s; identified m = {fit['m']:.5f} ± {fit.std['m']:.1e}; re-planned J = "
          f"{replanned.objective:.3f}, theta(2 s) = {caught.q[200, 1]:.1e}, |theta| over [4, 6] s <= "
          f"{np.abs(caught.q[400:, 1]).max():.1e}")

    fig, axes = plt.subplots(2, 2, figsize=(11, 6.4), sharex=True, constrained_layout=True)
    nodes = best.node_rows
    ax = axes[0, 0]
    ax.plot(held.t, held.column("theta"), label="optimized F, then the LQR from t = 2 s")
    ax.plot(open_loop.t, open_loop.column("theta"), "--", label="optimized F, then F = 0 (open loop)")
    ax.plot(best.t[nodes][::3], best.column("theta")[nodes][::3], "k.", ms=4, label="the optimum (collocation nodes)")
    ax.axvline(2.0, color="0.7", lw=0.8)
    ax.set_ylabel("θ (rad)")
    ax.set_title("Swing-up (optimize, Hermite–Simpson), then caught (lqr)")
    ax.legend(frameon=False, fontsize=8)
    ax = axes[1, 0]
    ax.plot(held.t, held.column("F"), label="F applied (table, then u* − K (x − x*))")
    ax.plot(best.t, best.column("F"), "k.", ms=2, label="the optimum's F at its points")
    ax.plot(held.t, held.column("x") * 10, label="x × 10 (m)")
    ax.axvline(2.0, color="0.7", lw=0.8)
    ax.set_xlabel("t (s)")
    ax.set_ylabel("F (N)")
    ax.legend(frameon=False, fontsize=8)
    ax = axes[0, 1]
    ax.plot(missed.t, missed.column("theta"), color="tab:red",
            label=f"plan for m = 0.2 kg, bob of {TRUE_M} kg: off the rail at t = {missed.t[-1]:.2f} s")
    ax.plot(caught.t, caught.column("theta"), color="tab:green",
            label=f"plan for the identified m = {fit['m']:.4f} kg")
    ax.axvline(2.0, color="0.7", lw=0.8)
    ax.set_ylabel("θ (rad)")
    ax.set_title(f"A bob of {TRUE_M} kg: m identified, the plan made again")
    ax.legend(frameon=False, fontsize=8)
    ax = axes[1, 1]
    ax.plot(run.t, record["theta"], ".", ms=2, color="0.5", label="record: θ with noise 1e-3 (F = 3 sin 2t + 2 sin 5t)")
    fitted = lagrangian.simulate(eom, 3.0, initial={"theta": np.pi}, parameters={"m": fit["m"]},
                                 inputs={"F": "3*sin(2*t) + 2*sin(5*t)"}, n_out=151)
    ax.plot(fitted.t, fitted.column("theta"), color="tab:green", label=f"fit: m = {fit['m']:.4f} ± {fit.std['m']:.0e} kg")
    ax.set_xlabel("t (s)")
    ax.set_ylabel("θ (rad)")
    ax.legend(frameon=False, fontsize=8)
    fig.savefig(HERE / "control_swing_up.png", dpi=110)
    plt.close(fig)


def main() -> None:
    eom = lagrangian.derive(lagrangian.load_model(CART_POLE))
    swing_up(eom)
    fb = lagrangian.lqr(eom, {"x": 0, "theta": 0}, Q={"theta": 10})
    closed_loop(eom, fb)
    basin(eom, fb)


if __name__ == "__main__":
    main()
