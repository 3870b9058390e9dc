"""One list of the public API: the package's names come from one table, each resolves and is documented."""

from __future__ import annotations

import ast
import importlib
import importlib.util
import inspect
import pkgutil
from pathlib import Path
from types import ModuleType

import pytest

import lagrangian

SRC = Path(lagrangian.__file__).resolve().parent


def public_modules() -> list[str]:
    """The modules whose ``__all__`` is public API: each stage's face, and the modules the package's table names."""
    stages = [f"lagrangian.{info.name}" for info in pkgutil.iter_modules(lagrangian.__path__)
              if not info.name.startswith("_") and info.name != "cli"]  # the command line is no library API
    named = [importlib.import_module(where, "lagrangian").__name__ for where in lagrangian._WHERE]
    return sorted(set(stages) | set(named))


def _type_checking_imports(path: Path) -> dict[str, str]:
    """{name: relative module} of the ``if TYPE_CHECKING:`` block of ``path``."""
    found: dict[str, str] = {}
    for node in ast.parse(path.read_text(encoding="utf-8")).body:
        if isinstance(node, ast.If) and isinstance(node.test, ast.Name) and node.test.id == "TYPE_CHECKING":
            for statement in node.body:
                assert isinstance(statement, ast.ImportFrom), ast.dump(statement)
                for alias in statement.names:
                    # `X as X` is what marks a re-export for type checkers (PEP 484's stub rule, mypy's
                    # implicit_reexport = False)
                    assert alias.asname == alias.name, f"{path}: import {alias.name} as {alias.asname}"
                    found[alias.name] = "." * statement.level + (statement.module or "")
    return found


def _documented_data(module_name: str, name: str) -> bool:
    """Whether ``name``, a value (not a class or function), has a ``#:`` comment or a string after its assignment.

    Looked for where the value is assigned: in ``module_name``, or in the module it imports the name from
    (``from ._simulate import METHODS as METHODS``, a lazy face's table, ``from .spec import *``).
    """
    module = importlib.import_module(module_name)
    path = Path(module.__file__)
    lines = path.read_text(encoding="utf-8").splitlines()
    body = ast.parse("\n".join(lines)).body
    for k, node in enumerate(body):
        targets = (node.targets if isinstance(node, ast.Assign)
                   else [node.target] if isinstance(node, ast.AnnAssign) else [])
        if any(isinstance(t, ast.Name) and t.id == name for t in targets):
            comment = lines[node.lineno - 2].lstrip() if node.lineno >= 2 else ""
            after = body[k + 1] if k + 1 < len(body) else None
            string_after = (isinstance(after, ast.Expr) and isinstance(after.value, ast.Constant)
                            and isinstance(after.value.value, str))
            return comment.startswith("#:") or string_after
    package = module_name if path.name == "__init__.py" else module_name.rpartition(".")[0]
    for where, names in getattr(module, "_WHERE", {}).items():
        if name in names:
            return _documented_data(importlib.import_module(where, package).__name__, name)
    for node in ast.walk(ast.parse("\n".join(lines))):
        if isinstance(node, ast.ImportFrom):
            source = importlib.util.resolve_name("." * node.level + (node.module or ""), package)
            if any(alias.name == name for alias in node.names):
                return _documented_data(source, name)
            if any(alias.name == "*" for alias in node.names) and name in importlib.import_module(source).__all__:
                return _documented_data(source, name)
    return False


def _has_docstring(module: ModuleType, name: str, value: object) -> bool:
    if inspect.ismodule(value) or inspect.isroutine(value):
        return bool((value.__doc__ or "").strip())
    if inspect.isclass(value):
        doc = value.__dict__.get("__doc__") or ""
        # a dataclass without a docstring is given its signature as one: not a description
        return bool(doc.strip()) and not doc.startswith(f"{value.__name__}(")
    return _documented_data(module.__name__, name)


def test_the_package_table_is_the_source_of_all_and_of_the_lazy_names():
    table = [name for names in lagrangian._WHERE.values() for name in names]
    assert len(table) == len(set(table)), "a name listed twice in lagrangian._WHERE"
    assert lagrangian.__all__ == ["__version__", *table]


