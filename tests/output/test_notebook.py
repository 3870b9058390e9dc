"""The notebooks of docs/notebooks run from top to bottom: executed by a Jupyter kernel (nbclient +
ipykernel, in the ``test`` extra), so that they never rot.

The notebook itself asserts that the first integrals K, H and E are conserved along the simulated
motion; here we check that every cell ran and that each object showed the way it should in a
notebook: rendered math for the equations and the integrals, a table for the trajectory, images for
the figures, and the report written.  control.ipynb asserts its own results (the swing-up's objective and
replay, the closed loop held upright, the mass identified within 3 standard errors, the new plan caught);
here every cell ran and the figures showed."""

from __future__ import annotations

from pathlib import Path

import pytest

NOTEBOOKS = Path(__file__).resolve().parents[2] / "docs" / "notebooks"
NOTEBOOK = NOTEBOOKS / "lagrange_top.ipynb"


@pytest.mark.slow
def test_lagrange_top_notebook_runs(tmp_path):
    nbformat = pytest.importorskip("nbformat")
    nbclient = pytest.importorskip("nbclient")
    pytest.importorskip("ipykernel")
    pytest.importorskip("matplotlib")
    notebook = nbformat.read(NOTEBOOK, as_version=4)
    assert not any(cell.get("outputs") for cell in notebook.cells if cell.cell_type == "code"), \
        "commit the notebook without its outputs"
    # The kernel is this interpreter (ipykernel's native kernel) and inherits PYTHONPATH, so it imports
    # the same lagrangian as the tests; it runs in tmp_path, where the report is written.
    nbclient.NotebookClient(notebook, timeout=120, kernel_name="python3",
                            resources={"metadata": {"path": str(tmp_path)}}).execute()
    outputs = [cell.outputs for cell in notebook.cells if cell.cell_type == "code"]
    assert not [o for cell in outputs for o in cell if o.output_type == "error"]
    data = [[o.get("data", {}) for o in cell] for cell in outputs]
    assert r"\ddot{\theta}" in data[0][-1]["text/latex"]          # eom: the three equations, rendered
    assert r"\ddot{\theta}" in data[1][-1]["text/latex"]          # L(theta) alone
    shown = [d["text/latex"] for d in data[2] if "text/latex" in d]  # K, H, E displayed one by one
    assert len(shown) == 3 and "['K', 'H', 'E']" in data[2][-1]["text/plain"]
    assert "<table" in data[3][-1]["text/html"]                   # the trajectory's summary
    assert "image/png" in data[5][-1] and "image/png" in data[6][-1]  # the apex and energy figures
    assert (tmp_path / "lagrange_top_report.html").stat().st_size > 10_000
    assert data[8][-1]["text/html"].startswith("<iframe srcdoc=")  # the 3-D view, a page in an iframe


@pytest.mark.slow
def test_control_notebook_runs():
    nbformat = pytest.importorskip("nbformat")
    nbclient = pytest.importorskip("nbclient")
    pytest.importorskip("ipykernel")
    pytest.importorskip("matplotlib")
    pytest.importorskip("casadi")
    notebook = nbformat.read(NOTEBOOKS / "control.ipynb", as_version=4)
    assert not any(cell.get("outputs") for cell in notebook.cells if cell.cell_type == "code"), \
        "commit the notebook without its outputs"
    # It runs where it lies (its model path is relative to docs/notebooks) and writes nothing.
    nbclient.NotebookClient(notebook, timeout=120, kernel_name="python3",
                            resources={"metadata": {"path": str(NOTEBOOKS)}}).execute()
    outputs = [cell.outputs for cell in notebook.cells if cell.cell_type == "code"]
    assert not [o for cell in outputs for o in cell if o.output_type == "error"]
    images = [o for cell in outputs for o in cell if "image/png" in o.get("data", {})]
    assert len(images) == 2
    text = "".join(o.get("text", "") for cell in outputs for o in cell)
    assert "status: optimal" in text and "identification of" in text
