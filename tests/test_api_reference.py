"""The API reference (docs/api/, Sphinx with numpydoc) builds from the docstrings with no warning.

Sphinx runs as ``make docs`` does, nitpicky (every reference into the package resolves) with warnings as
errors, on a copy of docs/api/ so that the pages it writes stay out of the checkout.  Every public name,
of the package and of each stage, must then have its entry in the pages.
"""

from __future__ import annotations

import ast
import html
import importlib
import os
import re
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

import lagrangian

ROOT = Path(__file__).resolve().parents[1]

pytest.importorskip("sphinx", reason="the docs extra (sphinx, numpydoc) is not installed")
pytest.importorskip("numpydoc", reason="the docs extra (sphinx, numpydoc) is not installed")


@pytest.fixture(scope="module")
def built(tmp_path_factory) -> Path:
    source = tmp_path_factory.mktemp("api")
    for name in ("conf.py", "index.rst"):
        shutil.copy(ROOT / "docs" / "api" / name, source / name)
    out = source / "_build"
    env = dict(os.environ, PYTHONPATH=os.pathsep.join([str(ROOT / "src"), os.environ.get("PYTHONPATH", "")]))
    run = subprocess.run([sys.executable, "-m", "sphinx", "-b", "html", "-n", "-W", "--keep-going", "-q",
                          "-d", str(source / "_doctrees"), str(source), str(out)],
                         check=False, capture_output=True, text=True, env=env, timeout=300)
    assert run.returncode == 0, f"sphinx-build failed:\n{run.stdout}\n{run.stderr}"
    return out


def _anchors(page: Path) -> set[str]:
    return {html.unescape(m) for m in re.findall(r'<dt class="sig sig-object py" id="([^"]+)"', page.read_text())}


@pytest.mark.slow
@pytest.mark.docs
def test_every_public_name_of_each_stage_has_its_entry(built):
    conf = (ROOT / "docs" / "api" / "conf.py").read_text(encoding="utf-8")
    assert "nitpicky = True" in conf  # what makes a broken reference a warning, and so an error here
    pages = sorted((built / "generated").glob("lagrangian*.html"))
    documented = set().union(*(_anchors(page) for page in pages))
    from test_public_api import public_modules  # the same list of stage modules as the API test

    for module_name in public_modules():
        module = importlib.import_module(module_name)
        missing = {f"{module_name}.{name}" for name in module.__all__} - documented
        assert not missing, f"not in the API reference: {sorted(missing)}"


@pytest.mark.slow
@pytest.mark.docs
def test_the_package_page_links_each_name_of_the_package_to_its_entry(built):
    text = (built / "generated" / "lagrangian.html").read_text()
    for where, names in lagrangian._WHERE.items():
        module = importlib.import_module(where, "lagrangian").__name__
        for name in names:
            # a resolved reference is a link to the entry on its stage's page
            assert f'href="{module}.html#{module}.{name}"' in text, name


def test_numpydoc_checks_every_docstring_but_for_three_sections():
    # every parameter typed and described, Returns, a one-line summary...: numpydoc's "all", so that a check
    # numpydoc adds is on too; only the extended summary, "See Also" and "Examples" are not asked for
    tree = ast.parse((ROOT / "docs" / "api" / "conf.py").read_text(encoding="utf-8"))
    assigned = {target.id: node.value for node in tree.body if isinstance(node, ast.Assign)
                for target in node.targets if isinstance(target, ast.Name)}
    assert ast.literal_eval(assigned["numpydoc_validation_checks"]) == {"all", "ES01", "SA01", "EX01"}
