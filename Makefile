# Two set-up commands (see README.md): `make demo` and `make test`.
# Both create the virtual environment .venv on first use and install the package into it: `make demo` the
# core alone (what `lagrangian derive` needs), `make test` the `test` extra too. `make check` is the quick loop.
PYTHON ?= python3
VENV ?= .venv
PY := $(VENV)/bin/python

.PHONY: demo test check lint types docs bench clean browser octave tex peers

# Two stamps, so that neither install is redone while pyproject.toml is unchanged: .core for the demo,
# .test for the tests (installing the test extra installs the core too, so it stamps both).
$(VENV)/.core: pyproject.toml
	test -x $(PY) || $(PYTHON) -m venv $(VENV)
	$(PY) -m pip install --quiet --upgrade pip
	$(PY) -m pip install --quiet -e .
	touch $@

$(VENV)/.test: pyproject.toml
	test -x $(PY) || $(PYTHON) -m venv $(VENV)
	$(PY) -m pip install --quiet --upgrade pip
	$(PY) -m pip install --quiet -e '.[test]'
	touch $(VENV)/.core $@

demo: $(VENV)/.core   ## derive the seed's Lagrange top
	$(VENV)/bin/lagrangian derive

# What `make check` leaves out: the slow tests and those needing a browser, TeX, Octave or the robot referees.
QUICK := not slow and not browser and not tex and not octave and not robots and not docs

lint: $(VENV)/.test   ## ruff on the package, the tests, the benchmarks and the tools (rules in pyproject.toml)
	$(PY) -m ruff check src tests benchmarks tools

check: lint types   ## the quick loop: lint, types and the fast tests (under 90 s on 2 cores)
	$(PY) -m pytest src tests -m "$(QUICK)" -p no:cacheprovider -n auto --maxprocesses 4

# The whole suite runs on every core (pytest-xdist, at most 4 workers): about 6 minutes on 2 cores, 11 in one process.
test: lint types $(VENV)/.test browser octave tex peers   ## lint, types and the whole test suite (CI runs this)
	$(PY) -m pytest src tests -n auto --maxprocesses 4

# mypy on src/ (settings in pyproject.toml), its error count held at or below tools/mypy_baseline.txt.
types: $(VENV)/.test   ## type-check the package; fails when the mypy error count rises
	$(PY) tools/type_ratchet.py

# The API reference from the docstrings (Sphinx with numpydoc, docs/api/): nitpicky (-n: every reference into
# the package resolves), warnings are errors (-W, all of them reported: --keep-going). Open docs/api/_build/index.html.
docs: $(VENV)/.test   ## build the API reference
	$(PY) -m sphinx -b html -n -W --keep-going -q docs/api docs/api/_build

# The HTML report's tests open the page in a headless browser (Debian's chromium). Install it when it
# is missing and we are root with apt-get; otherwise say so: those tests are then skipped, the build goes on.
browser:
	@if command -v chromium >/dev/null 2>&1 || command -v chromium-browser >/dev/null 2>&1 \
	    || command -v google-chrome >/dev/null 2>&1; then :; \
	elif [ "$$(id -u)" = 0 ] && command -v apt-get >/dev/null 2>&1; then \
	    echo "installing chromium (headless browser for the HTML report tests)..."; \
	    (DEBIAN_FRONTEND=noninteractive apt-get install -y -q chromium >/dev/null 2>&1 \
	     || (apt-get update -q >/dev/null 2>&1 \
	         && DEBIAN_FRONTEND=noninteractive apt-get install -y -q chromium >/dev/null 2>&1)) \
	    || echo "note: chromium could not be installed; the HTML report's browser tests will be skipped"; \
	else \
	    echo "note: chromium is not installed (installing it needs root and apt-get);" \
	         "the HTML report's browser tests will be skipped"; \
	fi

