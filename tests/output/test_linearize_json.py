"""The ``lagrangian.linearize`` document: valid against its schema, and its strings mean the numbers.

The symbolic document (every parameter a letter, read back with SymPy) evaluated at the
model's values must give the numeric document's matrices: two renderings of one
linearization that share no code path after `linearize`.
"""

from __future__ import annotations

import json
import math
from pathlib import Path

import jsonschema
import numpy as np
import pytest
import sympy
from lagrangian_test_support import EXAMPLES_DIR

import lagrangian
from lagrangian.output import LINEARIZE_SCHEMA_ID, linearize_document

SCHEMA = json.loads((Path(lagrangian.output.__file__).parent / "linearize.schema.json").read_text())

POINTS = {
    "simple_pendulum.toml": {"theta": 0},
    "double_pendulum.toml": {"theta1": 0, "theta2": 0},
    "bead_rotating_hoop.toml": {"theta": 0},
    "cart_pendulum.toml": {"x": 0, "theta": "pi"},
}


@pytest.mark.slow
@pytest.mark.parametrize("name", sorted(POINTS))
def test_document_is_valid_and_its_strings_mean_its_numbers(name):
    model = lagrangian.load_model(EXAMPLES_DIR / name)
    eom = lagrangian.derive(model)
    lin = lagrangian.linearize(eom, POINTS[name])
    doc = json.loads(json.dumps(linearize_document(lin, source=str(name), package_version="test")))
    jsonschema.validate(doc, SCHEMA)
    assert doc["schema"] == LINEARIZE_SCHEMA_ID and doc["version"] == 1 and doc["numeric"] is True
    assert doc["state"] == doc["coordinates"] + [c + "_dot" for c in doc["coordinates"]]
    assert len(doc["A"]) == len(doc["state"]) and all(len(r) == len(doc["state"]) for r in doc["A"])
    assert len(doc["eigenvalues"]) == len(doc["state"]) and doc["stable"] in (True, False, None)
    # The eigenvalues are those of the printed A.
    lam = sorted(np.linalg.eigvals(np.array(doc["A"])), key=lambda z: (round(z.real, 9), z.imag))
    got = sorted((complex(a, b) for a, b in doc["eigenvalues"]), key=lambda z: (round(z.real, 9), z.imag))
    np.testing.assert_allclose(got, lam, atol=1e-9)

    symbolic = lagrangian.linearize(eom, POINTS[name], symbolic=[p.name for p in model.parameters])
    sdoc = json.loads(json.dumps(linearize_document(symbolic, source=None, package_version="test")))
    jsonschema.validate(sdoc, SCHEMA)
    assert sdoc["numeric"] is False and sdoc["eigenvalues"] is None and sdoc["stable"] is None
    values = {sympy.Symbol(k): v for k, v in model.parameter_values.items()}
    for key in ("M", "K", "A"):
        evaluated = [[float(sympy.sympify(e).xreplace(values)) for e in row] for row in sdoc[key]]
        np.testing.assert_allclose(evaluated, doc[key], rtol=1e-12, atol=1e-12)


def test_matrices_without_columns_and_non_finite_numbers_stay_json():
    eom = lagrangian.derive(lagrangian.load_model(EXAMPLES_DIR / "simple_pendulum.toml"))
    doc = linearize_document(lagrangian.linearize(eom, {"theta": 0}), source=None, package_version="test")
    assert doc["B"] == [[], []] and doc["inputs"] == []
    text = json.dumps(doc, allow_nan=False)  # no NaN or Infinity
    assert math.isfinite(json.loads(text)["modes"]["pulsations"][0])
