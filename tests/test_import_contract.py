"""The import contract: how the package's modules may import one another.

Every import in ``src/lagrangian`` is read — at module level, inside functions, under
``TYPE_CHECKING`` or ``try``, and ``importlib.import_module("lagrangian...")`` or ``__import__`` with a
literal name or an f-string (``f"lagrangian.cli._{name}"`` imports from ``lagrangian.cli``), and the
tables of the lazy faces (``_WHERE``, `lagrangian._lazy`) — and checked against three rules:

1. **Imports flow one way along the stages** (`STAGES`): a module imports its own stage or an
   earlier one, never a later one, not even lazily inside a function.  Packages that share a stage
   are independent, except for the edges listed in `PEERS`.  The top-level modules (``errors``,
   ``_atomic``, ``_lazy``, ...) are stage 0: they import nothing but each other.  The package face
   ``lagrangian/__init__.py`` is above every stage: nothing inside the package imports it, but for
   its metadata (``__version__``), which is plain data set by the face, not a stage's API.
2. **No module imports the face of a package it belongs to** (``from . import X`` inside
   ``analysis/``, ``from ..output import X`` inside ``output/_report/``): the face imports its
   modules, so the reverse import is a circle package ↔ module.  Importing a sibling *module*
   (``from . import _sibling``) is an ordinary import and allowed.
3. **Private is private to its package**: a module or name whose path has a component starting
   with ``_`` (``model._vector``, ``model.spec._helper``) may be imported only from inside the
   package that holds it.  Other packages use the package's face (``from ..model import Vector``),
   and only the names of its ``__all__``, or one of its public modules (``lagrangian.model.spec``,
   ``lagrangian.model.vectors``).  A private name of a module is private to the module's package,
   as siblings share helpers; the top-level private modules (``lagrangian._atomic``) are shared by
   the whole package.

`EXCEPTIONS` lists, with the reason, the imports that break a rule by design.  Each entry must
still match an import: a stale entry fails, so the list only shrinks.
"""

from __future__ import annotations

import ast
import functools
from dataclasses import dataclass
from pathlib import Path

SRC = Path(__file__).resolve().parents[1] / "src"
PACKAGE = SRC / "lagrangian"

#: The pipeline's stages, in import order: model file → kinematics → Lagrange's equations →
#: analysis → symbols to code → compiled simulation → what is made of the results → command line.
STAGES = {
    "model": 1,
    "kinematics": 2,
    "dynamics": 3,
    "analysis": 4,
    "codegen": 5,
    "numerics": 6,
    "output": 7, "plotting": 7, "view3d": 7, "optimal": 7, "identification": 7,
    "cli": 8,
}
#: The top-level modules (``lagrangian/errors.py``, ``_atomic.py``, ...): the foundation.
FOUNDATION = 0
#: ``lagrangian/__init__.py``, which re-exports every stage's public names.
FACE = 9

#: The imports allowed between packages of one stage (importer, imported); they form no circle.
PEERS = {
    ("output", "view3d"),  # the report's 3-D stills and the page of a motion
    ("plotting", "view3d"),  # `animate` draws the `Scene` that the 3-D page draws
    ("plotting", "output"),  # figures labelled in the course's notation
}

#: Imports that break a rule by design: (importing module, imported module or module.name): why.  None at
#: present: a value of an early stage that needs a later one's work gets it through the package's face,
#: which stands above every stage (the Jupyter display, `lagrangian._display`), or the work moves down.
EXCEPTIONS: dict[tuple[str, str], str] = {}


@dataclass(frozen=True)
class Import:
    """One imported module or name: ``module`` is resolved to its absolute dotted name."""

    importer: str  # dotted name of the importing module (a package's face: its package name)
    path: Path
    line: int
    module: str  # lagrangian.model._vector
    name: str | None  # Vector, or None for ``import module`` and for submodules

    @property
    def target(self) -> str:
        return self.module + ("." + self.name if self.name else "")


def _module_name(path: Path) -> tuple[str, tuple[str, ...]]:
    """The dotted name of a file and the package that relative imports start from."""
    parts = path.relative_to(SRC).with_suffix("").parts
    if parts[-1] == "__init__":
        return ".".join(parts[:-1]), parts[:-1]
    return ".".join(parts), parts[:-1]


def _is_module(dotted: str) -> bool:
    where = SRC.joinpath(*dotted.split("."))
    return where.with_suffix(".py").is_file() or (where / "__init__.py").is_file()


