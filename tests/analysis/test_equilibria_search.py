"""Where the equilibria are searched, families of rests and rests of singular coordinates, against hand
derivations written here.

* Elastic pendulum (bob m on a spring k, rest length L, from O; r along −z1, θ from the downward
  vertical): k (r − L) = m g cos θ and m g r sin θ = 0, so r = L + m g/k hanging and r = L − m g/k
  upright (θ = π, the spring compressed), when L > m g/k.
* Bead on the parabola z = a r² turning at Ω: U = m (g a − Ω²/2) r², every r a rest at Ω² = 2 g a.
* A particle in the ring well U = k (x² + y² − a²)²: the circle x² + y² = a² is a curve of rests.
* Swinging Atwood machine: −M g + m g cos θ = 0 and m g r sin θ = 0 give r = 0, cos θ = M/m, where
  M(q) = diag(M + m, m r²) is singular.
"""

from __future__ import annotations

import json
import math

import numpy as np
import pytest
from more_systems import TEXTS
from more_systems import eom as system_eom

import lagrangian
from lagrangian.cli import _equilibria as cli
from lagrangian.cli.main import main
from lagrangian.output import equilibria_text

RING = """
[model]
name = "Ring well"
[parameters]
m = { value = 1.0 }
k = { value = 2.0 }
a = { value = 1.5 }
[coordinates]
x = { initial = 0.0, rate = 0.0 }
y = { initial = 0.0, rate = 0.0 }
[particles.P]
mass = "m"
position = "x*R0.x + y*R0.y"
[loads]
well = { potential = "k*(x^2 + y^2 - a^2)^2" }
"""


def _write(tmp_path, name: str, text: str | None = None) -> str:  # type: ignore[no-untyped-def]
    path = tmp_path / f"{name}.toml"
    path.write_text(text if text is not None else TEXTS[name], encoding="utf-8")
    return str(path)


@pytest.fixture(scope="module")
def elastic() -> lagrangian.analysis.Equilibria:
    return lagrangian.equilibria(system_eom("elastic"))


@pytest.mark.slow
def test_the_elastic_pendulum_rests_are_found_without_a_range_each_once(elastic):
    m, g, k, L = 1.0, 9.81, 75.0, 0.5
    rests = sorted((round(e.numeric["r"], 9), round(e.numeric["theta"], 9)) for e in elastic)
    assert rests == [(round(L - m * g / k, 9), round(math.pi, 9)), (round(L + m * g / k, 9), 0.0)]
    # r = −0.63, θ = π puts the bob where r = 0.63, θ = 0 does: the same rest, named once
    hanging = next(e for e in elastic if e.numeric["theta"] == 0.0)
    assert [(round(a["r"], 9), round(abs(a["theta"]), 9)) for a in hanging.aliases] == \
        [(round(-L - m * g / k, 9), round(math.pi, 9))]
    search = elastic.search
    assert search.numeric and search.unbounded == ("r",)
    assert {r.coordinate: r.kind for r in search.regions} == {"r": "scales", "theta": "angle"}


@pytest.mark.slow
def test_the_text_and_the_json_say_where_it_searched_and_that_a_rest_may_be_missing(elastic):
    names = ["r", "theta"]
    verdicts = [None] * len(elastic)
    out = equilibria_text(system_eom("elastic"), elastic, verdicts)
    assert "r = 0.3692, θ = π" in out  # the upright rest, compressed spring
    assert "Searched:" in out and "no range declared" in out and "may be missing" in out and "--range r=a:b" in out
    doc = json.loads(json.dumps(cli._document("Elastic pendulum", tuple(names), {}, elastic, verdicts,
                                              elastic.search)))
    assert doc["search"]["unbounded"] == ["r"] and doc["search"]["regions"][0]["bounds"] == [None, None]


