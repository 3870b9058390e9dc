"""The HTML report in a real browser: headless Chromium (Debian's ``chromium``; ``make test`` installs it).

Checked: the page loads with no console message and no failed resource, every equation
is laid out as MathML (the browser's ``display: math`` or ``block math``, a box of
nonzero size), no LaTeX is left in the visible text, every image decodes, and a screenshot
is taken.  Skipped, with the reason, where no Chromium can be found.
"""

from __future__ import annotations

import json
import os
import re
import shutil
import subprocess
from pathlib import Path

import numpy as np
import pytest
from lagrangian_test_support import EXAMPLES_DIR

import lagrangian
from lagrangian.model.zoo import planar_chain
from lagrangian.output import ReportFigure, report
from lagrangian.output._report.document import math_of

CHROMIUM = next((p for p in map(shutil.which, ("chromium", "chromium-browser", "google-chrome", "chrome")) if p), None)
pytestmark = [pytest.mark.browser, pytest.mark.skipif(
    CHROMIUM is None, reason="no headless Chromium on this machine (`make test` installs Debian's chromium as root)")]

#: Seconds Chromium may take to load and lay out a page (a cold start on a busy machine).
BROWSER_SECONDS = 120

# Run after the page has loaded: open every <details>, then measure every <math> and image.
_PROBE = """
<script>
window.__errors = [];
window.addEventListener('error', e => window.__errors.push(String(e.message || (e.target && e.target.outerHTML))), true);
window.addEventListener('load', () => {
  document.querySelectorAll('details').forEach(d => { d.open = true; });
  const maths = Array.from(document.querySelectorAll('math'));
  const bad = maths.filter(m => {
    const r = m.getBoundingClientRect();
    const display = getComputedStyle(m).display;
    return !['math', 'inline math', 'block math'].includes(display) || r.width <= 0 || r.height <= 0;
  }).map(m => m.outerHTML.slice(0, 200));
  const images = Array.from(document.images).map(i => i.complete && i.naturalWidth > 0);
  const box = e => e.getBoundingClientRect();
  const where = e => (e.closest('math') || e).outerHTML.slice(0, 300);
  // A labelled arrow (R0 -psi-> R1): the label above the arrow, neither over the frames on either
  // side (the arrow keeps its length, as \\overset{label}{\\longrightarrow} does in LaTeX).
  const arrows = [];
  document.querySelectorAll('mover').forEach(m => {
    const [base, over] = m.children;
    if (!base || !over) return;
    if (base.tagName === 'mo' && /[\u2190-\u21ff\u27f5-\u27ff]/.test(base.textContent)) {
      const a = box(base), l = box(over), r = box(m);
      const next = m.nextElementSibling, prev = m.previousElementSibling;
      if (l.bottom > a.top + 0.5 * a.height) arrows.push(['label over the arrow', l.bottom, a.top, where(m)]);
      if (next && box(next).left < r.right - 1) arrows.push(['overlaps the next', r.right, box(next).left, where(m)]);
      if (prev && box(prev).right > r.left + 1) arrows.push(['overlaps the previous', box(prev).right, r.left, where(m)]);
    }
    // An arrow over several letters (the vector OG) is drawn by the style sheet across them (class vec;
    // test_two_letter_vectors_carry_an_arrow_with_its_head measures it); any other spans them.
    if (over.tagName === 'mo' && base.children.length > 1
        && !(m.classList.contains('vec') && getComputedStyle(m).backgroundImage.includes('svg'))
        && box(over).width < 0.9 * box(base).width)
      arrows.push(['short arrow over', box(over).width, box(base).width, where(m)]);
  });
  // Brackets around a matrix (the inertia matrix) as tall as it.
  const fences = [];
  document.querySelectorAll('mtable').forEach(t => {
    const open = t.previousElementSibling, close = t.nextElementSibling;
    [open, close].forEach(f => {
      if (f && f.tagName === 'mo' && box(f).height < 0.9 * box(t).height)
        fences.push([f.textContent, box(f).height, box(t).height, where(t)]);
    });
  });
  // sin θ set apart by a thin space (LaTeX's \\sin), S/R0 with no space around the solidus.
  const spacing = [];
  const fontPx = e => parseFloat(getComputedStyle(e).fontSize);
  document.querySelectorAll('mi').forEach(f => {
    if (!/^(sin|cos|tan)$/.test(f.textContent)) return;
    const name = f.parentElement.tagName === 'msup' && f === f.parentElement.children[0] ? f.parentElement : f;
    let next = name.nextElementSibling;
    while (next && next.tagName === 'mspace') next = next.nextElementSibling;
    if (!next || next.tagName === 'mo' || (next.firstElementChild && next.firstElementChild.tagName === 'mo')
        || (next.firstElementChild && next.firstElementChild.firstElementChild
            && next.firstElementChild.firstElementChild.tagName === 'mo')) return;
    const gap = box(next).left - box(name).right;
    if (gap < 0.1 * fontPx(f)) spacing.push(['sin θ touching', gap, where(f)]);
  });
  document.querySelectorAll('mo').forEach(o => {
    if (o.textContent !== '/') return;
    const prev = o.previousElementSibling, next = o.nextElementSibling;
    if (prev && box(o).left - box(prev).right > 0.08 * fontPx(o)) spacing.push(['space before /', box(o).left - box(prev).right, where(o)]);
    if (next && box(next).left - box(o).right > 0.08 * fontPx(o)) spacing.push(['space after /', box(next).left - box(o).right, where(o)]);
  });
  // The table of contents: each entry's box and list marker (the titles carry their own numbers).
  const toc = Array.from(document.querySelectorAll('nav li')).map(li => {
    const r = box(li);
    return [r.left, r.top, r.right, r.bottom, getComputedStyle(li).listStyleType, li.textContent];
  });
  const probe = document.createElement('pre');
  probe.id = 'probe';
  probe.textContent = JSON.stringify({errors: window.__errors, maths: maths.length, bad: bad, images: images,
                                      arrows: arrows, fences: fences, toc: toc, spacing: spacing,
                                      text: document.body.innerText});
  document.body.appendChild(probe);
});
</script>
"""