def _is_package(dotted: str) -> bool:
    return (SRC.joinpath(*dotted.split(".")) / "__init__.py").is_file()


def _called(call: ast.Call) -> str:
    """The name of the function ``call`` calls: ``import_module`` for ``importlib.import_module(...)``."""
    return call.func.attr if isinstance(call.func, ast.Attribute) else getattr(call.func, "id", "")


def _named_module(arg: ast.expr) -> str | None:
    """The module a literal name gives (``"lagrangian.output"``), or that the fixed start of an f-string
    names (``f"lagrangian.cli._{name}"``: ``lagrangian.cli``); None for a name computed otherwise."""
    if isinstance(arg, ast.Constant) and isinstance(arg.value, str):
        return arg.value
    if isinstance(arg, ast.JoinedStr) and arg.values and isinstance(arg.values[0], ast.Constant):
        start = str(arg.values[0].value)
        return start.rpartition(".")[0] or None  # what follows the last dot is cut by the formatted part
    return None


@functools.cache
def all_imports() -> tuple[Import, ...]:
    """Every import of a `lagrangian` module or name in the package, at any depth of the code."""
    found = []
    for path in sorted(PACKAGE.rglob("*.py")):
        importer, package = _module_name(path)
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            if isinstance(node, ast.Import):
                found += [Import(importer, path, node.lineno, a.name, None) for a in node.names
                          if a.name.split(".")[0] == "lagrangian"]
            elif isinstance(node, ast.Call) and _called(node) in ("import_module", "__import__") and node.args:
                # importlib.import_module("lagrangian.output"), __import__(...), or f"lagrangian.output._{x}"
                # (an import of what its fixed part names): an import all the same
                module = _named_module(node.args[0])
                if module is not None and module.split(".")[0] == "lagrangian":
                    found.append(Import(importer, path, node.lineno, module, None))
            elif isinstance(node, ast.ImportFrom):
                module = _absolute(package, node.level, node.module, path, node.lineno)
                if module.split(".")[0] != "lagrangian":
                    continue
                for alias in node.names:
                    if alias.name != "*" and _is_module(f"{module}.{alias.name}"):
                        found.append(Import(importer, path, node.lineno, f"{module}.{alias.name}", None))
                    else:
                        found.append(Import(importer, path, node.lineno, module, alias.name))
            elif (isinstance(node, ast.Assign) and any(getattr(t, "id", "") == "_WHERE" for t in node.targets)
                  and isinstance(node.value, ast.Dict)):
                # a lazy face's table (`lagrangian._lazy`): {"._modes": ("modes", ...)} imports those names
                for key, names in zip(node.value.keys, node.value.values, strict=True):
                    assert isinstance(key, ast.Constant) and isinstance(names, ast.Tuple), f"{path}:{node.lineno}"
                    relative = key.value.lstrip(".")
                    module = _absolute(package, len(key.value) - len(relative), relative or None, path, key.lineno)
                    found += [Import(importer, path, key.lineno, module, n.value) for n in names.elts
                              if isinstance(n, ast.Constant)]
    return tuple(found)


def _absolute(package: tuple[str, ...], level: int, module: str | None, path: Path, line: int) -> str:
    """The absolute name of ``from <level dots><module> import ...`` written in ``package``."""
    if not level:
        return module or ""
    base = package[:len(package) - (level - 1)]
    assert base, f"{path}:{line} imports above the package"
    return ".".join(base) + ("." + module if module else "")


def stage_of(dotted: str) -> tuple[int, str]:
    """The stage of a module and the name of its stage package (``""`` for the foundation)."""
    parts = dotted.split(".")
    if len(parts) == 1:
        return FACE, ""
    if parts[1] in STAGES:
        return STAGES[parts[1]], parts[1]
    assert not _is_package(f"lagrangian.{parts[1]}"), f"lagrangian.{parts[1]} has no stage: add it to STAGES"
    return FOUNDATION, ""


def _dunder(name: str) -> bool:
    return name.startswith("__") and name.endswith("__")


def _within(module: str, package: str) -> bool:
    return module == package or module.startswith(package + ".")


