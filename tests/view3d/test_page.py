"""The page itself: three.js inline as a classic script, a Content-Security-Policy, escaped data, its size."""

from __future__ import annotations

import json
import re
import shutil
import subprocess

import numpy as np
import pytest

import lagrangian
from lagrangian.model.zoo import serial_arm
from lagrangian.view3d import Motion, View, build_scene, view
from lagrangian.view3d.html import THREE_VERSION, library, scene_json


def test_the_library_is_one_classic_script_with_three_js_inside(tmp_path):
    code = library()
    assert f"three.js r170 ({THREE_VERSION})" in code and "Permission is hereby granted" in code  # MIT licence kept
    assert not re.search(r"^\s*(import|export)\b", code, re.MULTILINE)  # no module statement left
    node = shutil.which("node")
    if node is None:
        pytest.skip("no Node.js to run the script outside a browser")
    probe = code + "\nprocess.stdout.write(JSON.stringify([THREE.REVISION, typeof OrbitControls, " \
                   "typeof LagrangianView.mount]));"
    script = tmp_path / "probe.js"
    script.write_text("globalThis.window = globalThis;\n" + probe, encoding="utf-8")
    out = subprocess.run([node, str(script)], capture_output=True, text=True, timeout=60, check=False)
    assert out.returncode == 0, out.stderr[-2000:]
    assert json.loads(out.stdout) == ["170", "function", "function"]


def test_the_page_forbids_every_request_and_escapes_its_data():
    hostile = "</script><!-- & \u2028 \"quoted\" <b>bold</b>"
    shown = view(lagrangian.lagrange_top(), title=hostile)
    page = shown.html()
    assert "default-src 'none'" in page and "connect-src 'none'" in page
    data = scene_json(shown.scene)
    assert not set("<>&\u2028") & set(data)
    assert json.loads(data)["title"] == hostile
    assert f"<title>{hostile}</title>" not in page and "<title>&lt;/script&gt;" in page
    assert not re.search(r"(src|href)\s*=\s*[\"']?(https?:|//)", page)  # nothing to fetch


def test_ten_seconds_of_a_seven_joint_arm_at_100_frames_per_second_fit_in_3_mb():
    model = serial_arm(7)
    t = np.linspace(0.0, 10.0, 1001)
    q = 0.3 + 0.8 * np.sin(np.outer(t, np.arange(1, 8)) * 0.7)
    qd = 0.8 * 0.7 * np.arange(1, 8) * np.cos(np.outer(t, np.arange(1, 8)) * 0.7)
    values = {p.name: p.value for p in model.parameters}
    scene = build_scene(model, [Motion("arm", t, q, qd)], values)
    assert len(scene.t) == 1001 and len(scene.arrows) == 7
    size = len(View(scene).html().encode("utf-8"))
    assert size < 3 * 2**20, size
