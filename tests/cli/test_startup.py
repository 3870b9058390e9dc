"""What the command line loads: the parser is built from light modules, and a simulation whose
library and plan are cached needs neither SymPy nor SciPy."""

import os
import subprocess
import sys
from pathlib import Path

import pytest

from lagrangian.cli._arguments import export, simulate
from lagrangian.numerics import METHODS, STABILIZATIONS
from lagrangian.output import EXPORT_TARGETS

ROOT = Path(__file__).resolve().parents[2]
#: What parsing any command line must not load (each costs tenths of a second or more).
HEAVY = ("numpy", "symengine", "sympy", "scipy", "lagrangian.model", "lagrangian.dynamics", "lagrangian.numerics",
         "lagrangian.output")

#: Runs the command line in-process, then prints the heavy packages it loaded.
RUN = ("import sys\n"
       "from lagrangian.cli.main import main\n"
       "code = main(sys.argv[1:])\n"
       "print(' '.join(sorted({m.split('.')[0] for m in sys.modules} & {'sympy', 'scipy', 'matplotlib'})))\n"
       "sys.exit(code)\n")


def test_the_parser_offers_the_methods_stabilizations_and_targets_of_the_library():
    assert simulate.METHODS == METHODS
    assert simulate.STABILIZATIONS == STABILIZATIONS
    assert export.TARGETS == tuple(EXPORT_TARGETS)


def test_help_and_parsing_every_command_import_nothing_of_the_pipeline():
    code = (
        "import sys\n"
        "from lagrangian.cli.main import COMMANDS, _parser\n"
        "parser = _parser()\n"
        "parser.format_help()\n"
        "extra = {'identify': ['m.toml', 'data.csv', '--fit', 'm'], 'export': ['--to', 'c'], 'sweep': ['--out', 'x.zarr'],\n"
        "         'optimize': ['problem.toml']}\n"
        "for name in COMMANDS:\n"
        "    parser.parse_args([name, *extra.get(name, [])])\n"
        "print(' '.join(sorted(m for m in sys.modules if m.startswith(" + repr(HEAVY) + "))))\n")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout
    assert out.split() == []


@pytest.mark.slow
def test_a_cached_simulation_loads_neither_sympy_nor_scipy(tmp_path):
    env = {**os.environ, "LAGRANGIAN_CACHE": str(tmp_path / "cache")}
    runs = []
    for name in ("first.csv", "again.csv"):
        argv = [sys.executable, "-c", RUN, "simulate", str(ROOT / "examples" / "lagrange_top.toml"), "--t-end", "1",
                "-o", str(tmp_path / name)]
        runs.append(subprocess.run(argv, capture_output=True, text=True, env=env, timeout=600, check=False))
        assert runs[-1].returncode == 0 and runs[-1].stderr == "", runs[-1].stderr
    first, again = runs
    assert again.stdout.splitlines()[-1] == ""  # no SymPy, SciPy or matplotlib
    assert again.stdout.splitlines()[1] == first.stdout.splitlines()[1]  # "conservation: K relative drift ..."
    rows = [[line for line in (tmp_path / name).read_text().splitlines() if not line.startswith("#")]
            for name in ("first.csv", "again.csv")]
    assert rows[0] == rows[1] and len(rows[0]) > 100
