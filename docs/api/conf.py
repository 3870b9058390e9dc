"""Sphinx configuration of the API reference, built from the docstrings (``make docs``).

The pages are written here, before Sphinx reads its sources, from the package's own lists: one page
for the package (`lagrangian.__all__`, its table `lagrangian._WHERE`) and one per stage module with
its ``__all__`` (each object documented once, where its stage exports it).  A name added to an
``__all__`` is in the reference at the next build; nothing here lists names by hand.
"""

from __future__ import annotations

import importlib
import inspect
import pkgutil
import re
import sys
import warnings
from pathlib import Path

from docutils import nodes
from sphinx.addnodes import pending_xref
from sphinx.application import Sphinx
from sphinx.environment import BuildEnvironment
from sphinx.util import logging

HERE = Path(__file__).resolve().parent
if (HERE.parents[1] / "src" / "lagrangian").is_dir():  # the checkout's package, installed or not
    sys.path.insert(0, str(HERE.parents[1] / "src"))

lagrangian = importlib.import_module("lagrangian")  # after the path is set: the checkout's own

project = "lagrangian"
author = "the lagrangian authors"
copyright = "the lagrangian authors"
release = version = lagrangian.__version__

extensions = ["sphinx.ext.autodoc", "sphinx.ext.autosummary", "numpydoc"]
root_doc = "index"
exclude_patterns = ["_build"]
html_theme = "alabaster"
html_static_path: list[str] = []

# Every cross-reference must resolve (sphinx-build -n): references into the package are checked;
# those to other libraries' types (NumPy, SymPy, SymEngine, the standard library) would need their
# inventories from the network, which a build here does not reach, so they are left as text.
nitpicky = True
nitpick_ignore_regex = [(r"py:.*", r"(?!lagrangian\b).*")]

autodoc_default_options = {"member-order": "bysource"}
autodoc_typehints = "signature"
autodoc_preserve_defaults = True
autosummary_generate = False  # the pages are written below, one per stage, not one per object
numpydoc_show_class_members = False  # members are documented by autodoc's :members:, on the same page
numpydoc_class_members_toctree = False
numpydoc_xref_param_type = False
# numpydoc's checks, each a build error: every check of its validator ("all") but three, which ask for
# sections these docstrings do not have:
#   ES01 (no extended summary): the one-line summary of a small function says it all; more would repeat it.
#   SA01 (no "See Also"): related names are cross-referenced in the sentences that say how they relate.
#   EX01 (no "Examples"): examples are doctests (`pytest src --doctest-modules`) where they teach, the entry
#        points (`ModelBuilder`, `verify`, `export`...), and in docs/*.md; 450 docstrings have none yet.
# So every parameter is documented (PR01) as "name : type" with a description of its own, a capital first
# and a period last (PR02-PR10), a function that returns has a Returns section that says what (RT01-RT05),
# the summary is one line, a capital first and a period last (SS01-SS06), and the structure holds (GL01-GL10,
# YD01, SA02-SA04).  A dataclass documents its fields as its Parameters (they are its constructor's).
numpydoc_validation_checks = {"all", "ES01", "SA01", "EX01"}


def stage_modules() -> list[str]:
    """The modules whose ``__all__`` is public API: each stage's face, and the modules the package's table names."""
    stages = [f"lagrangian.{info.name}" for info in pkgutil.iter_modules(lagrangian.__path__)
              if not info.name.startswith("_") and info.name != "cli"]  # the command line is no library API
    named = [importlib.import_module(where, "lagrangian").__name__ for where in lagrangian._WHERE]
    return sorted(set(stages) | set(named))


def _directive(module: str, name: str) -> str:
    value = getattr(importlib.import_module(module), name)
    if inspect.isclass(value) and issubclass(value, BaseException):
        return f".. autoexception:: {name}\n   :members:\n"
    if inspect.isclass(value):
        return f".. autoclass:: {name}\n   :members:\n"
    if inspect.isroutine(value):
        return f".. autofunction:: {name}\n"
    return f".. autodata:: {name}\n   :no-value:\n"


def _title(text: str) -> str:
    return f"{text}\n{'=' * len(text)}\n"


def stage_page(module: str) -> str:
    names = importlib.import_module(module).__all__
    parts = [_title(f"``{module}``"), f".. automodule:: {module}\n   :no-members:\n",
             f".. currentmodule:: {module}\n", ".. autosummary::\n", *(f"   {name}" for name in names), ""]
    parts += [_directive(module, name) for name in names]
    return "\n".join(parts)


