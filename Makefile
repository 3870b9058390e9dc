# Two set-up commands (see README.md): `make demo` and `make test`.
# Both create the virtual environment .venv on first use and install the package into it.
PYTHON ?= python3
VENV ?= .venv
PY := $(VENV)/bin/python

.PHONY: demo test bench clean

$(VENV)/.installed: pyproject.toml
	$(PYTHON) -m venv $(VENV)
	$(PY) -m pip install --quiet --upgrade pip
	$(PY) -m pip install --quiet -e '.[test]'
	touch $@

demo: $(VENV)/.installed   ## derive the seed's Lagrange top
	$(VENV)/bin/lagrangian derive

test: $(VENV)/.installed   ## run the test suite
	$(PY) -m pytest src tests

bench: $(VENV)/.installed   ## derivation benchmark against SymPy's LagrangesMethod (slow: minutes)
	$(PY) benchmarks/derive_vs_sympy.py

clean:
	rm -rf $(VENV) build *.egg-info src/*.egg-info
