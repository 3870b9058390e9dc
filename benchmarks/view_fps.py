"""How fast the 3-D view animates, measured in the browser, and how large its file is.

    .venv/bin/python benchmarks/view_fps.py              # 30-body chain, 10 s at 100 frames/s, 5 s of play
    .venv/bin/python benchmarks/view_fps.py --bodies 50 --seconds 8

The page of a chain of N rigid rods (`lagrangian.model.zoo.spatial_chain`: each rod a body, the
solid of its inertia, joined to the next by a ball joint) moving for 10 s, sampled at 100 frames/s, is opened in
headless Chromium (software WebGL, SwiftShader) at 800 × 600; the page's own benchmark plays it
for the given seconds, drawing every animation frame the browser asks for
(``requestAnimationFrame``), and reports the frames per second and the milliseconds each frame's
work took (interpolation, matrices, three.js's draw call submission).  The motion is a
prescribed q(t) (sines of growing frequency), not an integration: what is measured is the
drawing, which does not depend on where q came from.

Peers in the same run: an empty page's ``requestAnimationFrame`` rate (the display's cadence in
this browser: the most any page can show), and the page of a single pendulum; and, for the size,
the matplotlib animation's frame time for the same chain (the GIF's renderer).
"""

from __future__ import annotations

import argparse
import tempfile
import time
from pathlib import Path

import numpy as np

from lagrangian.model.zoo import serial_arm, spatial_chain
from lagrangian.view3d import Motion, View, build_scene
from lagrangian.view3d._chromium import Browser

EMPTY = """<!DOCTYPE html><html><body><script>
window.rafRate = s => new Promise(r => { let n = 0, t0 = null;
  function f(t) { if (t0 === null) t0 = t; n++; if (t - t0 < 1000 * s) requestAnimationFrame(f);
                  else r({fps: (n - 1) / ((t - t0) / 1000)}); }
  requestAnimationFrame(f); });
</script></body></html>"""


def chain_view(bodies: int, seconds: float = 10.0, rate: float = 100.0) -> View:
    model = spatial_chain(bodies)
    t = np.linspace(0.0, seconds, int(seconds * rate) + 1)
    k = np.arange(1, len(model.coordinates) + 1)
    q = 0.4 * np.sin(np.outer(t, 0.5 + 0.05 * k))
    qd = 0.4 * (0.5 + 0.05 * k) * np.cos(np.outer(t, 0.5 + 0.05 * k))
    values = {p.name: p.value for p in model.parameters}
    return View(build_scene(model, [Motion(model.name, t, q, qd)], values))


def arm_size() -> int:
    """Bytes of the page of 10 s of the 7-joint arm at 100 frames/s."""
    model = serial_arm(7)
    t = np.linspace(0.0, 10.0, 1001)
    q = 0.3 + 0.8 * np.sin(np.outer(t, np.arange(1, 8)) * 0.7)
    qd = 0.56 * np.arange(1, 8) * np.cos(np.outer(t, np.arange(1, 8)) * 0.7)
    return len(View(build_scene(model, [Motion("arm", t, q, qd)], {p.name: p.value for p in model.parameters}))
               .html().encode())


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--bodies", type=int, default=30, help="rods of the chain (default 30)")
    parser.add_argument("--seconds", type=float, default=5.0, help="seconds of play measured")
    args = parser.parse_args()
    folder = Path(tempfile.mkdtemp(prefix="view-fps-"))
    start = time.perf_counter()
    chain = chain_view(args.bodies)
    build = time.perf_counter() - start
    (folder / "chain.html").write_text(chain.html(), encoding="utf-8")
    (folder / "one.html").write_text(chain_view(1).html(), encoding="utf-8")
    (folder / "empty.html").write_text(EMPTY, encoding="utf-8")
    size = (folder / "chain.html").stat().st_size
    print(f"{args.bodies}-body chain, 10 s at 100 frames/s: scene built in {build:.2f} s, page {size / 2**20:.2f} MB "
          f"({len(chain.scene.parts)} parts, {len(chain.scene.carriers)} carriers)")
    print(f"7-joint arm (zoo serial_arm), 10 s at 100 frames/s: page {arm_size() / 2**20:.2f} MB (target < 3 MB)")
    with Browser() as browser:
        empty = browser.open(folder / "empty.html")
        empty.front()
        display = empty.evaluate(f"rafRate({args.seconds})", await_promise=True, timeout=120)["fps"]
        results = {}
        for name in ("one", "chain"):
            page = browser.open(folder / f"{name}.html")
            page.wait_for("window.lagrangianView !== undefined")
            page.evaluate("lagrangianView.benchmark(1)", await_promise=True, timeout=120)  # warm up
            results[name] = page.evaluate(f"lagrangianView.benchmark({args.seconds})", await_promise=True,
                                          timeout=120)
    print(f"empty page's requestAnimationFrame rate (the display's cadence): {display:.1f} frames/s")
    for name, label in (("one", "1-body pendulum"), ("chain", f"{args.bodies}-body chain")):
        r = results[name]
        print(f"{label:>18}: {r['fps']:.1f} frames/s ({r['fps'] / display:.2f} of the display's), "
              f"work per frame {r['work_ms_mean']:.2f} ms mean, {r['work_ms_p95']:.2f} ms p95")
    from lagrangian.view3d._matplotlib import Renderer
    from lagrangian.view3d._wireframe import wireframe

    renderer = Renderer(wireframe(chain.scene), title="chain", size=5.0, dpi=80, trail=0, elev=20.0, azim=-60.0)
    renderer.rgba(0)
    start = time.perf_counter()
    for i in range(1, 41):
        renderer.rgba(i)
    per = (time.perf_counter() - start) / 40
    print(f"matplotlib's frame of the same chain (the GIF's renderer, 400 × 400): {1e3 * per:.1f} ms, "
          f"{1 / per:.0f} frames/s")


if __name__ == "__main__":
    main()
