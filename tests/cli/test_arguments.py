"""The command line's parser is built from light modules: the pipeline is imported only to run a command."""

import subprocess
import sys

from lagrangian.cli._arguments import export, simulate
from lagrangian.numerics import METHODS, STABILIZATIONS
from lagrangian.output import EXPORT_TARGETS

#: What parsing any command line must not load (each costs tenths of a second or more).
HEAVY = ("numpy", "symengine", "sympy", "scipy", "lagrangian.model", "lagrangian.dynamics", "lagrangian.numerics",
         "lagrangian.output")


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
        "extra = {'identify': ['m.toml', 'data.csv', '--fit', 'm'], 'export': ['--to', 'c'], 'sweep': ['--out', 'x.zarr']}\n"
        "for name in COMMANDS:\n"
        "    parser.parse_args([name, *extra.get(name, [])])\n"
        "print(' '.join(sorted(m for m in sys.modules if m.startswith(" + repr(HEAVY) + "))))\n")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout
    assert out.split() == []
