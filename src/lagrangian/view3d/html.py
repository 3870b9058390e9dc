"""The 3-D view as HTML: one page, or a fragment of the report, with three.js and the viewer inline.

three.js is vendored (``vendor/``, version `THREE_VERSION` from the npm registry, MIT licence in
``vendor/LICENSE-three.txt``): its module build and the OrbitControls add-on, made into one
classic script here — the module's single closing ``export { a as B, ... }`` becomes the
object the wrapping function returns, and the add-on's ``import { ... } from 'three'`` reads
that object — so the page needs no module loader, no import map and no network: an inline
script runs the same in a file, in a report and in a notebook's iframe.

The scene is a ``<script type="application/json">`` whose ``<``, ``>`` and ``&`` are written as
``\\u003c``... (so no text in a name can close the element), and every name reaches the page
through ``textContent``.  A Content-Security-Policy forbids any request but inline code, inline
styles and ``data:``/``blob:`` images.
"""

from __future__ import annotations

import functools
import html
import json
import re
from importlib import resources

from ._scene import Scene

__all__ = ["CSP", "THREE_VERSION", "fragment", "library", "page", "scene_json"]

#: The vendored three.js release (npm ``three@0.170.0``, r170).
THREE_VERSION = "0.170.0"
#: What a page of the view may load: nothing from anywhere, but its inline script, styles and images.
CSP = ("default-src 'none'; script-src 'unsafe-inline'; style-src 'unsafe-inline'; img-src data: blob:; "
       "connect-src 'none'; base-uri 'none'; form-action 'none'")

def _read(name: str) -> str:
    return resources.files("lagrangian.view3d").joinpath(name).read_text(encoding="utf-8")


def _exports_as_object(source: str, what: str) -> tuple[str, str]:
    """(code without its final ``export { ... }``, the JavaScript object literal of those exports)."""
    m = re.search(r"export\s*\{([^}]*)\}\s*;?\s*$", source)
    if m is None:
        raise RuntimeError(f"{what}: no closing export clause")  # pragma: no cover - the vendored files have one
    items = []
    for item in m.group(1).split(","):
        words = item.split()
        if not words:
            continue
        local, exported = (words[0], words[2]) if len(words) == 3 and words[1] == "as" else (words[0], words[0])
        items.append(f"{exported}: {local}")
    return source[: m.start()], "{" + ", ".join(items) + "}"


@functools.cache
def library() -> str:
    """three.js, OrbitControls and the viewer as one classic script (defines ``THREE``, ``OrbitControls``,
    ``LagrangianView``)."""
    three, exports = _exports_as_object(_read("vendor/three.module.min.js"), "three.js")
    if re.search(r"\bimport\s*(\{[^}]*\}|\*\s*as\s+[\w$]+|[\w$]+)\s*from\s*['\"]", three) or "import.meta" in three:
        raise RuntimeError("three.js: the module build imports something")  # pragma: no cover
    controls = _read("vendor/OrbitControls.js")
    imported = re.match(r"\s*import\s*\{([^}]*)\}\s*from\s*['\"]three['\"]\s*;", controls)
    if imported is None:
        raise RuntimeError("OrbitControls.js: no import from 'three'")  # pragma: no cover
    names = ", ".join(n.strip() for n in imported.group(1).split(",") if n.strip())
    body, controls_exports = _exports_as_object(controls[imported.end():], "OrbitControls")
    license_ = _read("vendor/LICENSE-three.txt").strip().replace("*/", "* /")
    return "\n".join([
        f"/* three.js r{THREE_VERSION.split('.')[1]} ({THREE_VERSION}), https://threejs.org\n{license_}\n*/",
        f'var THREE = (function () {{ "use strict";\n{three}\nreturn {exports};\n}})();',
        (f'var OrbitControls = (function () {{ "use strict";\nconst {{ {names} }} = THREE;\n{body}\n'
         f"return {controls_exports}.OrbitControls;\n}})();"),
        _read("viewer.js"),
    ])


def scene_json(scene: Scene) -> str:
    """The scene document as JSON safe inside ``<script type="application/json">`` (no ``<``, ``>``, ``&``)."""
    text = json.dumps(scene.document, ensure_ascii=False, separators=(",", ":"), allow_nan=False)
    return (text.replace("<", "\\u003c").replace(">", "\\u003e").replace("&", "\\u0026")
            .replace("\u2028", "\\u2028").replace("\u2029", "\\u2029"))


def fragment(scene: Scene, *, ident: str = "lgv-1", height: str = "480px", caption: str = "") -> str:
    """A ``<figure>`` holding the view of ``scene``, its element named ``ident`` (one per page); the page
    must hold `library` once (before or after)."""
    cap = f"<figcaption>{html.escape(caption)}</figcaption>" if caption else ""
    return (f'<figure class="lgv-figure"><div id="{ident}" style="height: {height}"></div>{cap}</figure>\n'
            f'<script type="application/json" id="{ident}-data">{scene_json(scene)}</script>\n'
            f'<script>window.addEventListener("DOMContentLoaded", function () {{ LagrangianView.mount('
            f'document.getElementById("{ident}"), JSON.parse(document.getElementById("{ident}-data").textContent)); '
            f"}});</script>")


def page(scene: Scene) -> str:
    """A whole page showing ``scene`` and nothing else, filling the window."""
    lang = html.escape(scene.lang, quote=True)
    return (f'<!DOCTYPE html>\n<html lang="{lang}">\n<head>\n<meta charset="utf-8">\n'
            f'<meta http-equiv="Content-Security-Policy" content="{CSP}">\n'
            '<meta name="viewport" content="width=device-width, initial-scale=1">\n'
            f"<title>{html.escape(scene.title)}</title>\n"
            "<style>html, body { margin: 0; height: 100%; } body > figure { margin: 0; height: 100%; }</style>\n"
            "</head>\n<body>\n"
            f"{fragment(scene, height='100%')}\n"
            f"<script>\n{library()}\n</script>\n</body>\n</html>\n")
