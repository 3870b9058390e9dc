"""matplotlib is optional: imported only when a figure is made, with a clear message when missing."""

from __future__ import annotations

import subprocess
import sys

import pytest

from lagrangian.errors import LagrangianError, OutputError
from lagrangian.plotting import MissingPlotDependency
from lagrangian.plotting._mpl import require_matplotlib


@pytest.mark.slow
def test_importing_the_package_does_not_import_matplotlib():
    code = ("import sys, lagrangian, lagrangian.numerics, lagrangian.plotting; "
            "print('matplotlib' in sys.modules)")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "False"


def test_missing_matplotlib_says_how_to_install_it(monkeypatch):
    for name in list(sys.modules):
        if name == "matplotlib" or name.startswith("matplotlib."):
            monkeypatch.delitem(sys.modules, name)
    monkeypatch.setitem(sys.modules, "matplotlib", None)  # import matplotlib now fails
    with pytest.raises(MissingPlotDependency) as info:
        require_matplotlib()
    assert isinstance(info.value, OutputError) and isinstance(info.value, LagrangianError)
    assert "lagrangian[plot]" in str(info.value)