@functools.cache
def _public_names(module: str) -> frozenset[str]:
    """The ``__all__`` of a module, read from its source (importing every face would take seconds).

    A ``*name`` in the list is another module's ``__all__`` imported as ``name`` (``model``'s
    ``*_spec_all``, from ``.spec``).
    """
    where = SRC.joinpath(*module.split("."))
    path = where / "__init__.py" if where.is_dir() else where.with_suffix(".py")
    tree = ast.parse(path.read_text(encoding="utf-8"))
    package = module if path.name == "__init__.py" else module.rsplit(".", 1)[0]
    sources = {a.asname: f"{package}.{n.module}" for n in tree.body if isinstance(n, ast.ImportFrom) and n.level == 1
               for a in n.names if a.name == "__all__" and a.asname}
    names: set[str] = set()
    for node in tree.body:
        value = (node.value if isinstance(node, ast.Assign) and any(getattr(t, "id", "") == "__all__" for t in node.targets)
                 else node.value if isinstance(node, ast.AugAssign) and getattr(node.target, "id", "") == "__all__"
                 else None)
        for element in getattr(value, "elts", ()):
            if isinstance(element, ast.Constant):
                names.add(element.value)
            elif isinstance(element, ast.Starred) and isinstance(element.value, ast.Name):
                names |= _public_names(sources[element.value.id])
    return frozenset(names)


def violations(imp: Import) -> list[str]:
    """What ``imp`` breaks in the contract, as sentences (none when it keeps to it)."""
    found = []
    stage, package = stage_of(imp.importer)
    face_import = imp.name is not None and _is_package(imp.module)
    if imp.module == "lagrangian" and imp.name is not None:
        target_stage, target_package = (FOUNDATION if _dunder(imp.name) else FACE), ""
    else:
        target_stage, target_package = stage_of(imp.module)
    if target_stage > stage:
        found.append(f"imports {imp.target}, of a later stage ({target_stage} > {stage})")
    elif (target_stage == stage and package != target_package and stage != FOUNDATION
          and (package, target_package) not in PEERS):
        found.append(f"imports {imp.target}: {package} and {target_package} share stage {stage} "
                     "with no declared edge (PEERS)")
    if face_import and _within(imp.importer, imp.module) and not _dunder(imp.name or ""):
        found.append(f"imports {imp.name} from the face of its own package {imp.module}: an import circle")
    if (face_import and not _within(imp.importer, imp.module) and not _dunder(imp.name or "")
            and not (imp.name or "").startswith("_") and imp.name not in _public_names(imp.module)):
        found.append(f"imports {imp.target}, which {imp.module} does not list in its __all__")
    parts = imp.target.split(".")
    private = next((k for k, p in enumerate(parts) if p.startswith("_") and not p.startswith("__")), None)
    if private is not None:
        scope = ".".join(parts[:private])
        if not _is_package(scope):  # a private name of a module: private to the module's package
            scope = scope.rsplit(".", 1)[0]
        if not _within(imp.importer, scope):
            found.append(f"imports {imp.target}, private to {scope}")
    return found


@functools.cache
def _broken() -> dict[tuple[str, str], list[str]]:
    broken: dict[tuple[str, str], list[str]] = {}
    for imp in all_imports():
        for why in violations(imp):
            broken.setdefault((imp.importer, imp.target), []).append(
                f"{imp.path.relative_to(SRC)}:{imp.line}: {why}")
    return broken


def test_every_import_names_a_module_that_exists() -> None:
    # Also the imports inside functions, which run only on some paths (a report with a given
    # constraint): after modules move, a stale `..model._x` would fail only there.
    missing = [f"{imp.path.relative_to(SRC)}:{imp.line}: no module {imp.module}" for imp in all_imports()
               if not _is_module(imp.module)]
    assert not missing, "\n".join(missing)


def test_every_stage_package_is_known() -> None:
    packages = {p.parent.name for p in PACKAGE.glob("*/__init__.py")}
    assert packages <= set(STAGES), f"packages without a stage: {sorted(packages - set(STAGES))}"


def test_peers_form_no_circle() -> None:
    assert all(STAGES[a] == STAGES[b] for a, b in PEERS)
    reach = {a: {b for x, b in PEERS if x == a} for a, _ in PEERS}
    for _ in PEERS:  # the transitive closure, one step per edge at most
        reach = {a: bs | {c for b in bs for c in reach.get(b, ())} for a, bs in reach.items()}
    assert not [a for a, bs in reach.items() if a in bs], reach


def test_imports_keep_to_the_contract() -> None:
    broken = _broken()
    unexpected = [line for key, lines in sorted(broken.items()) if key not in EXCEPTIONS for line in lines]
    assert not unexpected, f"{len(unexpected)} imports break the contract:\n" + "\n".join(unexpected)


