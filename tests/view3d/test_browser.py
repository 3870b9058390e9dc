"""The 3-D view in a real browser (headless Chromium, software WebGL): the pixels show the bodies where they are.

For the double pendulum, the top and a URDF arm, the 3-D positions of points of the bodies are
computed here by hand from the trajectory's angles (the closed forms written in each test, not
the engine's kinematics); projected through the camera matrix the page exposes, the pixels there
have the bodies' colours.  Moving the slider to t shows the state at t, playing advances time, the
page requests nothing but itself and logs nothing, and hostile names reach the page as text.
"""

from __future__ import annotations

import html
import re
import time

import numpy as np
import pytest
from view_test_support import has_colour, motion, open_view, page_messages, pixels, project

import lagrangian
from lagrangian.view3d import view

pytestmark = pytest.mark.browser

BLUE, RED, GREEN = "#1f77b4", "#d62728", "#2ca02c"


def _quiet(page) -> None:
    """Labels, triads, angles and traces off: nothing over the bodies but the bodies."""
    for key in ("labels", "frames", "angles", "traces"):
        page.evaluate(f"lagrangianView.show('{key}', false)")


def _shot_at(page, t: float):
    page.evaluate(f"lagrangianView.setTime({t!r})")
    return pixels(page.screenshot()), page.evaluate("lagrangianView.cameraMatrix()")


def _rotation_x(angle: float) -> np.ndarray:
    c, s = np.cos(angle), np.sin(angle)
    return np.array([[1, 0, 0], [0, c, -s], [0, s, c]])


def test_double_pendulum_bodies_are_where_the_angles_put_them(browser, tmp_path):
    eom, traj = motion("double_pendulum.toml", 3.0, 301)
    page = open_view(browser, view(traj, eom), tmp_path)
    _quiet(page)
    l1, l2 = traj.parameters["l1"], traj.parameters["l2"]
    for t in (0.0, 0.73, 1.91):
        th1 = np.interp(t, traj.t, traj.column("theta1"))
        th2 = np.interp(t, traj.t, traj.column("theta2"))
        # R1 turns from R0 by θ1 about x0: OA = −l1 z1 = l1 (0, sin θ1, −cos θ1); G2 = A + l2/2 (0, sin, −cos)(θ1 + θ2).
        a = l1 * np.array([0.0, np.sin(th1), -np.cos(th1)])
        g1, g2 = a / 2, a + l2 / 2 * np.array([0.0, np.sin(th1 + th2), -np.cos(th1 + th2)])
        image, camera = _shot_at(page, t)
        assert has_colour(image, project(camera, g1), BLUE), t
        assert has_colour(image, project(camera, g2), RED), t
        # Three quarters of the way along each rod as well: the rod lies where the angle says.
        assert has_colour(image, project(camera, a + 0.75 * (2 * (g2 - a))), RED), t
    assert page_messages(page) == []
    assert page.requests() == [(tmp_path / "view.html").as_uri()]


def test_the_slider_shows_the_state_at_its_time_and_play_advances(browser, tmp_path):
    eom, traj = motion("double_pendulum.toml", 3.0, 301)
    page = open_view(browser, view(traj, eom), tmp_path)
    _quiet(page)
    l1, l2 = traj.parameters["l1"], traj.parameters["l2"]

    def bob(t: float) -> np.ndarray:  # the free end of the second rod
        th1 = np.interp(t, traj.t, traj.column("theta1"))
        th12 = th1 + np.interp(t, traj.t, traj.column("theta2"))
        return l1 * np.array([0, np.sin(th1), -np.cos(th1)]) + l2 * np.array([0, np.sin(th12), -np.cos(th12)])

    # The slider is the page's own control (1000 steps over the run): set it as a hand would, then read the time.
    page.evaluate("(() => { const s = document.querySelector('.lgv-slider'); s.value = '410';"
                  " s.dispatchEvent(new Event('input')); })()")
    page.evaluate("new Promise(r => requestAnimationFrame(() => requestAnimationFrame(r)))", await_promise=True)
    t = page.evaluate("lagrangianView.time()")
    assert t == pytest.approx(0.41 * 3.0, abs=1e-12)
    image = pixels(page.screenshot())
    camera = page.evaluate("lagrangianView.cameraMatrix()")
    inside = bob(t) - 0.03 * (bob(t) - np.array([0, 0, 0]))  # just inside the rod's free end
    assert has_colour(image, project(camera, inside), RED)
    # Where the bob was at t = 0 there is nothing now (the pendulum has swung away).
    far = project(camera, bob(0.0) - 0.03 * bob(0.0))
    assert not has_colour(image, far, RED) and not has_colour(image, far, BLUE)
    assert page.evaluate("document.querySelector('.lgv-time').textContent") == f"t = {t:.3f} s"
    # Play: time goes on, frames are drawn; pause stops it.
    frames = page.evaluate("lagrangianView.frameCount")
    page.evaluate("lagrangianView.play()")
    time.sleep(1.0)
    page.evaluate("lagrangianView.pause()")
    later = page.evaluate("lagrangianView.time()")
    assert later != pytest.approx(t) and page.evaluate("lagrangianView.frameCount") > frames + 5
    assert page.evaluate("lagrangianView.playing()") is False
    assert page_messages(page) == []