def package_page() -> str:
    parts = [_title("``lagrangian``"), ".. automodule:: lagrangian\n   :no-members:\n",
             "The names of the package, each documented with its stage:\n"]
    for where, names in lagrangian._WHERE.items():
        module = importlib.import_module(where, "lagrangian").__name__
        parts.append(f"* :doc:`{module}`: " + ", ".join(
            f":py:obj:`lagrangian.{name} <{module}.{name}>`" for name in names))
    parts.append(f"\n``__version__``: the package's version (``{lagrangian.__version__}``).\n")
    return "\n".join(parts)


def write_pages(directory: Path) -> list[str]:
    """Write the package's page and the stages' pages into ``directory``; their names, in the toctree's order."""
    directory.mkdir(exist_ok=True)
    pages = {"lagrangian": package_page()} | {module: stage_page(module) for module in stage_modules()}
    for old in directory.glob("*.rst"):
        if old.stem not in pages:
            old.unlink()
    for name, text in pages.items():
        path = directory / f"{name}.rst"
        if not path.exists() or path.read_text(encoding="utf-8") != text:  # unchanged pages stay unread
            path.write_text(text, encoding="utf-8")
    return list(pages)


PAGES = write_pages(HERE / "generated")

#: Every documented object, by its documented name (``lagrangian.numerics.Trajectory``).
DOCUMENTED = {f"{module}.{name}": getattr(importlib.import_module(module), name)
              for module in stage_modules() for name in importlib.import_module(module).__all__}

# A constant (``MAX_OPS``, ``GALILEAN_FRAME``, a type alias such as ``Load``) is documented by its ``#:``
# comment, which tests/test_public_api.py requires; numpydoc would check the docstring of its value's type
# instead (str's, int's, UnionType's), so the constants are left out of numpydoc's checks.
numpydoc_validation_exclude = {rf"^{re.escape(name)}$" for name, value in DOCUMENTED.items()
                               if not (inspect.isclass(value) or inspect.isroutine(value))}


def _lookup(target: str) -> object | None:
    """The object that the dotted name ``target`` names, or None when it names nothing."""
    module, _, name = target.rpartition(".")
    try:
        return getattr(importlib.import_module(module), name, None)
    except (ImportError, ValueError):
        return None if "." not in module else getattr(_lookup(module), name, None)


def _public_name(target: str) -> str | None:
    """The documented name of what ``target`` names through a private path, or None.

    An annotation names a type where it is defined or imported: ``lagrangian.analysis._reactions.Trajectory``
    (imported there for type checking only) is documented as ``lagrangian.numerics.Trajectory``.  The type is
    the object at ``target`` when that imports, else the one documented object of the same last name.
    """
    name = target.rpartition(".")[2]
    found = _lookup(target)
    same = [full for full, value in DOCUMENTED.items() if full.rpartition(".")[2] == name
            and (found is None or value is found)]
    return same[0] if len(same) == 1 else None


def _resolve_private(app: Sphinx, env: BuildEnvironment, node: pending_xref,
                     contnode: nodes.TextElement) -> nodes.reference | None:
    """Sphinx's ``missing-reference``: a reference into the package that names no entry of the reference.

    A public object named through its module's path (``lagrangian.analysis._reactions.Trajectory``) links
    to its entry; a type that exists but that no stage exports (``lagrangian.analysis._top.Nutation``,
    ``lagrangian.codegen.targets.base.ExportedRow``) is shown as text; a name that names nothing
    (``lagrangian.numerics.Trajectry``) is left to Sphinx, which warns: an error in ``make docs``.
    """
    target = node.get("reftarget", "")
    if node.get("refdomain") != "py" or not target.startswith("lagrangian."):
        return None
    public = _public_name(target)
    if public is not None and public != target:
        return env.domains["py"].resolve_xref(env, node["refdoc"], app.builder, node["reftype"], public, node,
                                              contnode)
    return contnode if _lookup(target) is not None else None


# A private module's name that does not import at run time (imported there for type checking only) and
# names no documented object: shown as text too.
nitpick_ignore_regex.append((r"py:.*", r"lagrangian(\.\w+)*\._\w+(\.\w+)*"))


# numpydoc reports a docstring it cannot read (an unknown section, a bad "See Also" entry) with Python's
# `warnings`, which ``sphinx-build -W`` does not see: they are passed on as Sphinx warnings, each time.
_LOG = logging.getLogger("numpydoc")
_show_warning = warnings.showwarning
warnings.filterwarnings("always", category=UserWarning, module=r"numpydoc\b")


def _numpydoc_warning(message: Warning | str, category: type[Warning], filename: str, lineno: int,
                      file: object = None, line: str | None = None) -> None:
    if "numpydoc" in Path(filename).parts or "docscrape" in filename:
        _LOG.warning("numpydoc: %s", message)
    else:
        _show_warning(message, category, filename, lineno, file, line)  # type: ignore[arg-type]


warnings.showwarning = _numpydoc_warning


def setup(app: Sphinx) -> None:
    app.connect("missing-reference", _resolve_private)