def test_exceptions_still_break_a_rule() -> None:
    # An entry whose import is gone (or now allowed) is removed, so the list only shrinks.
    stale = sorted(set(EXCEPTIONS) - set(_broken()))
    assert not stale, f"entries that no longer match a forbidden import: {stale}"


def test_package_docstrings_number_the_stages_as_the_contract() -> None:
    for name, stage in STAGES.items():
        face = PACKAGE / name / "__init__.py"
        if face.is_file():
            doc = ast.get_docstring(ast.parse(face.read_text(encoding="utf-8"))) or ""
            assert doc.startswith(f"Stage {stage} — "), f"{face}: {doc.splitlines()[0] if doc else doc!r}"


# -- the checker itself, on hand-written imports -------------------------------------------------

def _imp(importer: str, module: str, name: str | None = None) -> Import:
    return Import(importer, PACKAGE / "x.py", 1, module, name)


def test_the_checker_finds_each_kind_of_break() -> None:
    assert violations(_imp("lagrangian.dynamics._lagrange", "lagrangian.output._display", "equations_latex"))
    assert any("stage 7" in v for v in violations(_imp("lagrangian.optimal._solve", "lagrangian.identification")))
    assert any("circle" in v for v in violations(_imp("lagrangian.analysis._modes", "lagrangian.analysis", "modes")))
    assert any("circle" in v for v in violations(_imp("lagrangian.output._report.build", "lagrangian.output",
                                                      "Notation")))
    assert any("private to lagrangian.model" in v
               for v in violations(_imp("lagrangian.dynamics._energy", "lagrangian.model._frames")))
    assert any("private to lagrangian.model" in v
               for v in violations(_imp("lagrangian.dynamics._energy", "lagrangian.model.spec", "_check")))
    assert any("__all__" in v for v in violations(_imp("lagrangian.analysis._modes", "lagrangian.dynamics", "se")))
    assert any("later stage" in v for v in violations(_imp("lagrangian.errors", "lagrangian.model")))
    assert any("later stage" in v for v in violations(_imp("lagrangian.cli.main", "lagrangian", "derive")))


def test_the_reader_sees_imports_made_by_name() -> None:
    tree = ast.parse('import_module("lagrangian.output")\n__import__("lagrangian.numerics")\n'
                     'importlib.import_module(f"lagrangian.view3d._{name}")\nimport_module(f"{name}.x")\n')
    calls = [node for node in ast.walk(tree) if isinstance(node, ast.Call)]
    assert [_named_module(c.args[0]) for c in calls if _called(c) in ("import_module", "__import__")] == [
        "lagrangian.output", "lagrangian.numerics", "lagrangian.view3d", None]
    face = PACKAGE / "analysis" / "__init__.py"
    table = next(node for node in ast.parse(face.read_text(encoding="utf-8")).body
                 if isinstance(node, ast.Assign) and getattr(node.targets[0], "id", "") == "_WHERE")
    lazy = {imp.target for imp in all_imports()
            if imp.importer == "lagrangian.analysis" and table.lineno <= imp.line <= (table.end_lineno or 0)}
    assert {"lagrangian.analysis._modes.modes", "lagrangian.errors.AnalysisError"} <= lazy  # its `_WHERE` table
    cli = [imp for imp in all_imports() if imp.importer == "lagrangian.cli._arguments.common"]
    assert any(imp.module == "lagrangian.cli" for imp in cli)  # importlib.import_module(f"lagrangian.cli._{name}")


def test_the_checker_allows_what_the_contract_allows() -> None:
    assert not violations(_imp("lagrangian.dynamics._energy", "lagrangian.model", "Vector"))
    assert not violations(_imp("lagrangian.dynamics._energy", "lagrangian.model.spec", "Body"))
    assert not violations(_imp("lagrangian.model._toml", "lagrangian.model._expr", "_helper"))
    assert not violations(_imp("lagrangian.analysis._modes", "lagrangian.analysis._linear_model"))  # a sibling
    assert not violations(_imp("lagrangian.numerics._files", "lagrangian._atomic", "write_atomic"))
    assert not violations(_imp("lagrangian.plotting._apex", "lagrangian.view3d", "Scene"))
    assert not violations(_imp("lagrangian.cli.main", "lagrangian", "__version__"))