def _chromium(tmp_path: Path, *args: str) -> subprocess.CompletedProcess:
    profile = tmp_path / "chromium-profile"
    # WebGL (the statement's 3-D figure) on SwiftShader, Chromium's software renderer, asked for by name.
    command = [CHROMIUM, "--headless", "--no-sandbox", "--disable-gpu", "--enable-unsafe-swiftshader",
               "--disable-background-networking",
               "--disable-component-update", "--disable-sync", "--no-first-run", "--hide-scrollbars",
               f"--user-data-dir={profile}", "--enable-logging=stderr", "--v=0", *args]
    return subprocess.run(command, capture_output=True, text=True, timeout=BROWSER_SECONDS)  # type: ignore[arg-type]


#: What the software renderer logs on every frame it composites: a performance note of the GL driver (ANGLE on
#: SwiftShader reads the WebGL canvas back), not a message of the page.
_DRIVER_NOTE = "GL Driver Message (OpenGL, Performance"


def _console(stderr: str) -> list[str]:
    return [line for line in stderr.splitlines() if ":CONSOLE" in line and _DRIVER_NOTE not in line]


def _check_page(html: str, expected_math: int, tmp_path: Path, images: int = 0) -> dict:
    page = tmp_path / "report.html"
    page.write_text(html, encoding="utf-8")
    # The page with a probe script added at its end (the script itself logs nothing): the page must load
    # with no console message and no failed resource, every equation laid out as MathML, no LaTeX left.
    probed = tmp_path / "probed.html"
    probed.write_text(html.replace("</body>", _PROBE + "</body>"), encoding="utf-8")
    run = _chromium(tmp_path, "--virtual-time-budget=10000", "--window-size=1200,2000", "--dump-dom", probed.as_uri())
    assert run.returncode == 0, run.stderr[-2000:]
    assert _console(run.stderr) == [], _console(run.stderr)
    found = re.search(r'<pre id="probe">(.*?)</pre>', run.stdout, re.S)
    assert found, run.stdout[-2000:]
    result = json.loads(found.group(1).replace("&lt;", "<").replace("&gt;", ">").replace("&quot;", '"')
                        .replace("&amp;", "&"))
    assert result["errors"] == []
    assert result["maths"] == expected_math
    assert result["bad"] == []
    assert result["images"] == [True] * images
    assert result["arrows"] == [], result["arrows"][:5]
    assert result["fences"] == [], result["fences"][:5]
    assert result["spacing"] == [], result["spacing"][:5]
    # The table of contents at 1200 px: numbered once (no list numbers before "1. Choix …"), no entry over another.
    toc = result["toc"]
    assert toc and all(style == "none" for *_, style, _ in toc), toc[:3]
    for k, (l1, t1, r1, b1, *_rest) in enumerate(toc):
        for l2, t2, r2, b2, *_ in toc[k + 1:]:
            assert min(r1, r2) - max(l1, l2) <= 0.5 or min(b1, b2) - max(t1, t2) <= 0.5, (toc[k], (l2, t2, r2, b2))
    # latex2mathml's \xrightarrow: an <mpadded> pulled up over the arrow (negative height / offset).
    assert not re.search(r'<mpadded[^>]*="-', html)
    for raw in (r"\frac", r"\dot", r"\vec", r"\left", r"\text", "$", "^{", "_{"):
        assert raw not in result["text"], raw
    return result


