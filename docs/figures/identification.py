"""The figure of docs/identification.md: a cart-pole's masses and rod length fitted to a measured motion.

1. A "measured" record: the inverted pendulum on a cart of `examples/inverted_pendulum_cart.toml`,
   with other values than the file's (mc = 1.3 kg, m = 0.25 kg, l = 0.55 m), integrated by SciPy on
   its equations written out by hand (not by lagrangian), pushed by a multi-sine force F(t) applied as
   the linear interpolation of its samples, sampled at 200 Hz for 5 s; white noise of 1e-4 (m, rad)
   on x and θ.  Written to ``cart_record.csv`` (t, x, theta, F).
2. ``identify`` by the regressor (mc, m with l known: linear) and by shooting (mc, m and l).
3. The figure ``identification.png``: the record and the motion simulated with the fitted values,
   the residuals, and each estimate ± 3 standard errors against the truth.

Run:  .venv/bin/python docs/figures/identification.py [OUTPUT_DIR]
(default: the figure into docs/figures, the record into a temporary folder)
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
from scipy.integrate import solve_ivp

import lagrangian
from lagrangian.identification import SavitzkyGolay, Shooting, identify

ROOT = Path(__file__).resolve().parents[2]
MODEL = ROOT / "examples" / "inverted_pendulum_cart.toml"
TRUE = {"mc": 1.3, "m": 0.25, "l": 0.55}
G = 9.81


def record(t_end: float = 5.0, rate: float = 200.0, noise: float = 1e-4, seed: int = 1) -> dict[str, np.ndarray]:
    """(mc + m) ẍ + m l cos θ θ̈ − m l sin θ θ̇² = F,  m l cos θ ẍ + m l² θ̈ − m g l sin θ = 0 (θ from the
    ascending vertical), by SciPy's DOP853 between consecutive samples (F linear on each)."""
    t = np.linspace(0.0, t_end, round(t_end * rate) + 1)
    F = 1.5 * np.sin(1.7 * t) + 1.0 * np.sin(4.3 * t + 1.0) + 0.5 * np.sin(9.1 * t)
    mc, m, l = TRUE["mc"], TRUE["m"], TRUE["l"]

    def f(time, y, k):
        _, th, xd, thd = y
        force = F[k] + (F[k + 1] - F[k]) * (time - t[k]) / (t[k + 1] - t[k])
        a11, a12, a22 = mc + m, m * l * np.cos(th), m * l * l
        r1, r2 = force + m * l * np.sin(th) * thd**2, m * G * l * np.sin(th)
        det = a11 * a22 - a12 * a12
        return [xd, thd, (a22 * r1 - a12 * r2) / det, (a11 * r2 - a12 * r1) / det]

    y = np.empty((len(t), 4))
    y[0] = [0.0, 3.0, 0.0, 0.0]  # hanging 0.14 rad from the bottom
    for k in range(len(t) - 1):
        y[k + 1] = solve_ivp(f, (t[k], t[k + 1]), y[k], args=(k,), rtol=1e-11, atol=1e-11, method="DOP853").y[:, -1]
    rng = np.random.default_rng(seed)
    return {"t": t, "x": y[:, 0] + rng.normal(scale=noise, size=len(t)),
            "theta": y[:, 1] + rng.normal(scale=noise, size=len(t)), "F": F}


def main(out: Path, records: Path) -> None:
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    out.mkdir(parents=True, exist_ok=True)
    data = record()
    csv = records / "cart_record.csv"
    columns = ["t", "x", "theta", "F"]
    rows = np.column_stack([data[c] for c in columns])
    csv.write_text("# a cart-pole pushed by F, x and theta measured with noise 1e-4\n" + ",".join(columns) + "\n"
                   + "".join(",".join(repr(float(v)) for v in row) + "\n" for row in rows))
    eom = lagrangian.derive(lagrangian.load_model(MODEL))
    linear = identify(eom, csv, ["mc", "m"], values={"l": TRUE["l"]}, derivatives=SavitzkyGolay(41, 4))
    shot = identify(eom, csv, ["mc", "m", "l"], guess={"mc": 1.0, "m": 0.2, "l": 0.6}, shooting=Shooting(segments=10))
    print(linear.summary())
    print(shot.summary())
    fig = Figure(figsize=(10, 7.5), layout="constrained")
    FigureCanvasAgg(fig)
    axes = fig.subplot_mosaic([["motion", "motion"], ["residuals", "estimates"]], height_ratios=[1.2, 1])
    ax = axes["motion"]
    t = data["t"]
    fitted = data["theta"] - shot.residuals[:, shot.residual_names.index("theta")]
    ax.plot(t, data["theta"], ".", ms=2.5, color="0.6", label="θ measured")
    ax.plot(t, fitted, color="C0", lw=1.2, label="θ simulated with the fitted mc, m, l (shooting)")
    ax.set_ylabel("θ (rad)")
    twin = ax.twinx()
    twin.plot(t, data["F"], color="C3", lw=0.8, alpha=0.6)
    twin.set_ylabel("F (N)", color="C3")
    ax.set_xlabel("t (s)")
    ax.legend(loc="upper right", fontsize=8)
    ax.set_title("The record (noise 1e-4 rad) and the fitted model's motion")
    ax = axes["residuals"]
    for k, name in enumerate(shot.residual_names):
        ax.plot(t, shot.residuals[:, k] * 1e4, lw=0.6, label=name)
    ax.set_xlabel("t (s)")
    ax.set_ylabel("residual (1e-4 m or rad)")
    ax.set_title("Shooting residuals: the measurement noise")
    ax.legend(fontsize=8)
    ax = axes["estimates"]
    labels, ys = [], 0
    for fit, colour, what in ((linear, "C1", "regressor"), (shot, "C0", "shooting")):
        for name in fit.parameters:
            rel = (fit[name] - TRUE[name]) / TRUE[name]
            err = 3 * fit.std[name] / TRUE[name]
            ax.errorbar(rel * 1e3, ys, xerr=err * 1e3, fmt="o", color=colour, capsize=3)
            labels.append(f"{name} ({what})")
            ys += 1
    ax.axvline(0.0, color="k", lw=0.8)
    ax.set_yticks(range(len(labels)), labels)
    ax.set_xlabel("(estimate − truth)/truth (‰), bars ± 3 standard errors")
    ax.set_title("Estimates against the values the record was made with")
    fig.savefig(out / "identification.png", dpi=110)
    print(f"wrote {out / 'identification.png'} and {csv}")


if __name__ == "__main__":
    if len(sys.argv) > 1:
        main(Path(sys.argv[1]), Path(sys.argv[1]))
    else:
        import tempfile

        with tempfile.TemporaryDirectory() as tmp:
            main(Path(__file__).resolve().parent, Path(tmp))
