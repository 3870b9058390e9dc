"""The figures of docs/control.md: the cart-pole's LQR closed loop and its basin of attraction.

Run from the repository root:  .venv/bin/python docs/figures/control_figures.py
Writes docs/figures/control_closed_loop.png and docs/figures/control_basin.png.
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


def main() -> None:
    eom = lagrangian.derive(lagrangian.load_model(CART_POLE))
    fb = lagrangian.lqr(eom, {"x": 0, "theta": 0}, Q={"theta": 10})
    closed_loop(eom, fb)
    basin(eom, fb)


if __name__ == "__main__":
    main()