def _screenshot(html_path: Path, tmp_path: Path) -> Path:
    """A screenshot of the page, kept in ``tmp_path`` (pytest keeps the last runs' folders) and copied to
    ``$LAGRANGIAN_TEST_ARTIFACTS`` when set, for a person to look at."""
    shot = tmp_path / "report.png"
    run = _chromium(tmp_path, "--window-size=1100,3000", f"--screenshot={shot}", html_path.as_uri())
    assert run.returncode == 0, run.stderr[-2000:]
    assert shot.read_bytes().startswith(b"\x89PNG\r\n\x1a\n") and shot.stat().st_size > 10_000
    import matplotlib.image

    pixels = matplotlib.image.imread(shot)
    assert pixels.std() > 0.01  # not a blank page
    artifacts = os.environ.get("LAGRANGIAN_TEST_ARTIFACTS")
    if artifacts:
        Path(artifacts).mkdir(parents=True, exist_ok=True)
        shutil.copy(shot, Path(artifacts) / f"{html_path.stem}-{tmp_path.name}.png")
    return shot


def _math_count(r) -> int:
    return sum(len(math_of(s.blocks)) for s in r.document.sections)


def test_top_in_french_renders_in_a_browser(tmp_path):
    from io import BytesIO

    import matplotlib.figure

    fig = matplotlib.figure.Figure(figsize=(3, 2))
    fig.add_subplot().plot(np.sin(np.linspace(0, 6, 50)))
    buffer = BytesIO()
    fig.savefig(buffer, format="png")
    r = report(lagrangian.lagrange_top(), lang="fr", verification=True,
               figures=[ReportFigure(buffer.getvalue(), "θ(t)")])
    result = _check_page(r.html(), _math_count(r), tmp_path, images=1)
    assert "Équations de Lagrange" in result["text"] and "angles d\u2019Euler" in result["text"]
    _screenshot(tmp_path / "report.html", tmp_path)


@pytest.mark.parametrize("name", ["double_pendulum.toml", "pendulum_tension.toml"])
def test_other_models_render_in_a_browser(name, tmp_path):
    r = report(EXAMPLES_DIR / name, lang="en", verification=True)
    _check_page(r.html(), _math_count(r), tmp_path)


def test_a_40_link_chain_renders_in_a_browser(tmp_path):
    r = report(lagrangian.derive(planar_chain(40)), lang="fr")
    _check_page(r.html(), _math_count(r), tmp_path)


_OVERFLOW = """
<script>
window.addEventListener('load', () => {
  document.querySelectorAll('details').forEach(d => { d.open = true; });
  const forms = Array.from(document.querySelectorAll('.full-form .display'));
  const wide = forms.filter(e => e.scrollWidth > e.clientWidth + 1).map(e => [e.scrollWidth, e.clientWidth]);
  const probe = document.createElement('pre');
  probe.id = 'probe';
  probe.textContent = JSON.stringify({forms: forms.length, wide: wide});
  document.body.appendChild(probe);
});
</script>
"""


