"""The public surface of the package."""

from pathlib import Path

import pytest

import lagrangian
from lagrangian.model.zoo import LAGRANGE_TOP_TOML

ROOT = Path(__file__).resolve().parents[1]


def test_dir_is_all():
    assert set(dir(lagrangian)) == set(lagrangian.__all__)
    for name in lagrangian.__all__:
        assert hasattr(lagrangian, name), name


def test_embedded_default_is_the_example_file():
    assert (ROOT / "examples" / "lagrange_top.toml").read_text(encoding="utf-8") == LAGRANGE_TOP_TOML


def test_no_evaluation_of_text_in_the_package():
    # Model files come from strangers: nothing in src may evaluate text.
    for path in (ROOT / "src" / "lagrangian").rglob("*.py"):
        code = path.read_text(encoding="utf-8")
        for forbidden in ("eval(", "exec(", "sympify(", "parse_expr("):
            assert forbidden not in code.replace("_sympy_()", ""), f"{forbidden} in {path}"


@pytest.mark.slow
def test_module_level_imports_flow_one_way():
    # model -> kinematics -> dynamics -> analysis -> numerics -> output/plotting/optimal -> cli: a stage's
    # modules never import a later stage at module level (not even for annotations, under TYPE_CHECKING).
    import ast

    order = {"model": 0, "kinematics": 1, "dynamics": 2, "analysis": 3, "numerics": 4, "output": 5,
             "plotting": 5, "optimal": 5, "cli": 6}
    for path in (ROOT / "src" / "lagrangian").rglob("*.py"):
        parts = path.relative_to(ROOT / "src" / "lagrangian").parts
        if len(parts) < 2 or parts[0] not in order:
            continue
        tree = ast.parse(path.read_text(encoding="utf-8"))
        nodes = list(tree.body) + [n for top in tree.body if isinstance(top, ast.If) for n in top.body]
        for node in nodes:
            if isinstance(node, ast.ImportFrom) and node.level >= 1:
                # Resolved from the module's package, at any depth (output/report/steps/x.py: ``....dynamics``).
                package = parts[:-1]
                base = package[:len(package) - (node.level - 1)]
                top = node.module.split(".")[:1] if node.module else [a.name for a in node.names]
                for target in [base[0]] if base else top:
                    if target in order:
                        assert order[target] <= order[parts[0]], f"{path} imports {target} (a later stage)"


@pytest.mark.slow
def test_every_relative_import_names_a_module_that_exists():
    # Also the imports inside functions, which run only on some paths (a report with a given
    # constraint): after modules move (output/report/), a stale `..model` would fail only there.
    import ast
    import importlib.util

    src = ROOT / "src"
    for path in (src / "lagrangian").rglob("*.py"):
        package = path.relative_to(src).parent.parts  # of a module and of an __init__ alike
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            if isinstance(node, ast.ImportFrom) and node.level >= 1:
                base = package[:len(package) - (node.level - 1)]
                assert base, f"{path}:{node.lineno} imports above the package"
                target = ".".join(base) + ("." + node.module if node.module else "")
                assert importlib.util.find_spec(target) is not None, f"{path}:{node.lineno}: no module {target}"