@pytest.mark.slow
def test_a_declared_range_is_where_the_search_looks():
    text = TEXTS["elastic"].replace('r = { initial = 0.6, rate = 0.0 }', 'r = { initial = 0.6, rate = 0.0, range = [0, "inf"] }')
    assert text != TEXTS["elastic"]
    found = lagrangian.equilibria(lagrangian.derive(lagrangian.parse_model(text)))
    region = found.search.regions[0]
    assert (region.kind, region.bounds) == ("declared", (0.0, math.inf))
    assert all(e.numeric["r"] > 0 and not e.aliases for e in found) and len(found) == 2


def test_at_the_critical_rate_every_radius_of_the_turning_parabola_is_a_rest():
    found = lagrangian.equilibria(system_eom("parabola"))  # Ω² = 9.81 = 2 g a
    assert len(found) == 1 and found[0].free == ("r",)
    assert found.search.regions[0].kind == "scales"  # r is a length: never searched as an angle
    below = lagrangian.equilibria(system_eom("parabola"), parameters={"Omega": 2.0})
    assert [(e.free, e.numeric) for e in below] == [((), {"r": 0.0})]  # m (2 g a − Ω²) r = 0


def test_the_family_of_rests_at_the_critical_rate_is_printed_once_with_its_verdict(tmp_path, capsys):
    assert main(["equilibria", _write(tmp_path, "parabola")]) == 0
    out = capsys.readouterr().out
    listed = [line for line in out.splitlines() if line.startswith("  ") and ". " in line[:6]]
    assert listed == ["  1. r any  (numeric; residual 0.0e+00)"]
    assert "marginal" in out  # a shift along the family is another rest: the linearization does not decide


@pytest.mark.slow
def test_a_circle_of_rests_is_one_family_with_its_centre_apart():
    a = 1.5
    found = lagrangian.equilibria(lagrangian.derive(lagrangian.parse_model(RING)))
    centre = [e for e in found if e.numeric == {"x": 0.0, "y": 0.0}]
    ring = [e for e in found if e not in centre]
    assert len(centre) == 1 and centre[0].family == 0
    assert len(ring) == 1 and ring[0].family == 1  # one point stands for the circle
    x, y = (float(ring[0].numeric[n]) for n in ("x", "y"))
    assert math.hypot(x, y) == pytest.approx(a, rel=1e-9)


@pytest.mark.slow
def test_a_rest_where_the_mass_matrix_is_singular_says_so(tmp_path, capsys):
    M, m = 1.0, 2.0
    assert main(["equilibria", _write(tmp_path, "atwood"), "--json"]) == 0
    found = json.loads(capsys.readouterr().out)["equilibria"]
    assert len(found) == 1  # θ = ± arccos(M/m) at r = 0 put both masses in the same place: one rest
    e = found[0]
    assert e["numeric"]["r"] == 0.0 and abs(e["numeric"]["theta"]) == pytest.approx(math.acos(M / m), rel=1e-12)
    assert len(e["aliases"]) == 1
    assert e["stability_verdict"] == "undecided" and "mass matrix M is singular here" in e["stability_reason"]


def test_a_time_dependent_load_switched_off_by_its_amplitude_leaves_an_autonomous_system(tmp_path, capsys):
    eom = system_eom("driven")
    m, c, k = 1.0, 0.4, 4.0
    with pytest.raises(lagrangian.LinearizationError, match="depend on the time t"):
        lagrangian.linearize(eom, {"x": 0})
    with pytest.raises(lagrangian.analysis.EquilibriumError, match="depends on t explicitly"):
        lagrangian.equilibria(eom)
    lin = lagrangian.linearize(eom, {"x": 0}, parameters={"F0": 0.0})
    np.testing.assert_allclose(lin.numeric()[0], [[0, 1], [-k / m, -c / m]], rtol=1e-14)  # m ẍ + c ẋ + k x = 0
    assert lin.stability().verdict == "asymptotically stable"
    found = lagrangian.equilibria(eom, parameters={"F0": 0.0})
    assert [e.numeric for e in found] == [{"x": 0.0}]
    assert main(["linearize", _write(tmp_path, "driven"), "--at", "x=0", "--set", "F0=0"]) == 0
    assert "asymptotically stable" in capsys.readouterr().out
