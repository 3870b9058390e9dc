"""The public surface of the package."""

from pathlib import Path

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