@pytest.mark.parametrize("package", ["lagrangian", "lagrangian.analysis", "lagrangian.numerics"])
def test_type_checking_imports_say_what_the_lazy_table_says(package):
    module = importlib.import_module(package)
    table = {name: where for where, names in module._WHERE.items() for name in names}
    imports = _type_checking_imports(Path(module.__file__))
    # the static view may import a name from the stage's face rather than its private module: same object
    assert set(imports) == set(table), set(imports) ^ set(table)
    for name in table:
        assert getattr(importlib.import_module(imports[name], package), name) is getattr(module, name), name
    assert sorted(set(module.__all__) - {"__version__"}) == sorted(table)


def test_each_name_of_the_package_is_a_public_name_of_its_module():
    for where, names in lagrangian._WHERE.items():
        module = importlib.import_module(where, "lagrangian")
        missing = set(names) - set(module.__all__)
        assert not missing, f"{module.__name__}.__all__ lacks {sorted(missing)}"


@pytest.mark.parametrize("module_name", public_modules())
def test_every_public_name_resolves_and_has_a_docstring(module_name):
    module = importlib.import_module(module_name)
    assert (module.__doc__ or "").strip(), f"{module_name} has no docstring"
    assert len(module.__all__) == len(set(module.__all__)), f"{module_name}.__all__ lists a name twice"
    undocumented = []
    for name in module.__all__:
        value = getattr(module, name)  # AttributeError: a name in __all__ that does not resolve
        if not _has_docstring(module, name, value):
            undocumented.append(name)
    assert not undocumented, f"{module_name}: no docstring for {undocumented}"


def test_top_level_names_resolve_to_their_stage_objects():
    for where, names in lagrangian._WHERE.items():
        module = importlib.import_module(where, "lagrangian")
        for name in names:
            assert getattr(lagrangian, name) is getattr(module, name), name


def test_one_version_string():
    try:
        import tomllib
    except ModuleNotFoundError:  # Python 3.10
        import tomli as tomllib

    from lagrangian._version import __version__

    assert lagrangian.__version__ == __version__
    pyproject = tomllib.loads((SRC.parents[1] / "pyproject.toml").read_text(encoding="utf-8"))
    # written once, in _version.py: the package metadata reads it from there
    assert "version" not in pyproject["project"] and "version" in pyproject["project"]["dynamic"]
    assert pyproject["tool"]["setuptools"]["dynamic"]["version"] == {"attr": "lagrangian._version.__version__"}


@pytest.mark.parametrize("module_name", public_modules())
def test_no_public_name_is_also_a_submodule(module_name):
    # `lagrangian.output.report` the function once hid `lagrangian.output.report` the package: an attribute
    # and a submodule of one name make `import package.name.module` and `package.name` disagree.
    module = importlib.import_module(module_name)
    if not hasattr(module, "__path__"):
        return
    submodules = {info.name for info in pkgutil.iter_modules(module.__path__)}
    assert not submodules & set(module.__all__), sorted(submodules & set(module.__all__))


@pytest.mark.parametrize("module_name", [name for name in public_modules()
                                         if hasattr(importlib.import_module(name), "__path__")])
def test_a_stage_face_re_exports_exactly_its_all(module_name):
    # A face's names are its `X as X` imports (eager, or under TYPE_CHECKING beside a lazy table) and what
    # it star-imports from a module's __all__: the same names as its __all__, neither list ahead.
    module = importlib.import_module(module_name)
    tree = ast.parse(Path(module.__file__).read_text(encoding="utf-8"))
    statements = list(tree.body) + [node for top in tree.body if isinstance(top, ast.If) for node in top.body]
    exported: set[str] = set()
    for node in statements:
        if isinstance(node, ast.ImportFrom):
            source = importlib.util.resolve_name("." * node.level + (node.module or ""), module_name)
            for alias in node.names:
                if alias.name == "*":
                    exported |= set(importlib.import_module(source).__all__)
                elif alias.asname == alias.name:
                    exported.add(alias.name)
    assert exported == set(module.__all__), sorted(exported ^ set(module.__all__))