def test_full_forms_fit_the_page_without_scrolling(tmp_path):
    """The full forms of a 6-link chain's L(θ_i), unfolded, are cut into lines that fit the page's width."""
    r = report(lagrangian.derive(planar_chain(6)), lang="fr")
    page = tmp_path / "forms.html"
    page.write_text(r.html().replace("</body>", _OVERFLOW + "</body>"), encoding="utf-8")
    run = _chromium(tmp_path, "--window-size=1100,2000", "--virtual-time-budget=10000", "--dump-dom", page.as_uri())
    assert run.returncode == 0, run.stderr[-2000:]
    found = re.search(r'<pre id="probe">(.*?)</pre>', run.stdout, re.S)
    assert found, run.stdout[-2000:]
    result = json.loads(found.group(1).replace("&quot;", '"'))
    assert result["forms"] >= 12 and result["wide"] == []


_VECTORS = (r"\overrightarrow{OG}", r"\overrightarrow{O_{1}G_{2}}", r"\overrightarrow{OO'}", r"\overrightarrow{AB} = \vec{x}")

# The boxes of each vector's arrow-and-letters (mover) and of its letters (the base), in CSS pixels.
_VECTOR_BOXES = """
<script>
window.addEventListener('load', () => {
  const box = e => { const r = e.getBoundingClientRect(); return [r.left, r.top, r.right, r.bottom]; };
  const vectors = Array.from(document.querySelectorAll('mover')).filter(m => m.children[0].children.length > 1)
    .map(m => [box(m), box(m.children[0]), getComputedStyle(m).transform, getComputedStyle(m.children[1]).transform]);
  const probe = document.createElement('pre');
  probe.id = 'probe';
  probe.textContent = JSON.stringify(vectors);
  document.body.appendChild(probe);
});
</script>
"""


def test_two_letter_vectors_carry_an_arrow_with_its_head(tmp_path):
    """OG is drawn as a vector, not as OG with a bar (a mesure algébrique in French notation): on a
    screenshot, the mark above the letters spans both of them and ends in a head at the right, several
    times as tall as the line; and no CSS transform is used to widen a glyph."""
    from lagrangian.output._report.document import Display, Document, Equation, Section
    from lagrangian.output._report.render.html import render_html

    doc = Document("fr", "Vecteurs", "", (Section("v", "Vecteurs", (Display(tuple(Equation((v,)) for v in _VECTORS)),)),))
    big = "<style>.lagrangian-report .display math { font-size: 72px; }</style></head>"
    html_text = render_html(doc)
    assert "transform" not in html_text
    html_text = html_text.replace("</head>", big).replace("</body>", _VECTOR_BOXES + "</body>")
    page = tmp_path / "vectors.html"
    page.write_text(html_text, encoding="utf-8")
    window = "--window-size=900,1400"
    run = _chromium(tmp_path, "--virtual-time-budget=5000", window, "--dump-dom", page.as_uri())
    assert run.returncode == 0, run.stderr[-2000:]
    found = re.search(r'<pre id="probe">(.*?)</pre>', run.stdout, re.S)
    assert found, run.stdout[-2000:]
    vectors = json.loads(found.group(1).replace("&quot;", '"'))
    assert len(vectors) == len(_VECTORS)
    shot = tmp_path / "vectors.png"
    run = _chromium(tmp_path, "--virtual-time-budget=5000", window, f"--screenshot={shot}", page.as_uri())
    assert run.returncode == 0, run.stderr[-2000:]
    import matplotlib.image

    pixels = matplotlib.image.imread(shot)
    dark = pixels[..., :3].mean(axis=2) < 0.5
    for (ml, mt, mr, mb), (bl, bt, br, _), *transforms in vectors:
        assert transforms == ["none", "none"]
        width = br - bl
        # The band above the letters, within the arrow's box: where the arrow is drawn.
        band = dark[int(mt):int(bt), int(ml) - 2:int(mr) + 3]
        cols = np.flatnonzero(band.any(axis=0))
        assert cols.size, (ml, mt, mr, mb)
        left, right = ml - 2 + cols[0], ml - 2 + cols[-1]
        # From the first letter's left edge to the last one's right edge (a glyph arrow left at its own width fails).
        assert left <= bl + 0.12 * width and right >= br - 0.12 * width, (left, right, bl, br)
        height = band.sum(axis=0)[cols[0]:cols[-1] + 1]
        line = np.median(height[: len(height) // 2])
        head = height[-max(3, len(height) // 8):].max()
        # A head at the right end: several times the line's thickness (an overline has none).
        assert line >= 1 and head >= 3 * line, (line, head)
        assert int(np.argmax(height)) >= 0.75 * len(height), (list(height), width)
