"""The report's `document` laid out in one format per module.

* `markdown` — Markdown with GitHub's and GitLab's math syntax;
* `html` — one self-contained HTML page (MathML, images as data: URIs);
* `tex` — a LaTeX document that ``pdflatex`` compiles;
* `pdf` — that LaTeX compiled by a TeX engine installed on the machine.

The renderers only lay out what the steps built: the formats always say the same thing.
"""
