"""The code-generation stage sits between analysis and numerics: symbols in, source text out."""

from __future__ import annotations

import ast
import subprocess
import sys
from pathlib import Path

import lagrangian

PACKAGE = Path(lagrangian.__file__).parent
#: What codegen may import of the package: the stages before it, the errors and the shared helpers.
EARLIER = {"model", "kinematics", "dynamics", "analysis", "errors", "_abs_derivative", "_lazy", "__version__"}
LATER = {"numerics", "output", "plotting", "optimal", "view3d", "identification", "cli"}


def _package_imports(path: Path) -> list[tuple[int, str]]:
    """(line, first name below ``lagrangian``) of every import of the package, inside functions too."""
    package = path.relative_to(PACKAGE.parent).parent.parts  # ("lagrangian", "codegen", ...)
    out = []
    for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
        if isinstance(node, ast.ImportFrom):
            if node.level:
                base = package[:len(package) - (node.level - 1)]
                dotted = [*base, *(node.module.split(".") if node.module else [])]
            else:
                dotted = (node.module or "").split(".")
            if dotted[0] != "lagrangian":
                continue
            if len(dotted) > 1:
                out.append((node.lineno, dotted[1]))
            else:
                out += [(node.lineno, a.name) for a in node.names]
        elif isinstance(node, ast.Import):
            out += [(node.lineno, a.name.split(".")[1]) for a in node.names
                    if a.name.startswith("lagrangian.")]
    return out


def test_codegen_imports_only_earlier_stages_even_inside_functions():
    for path in (PACKAGE / "codegen").rglob("*.py"):
        for line, name in _package_imports(path):
            assert name == "codegen" or name in EARLIER, f"{path.relative_to(PACKAGE)}:{line} imports `{name}`"
            assert name not in LATER


def test_nothing_in_codegen_relies_on_assert():
    # `python -O` removes asserts: a check that guards generated code must be a plain `if`.
    for path in (PACKAGE / "codegen").rglob("*.py"):
        tree = ast.parse(path.read_text(encoding="utf-8"))
        assert not any(isinstance(node, ast.Assert) for node in ast.walk(tree)), path.relative_to(PACKAGE)


def test_importing_codegen_loads_no_later_stage_nor_sympy():
    code = ("import sys\nfrom lagrangian.codegen import generate_c, export, EXPORT_TARGETS\n"
            "print(sorted(m for m in sys.modules if m.split('.')[0] == 'sympy'"
            " or m.split('.')[:2] in (['lagrangian', 'numerics'], ['lagrangian', 'output'])))")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "[]", out.stdout