def test_top_disk_is_at_g_on_its_leaning_axis(browser, tmp_path):
    eom, traj = motion("lagrange_top.toml", 1.0, 501)
    page = open_view(browser, view(traj, eom), tmp_path)
    _quiet(page)
    a = traj.parameters["a"]
    for t in (0.0, 0.37, 0.81):
        psi, theta = (np.interp(t, traj.t, traj.column(n)) for n in ("psi", "theta"))
        z = np.array([np.sin(theta) * np.sin(psi), -np.sin(theta) * np.cos(psi), np.cos(theta)])  # the top's axis
        image, camera = _shot_at(page, t)
        assert has_colour(image, project(camera, a * z), BLUE), t  # G, the disk's centre
    assert page_messages(page) == []
    assert page.requests() == [(tmp_path / "view.html").as_uri()]


def test_urdf_arm_links_have_their_declared_colours_where_the_joints_put_them(browser, tmp_path):
    eom, traj = motion("rrr_arm.urdf", 1.0, 201, waist=0.6, shoulder=-0.4, elbow=0.9)
    page = open_view(browser, view(traj, eom), tmp_path)
    _quiet(page)

    def turn(waist: float, pitch: float, x: float) -> np.ndarray:  # Rz(waist) Ry(pitch) (x, 0, 0)
        return x * np.array([np.cos(waist) * np.cos(pitch), np.sin(waist) * np.cos(pitch), -np.sin(pitch)])

    for t in (0.0, 0.55):
        w, s, e = (np.interp(t, traj.t, traj.column(n)) for n in ("waist", "shoulder", "elbow"))
        shoulder = np.array([0.0, 0.0, 0.3])
        elbow = shoulder + turn(w, s, 0.5)
        image, camera = _shot_at(page, t)
        # examples/rrr_arm.urdf: the column's cylinder (blue), the upper arm's box (red), the forearm's (green).
        assert has_colour(image, project(camera, [0.0, 0.0, 0.2]), "#1f78b5"), t
        assert has_colour(image, project(camera, shoulder + turn(w, s, 0.3)), "#d62629"), t
        assert has_colour(image, project(camera, elbow + turn(w, s + e, 0.2)), "#2ba12b"), t
    assert page_messages(page) == []
    assert page.requests() == [(tmp_path / "view.html").as_uri()]


HOSTILE = '</script><script>window.__owned = 1</script><img src=x onerror="window.__owned = 2">"\'&amp;'


def test_hostile_names_reach_the_page_as_text(browser, tmp_path):
    from lagrangian_test_support import example_text

    source = re.sub(r'(?m)^name = .*$', lambda _: f"name = {_toml(HOSTILE)}", example_text("simple_pendulum.toml"),
                    count=1)
    source = re.sub(r'(?m)^title = .*$', "", source)
    model = lagrangian.parse_model(source)
    eom, traj = motion("simple_pendulum.toml", 1.0, 51)
    shown = view(traj, eom, labels=[HOSTILE], title=HOSTILE)
    source_html = shown.html()
    assert HOSTILE not in source_html and "\\u003c/script\\u003e\\u003cscript\\u003e" in source_html
    page = open_view(browser, shown, tmp_path)
    assert page.evaluate("document.title") == HOSTILE
    assert page.evaluate("document.querySelector('.lgv-title').textContent") == HOSTILE
    assert page.evaluate("window.__owned === undefined") is True
    assert page.evaluate("document.querySelectorAll('img').length") == 0
    assert page.evaluate("document.scripts.length") == 3  # the scene's data, its mount, the library
    at_rest = open_view(browser, view(model), tmp_path)
    assert at_rest.evaluate("document.title") == HOSTILE and at_rest.evaluate("window.__owned === undefined")
    assert page_messages(page) == [] and page_messages(at_rest) == []


def _toml(text: str) -> str:
    return '"' + text.replace("\\", "\\\\").replace('"', '\\"') + '"'


def test_the_notebook_display_is_the_page_in_an_iframe(browser, tmp_path):
    shown = view(lagrangian.lagrange_top())
    fragment = shown._repr_html_()
    match = re.fullmatch(r'<iframe srcdoc="([^"]*)" (.*)></iframe>', fragment, re.DOTALL)
    assert match and 'sandbox="allow-scripts"' in match.group(2)
    assert html.unescape(match.group(1)) == shown.html()
    # A notebook's output cell: the iframe alone in a page; it draws the top (pixels other than white).
    outer = tmp_path / "cell.html"
    outer.write_text(f"<!DOCTYPE html><html><body style='margin:0'>{fragment}</body></html>", encoding="utf-8")
    page = browser.open(outer, width=900, height=620)
    deadline = time.monotonic() + 30
    while time.monotonic() < deadline:
        image = pixels(page.screenshot())[:540]
        if np.mean(np.any(image < 200, axis=2)) > 0.01:
            break
        time.sleep(0.3)
    assert np.mean(np.any(image < 200, axis=2)) > 0.01  # the disk, the grid, the labels
    assert page_messages(page) == []
    assert all(u.startswith(("about:", outer.as_uri())) for u in page.requests()), page.requests()
