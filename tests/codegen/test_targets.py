"""The export targets: one interface (`AbstractTarget`), one module each, none importing the dispatcher."""

from __future__ import annotations

import ast
import typing
from pathlib import Path

import pytest

import lagrangian
from lagrangian.codegen import EXPORT_TARGETS, AbstractTarget, export_files, exported_symbols
from lagrangian.codegen.targets import CTarget, JaxTarget, NumpyTarget, OctaveTarget

TARGETS = Path(lagrangian.__file__).parent / "codegen" / "targets"


@pytest.fixture(scope="module")
def top() -> lagrangian.EquationsOfMotion:
    return lagrangian.derive(lagrangian.lagrange_top())


def test_each_target_is_registered_under_its_name():
    assert set(EXPORT_TARGETS) == {"c", "numpy", "jax", "octave"}
    for name, target in EXPORT_TARGETS.items():
        assert isinstance(target, AbstractTarget)
        assert target.name == name
        assert getattr(type(target), "__final__", False), f"{type(target).__name__} is not final"
    assert {type(t) for t in EXPORT_TARGETS.values()} == {CTarget, JaxTarget, NumpyTarget, OctaveTarget}


def test_a_target_without_files_cannot_be_made():
    class Partial(AbstractTarget):
        name = "partial"

    with pytest.raises(TypeError):
        Partial()  # type: ignore[abstract]


def test_no_target_imports_the_dispatcher():
    # The targets read `base` (ExportedSymbols, cse_lines) and the printers; the dispatcher imports them.
    for path in TARGETS.glob("*.py"):
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            if isinstance(node, ast.ImportFrom):
                module = node.module or ""
                names = [a.name for a in node.names]
                assert "_export" not in module.split(".") and "_export" not in names, f"{path.name}:{node.lineno}"
                assert not (node.level == 0 and module.startswith("lagrangian.codegen._export")), path.name


def test_only_the_c_target_gets_the_in_package_form(top):
    assert [name for name, t in EXPORT_TARGETS.items() if t.in_package_form] == ["c"]
    assert exported_symbols(top, "c").fast is not None and exported_symbols(top, "c").integrals
    numpy_symbols = exported_symbols(top, "numpy")
    assert numpy_symbols.fast is None and numpy_symbols.integrals == ()


def test_the_dispatcher_returns_what_the_target_prints(top):
    for name, target in EXPORT_TARGETS.items():
        assert export_files(top, name) == target.files(exported_symbols(top, name))


def test_the_c_target_refuses_symbols_without_the_in_package_form(top):
    with pytest.raises(ValueError, match="in-package form"):
        CTarget().files(exported_symbols(top, "numpy"))


def test_files_is_the_one_abstract_method():
    assert AbstractTarget.__abstractmethods__ == frozenset({"files"})
    hints = typing.get_type_hints(AbstractTarget.files)
    assert hints["return"] == dict[str, str]