# The Octave export's tests run the exported .m files with GNU Octave (Debian's octave, without its
# recommended packages: about 70 MB to download, 1.5 minutes). Install it when missing and we are root
# with apt-get, unless SKIP_OCTAVE=1; otherwise those tests check the files' structure only.
octave:
	@if command -v octave >/dev/null 2>&1 || [ -n "$(SKIP_OCTAVE)" ]; then :; \
	elif [ "$$(id -u)" = 0 ] && command -v apt-get >/dev/null 2>&1; then \
	    echo "installing octave (runs the Octave export in the tests; SKIP_OCTAVE=1 to skip)..."; \
	    (DEBIAN_FRONTEND=noninteractive apt-get install -y -q --no-install-recommends octave >/dev/null 2>&1 \
	     || (apt-get update -q >/dev/null 2>&1 \
	         && DEBIAN_FRONTEND=noninteractive apt-get install -y -q --no-install-recommends octave \
	            >/dev/null 2>&1)) \
	    || echo "note: octave could not be installed; the Octave export is checked for structure only"; \
	else \
	    echo "note: octave is not installed (installing it needs root and apt-get);" \
	         "the Octave export is checked for structure only"; \
	fi

# The LaTeX report's tests compile it (pdflatex, from Debian's TeX Live: about 100 MB) and read the PDF back
# (pdftotext and pdffonts, poppler-utils). lmodern gives the Type 1 Latin Modern fonts, so that the text is not
# in bitmap Type 3 fonts (the EC fonts' default without it). Installed like chromium: when missing and we are
# root with apt-get; else those tests are skipped.
TEX_PACKAGES := texlive-latex-base texlive-latex-recommended texlive-lang-french lmodern poppler-utils
tex:
	@if command -v pdflatex >/dev/null 2>&1 && command -v pdftotext >/dev/null 2>&1 \
	    && command -v pdffonts >/dev/null 2>&1 && kpsewhich lmodern.sty >/dev/null 2>&1; then :; \
	elif [ "$$(id -u)" = 0 ] && command -v apt-get >/dev/null 2>&1; then \
	    echo "installing TeX Live and poppler-utils (LaTeX and PDF report tests)..."; \
	    (DEBIAN_FRONTEND=noninteractive apt-get install -y -q --no-install-recommends $(TEX_PACKAGES) >/dev/null 2>&1 \
	     || (apt-get update -q >/dev/null 2>&1 \
	         && DEBIAN_FRONTEND=noninteractive apt-get install -y -q --no-install-recommends $(TEX_PACKAGES) \
	            >/dev/null 2>&1)) \
	    || echo "note: TeX Live could not be installed; the LaTeX and PDF report tests will be skipped"; \
	else \
	    echo "note: pdflatex is not installed (installing it needs root and apt-get);" \
	         "the LaTeX and PDF report tests will be skipped"; \
	fi

# The optimal-control tests compare with opty (direct collocation on SymPy mechanics), which runs IPOPT through
# cyipopt, built against the system's IPOPT. Install them when missing and we are root with apt-get, unless
# SKIP_PEERS=1; otherwise the comparison tests are skipped (the others run: CasADi ships its own IPOPT).
PEER_PACKAGES := coinor-libipopt-dev libmumps-seq-dev liblapack-dev libblas-dev gfortran pkg-config
peers: $(VENV)/.test
	@if $(PY) -c "import cyipopt, opty" >/dev/null 2>&1 || [ -n "$(SKIP_PEERS)" ]; then :; \
	elif [ "$$(id -u)" = 0 ] && command -v apt-get >/dev/null 2>&1; then \
	    echo "installing IPOPT, cyipopt and opty (the optimal-control peers; SKIP_PEERS=1 to skip)..."; \
	    ((DEBIAN_FRONTEND=noninteractive apt-get install -y -q --no-install-recommends $(PEER_PACKAGES) >/dev/null 2>&1 \
	      || (apt-get update -q >/dev/null 2>&1 \
	          && DEBIAN_FRONTEND=noninteractive apt-get install -y -q --no-install-recommends $(PEER_PACKAGES) \
	             >/dev/null 2>&1)) \
	     && $(PY) -m pip install --quiet -e '.[peers]') \
	    || echo "note: cyipopt and opty could not be installed; the comparisons with opty will be skipped"; \
	else \
	    echo "note: opty is not installed (its IPOPT needs root and apt-get);" \
	         "the comparisons with opty will be skipped"; \
	fi

bench: $(VENV)/.test   ## derivation benchmark against SymPy's LagrangesMethod (slow: minutes)
	$(PY) benchmarks/derive_vs_sympy.py

clean:
	rm -rf $(VENV) build *.egg-info src/*.egg-info docs/api/_build docs/api/generated
