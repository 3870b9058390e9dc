"""Compile plans: the second system of the same derived equations loads its library without regenerating it."""

import dataclasses
import json

import numpy as np
import pytest

import lagrangian
from lagrangian.model.zoo import lagrange_top, planar_chain
from lagrangian.numerics import _plans, _system, compile_system
from lagrangian.numerics._plans import plan_key


@pytest.fixture
def cache(tmp_path, monkeypatch):
    monkeypatch.setenv("LAGRANGIAN_CACHE", str(tmp_path / "cache"))
    return tmp_path / "cache"


def _forbid_generation(monkeypatch) -> None:
    def refused(*args, **kwargs):
        raise AssertionError("the system was made from the equations although its plan is in the cache")

    monkeypatch.setattr(_system, "generate_c", refused)
    monkeypatch.setattr(_system, "first_integrals", refused)


def _plan_file(cache):
    (path,) = cache.glob("plan_*.json")
    return path


@pytest.mark.slow
def test_a_system_made_again_comes_from_its_plan_and_computes_the_same(cache, monkeypatch):
    first = compile_system(lagrangian.derive(lagrange_top()))
    plan = json.loads(_plan_file(cache).read_text())
    assert plan["integrals"] == ["K", "H", "E"] and plan["monitors"] == ["K", "H", "E", "T", "U"]
    assert oct(_plan_file(cache).stat().st_mode & 0o777) == "0o600"
    with monkeypatch.context() as m:
        _forbid_generation(m)
        again = compile_system(lagrangian.derive(lagrange_top()))
        assert again.integrals == first.integrals and again.monitors == first.monitors
        p = again.parameter_vector()
        assert np.array_equal(p, first.parameter_vector())
        rng = np.random.default_rng(0)
        Y = np.hstack([rng.uniform(0.2, 1.2, (20, 3)), rng.uniform(-3, 3, (20, 3))])
        assert np.array_equal(again.rhs(0.0, Y, p), first.rhs(0.0, Y, p))
        assert np.array_equal(again.monitor_values(0.0, Y, p), first.monitor_values(0.0, Y, p))
        a, b = lagrangian.simulate(first, 1.0), lagrangian.simulate(again, 1.0)
        assert np.array_equal(a.q, b.q) and a.drift == b.drift
    # What the plan skipped is made on first use, as it would have been.
    assert [fi.name for fi in again.first_integrals] == ["K", "H", "E"]
    assert again.source == first.source


def test_equations_not_made_by_derive_get_no_plan():
    eom = lagrangian.derive(lagrange_top())
    assert eom.derived_with == "auto" and plan_key(eom, {}, None, ()) is not None
    changed = dataclasses.replace(eom, F=tuple(f + 1 for f in eom.F))
    assert changed.derived_with is None and plan_key(changed, {}, None, ()) is None


def test_the_key_names_the_model_the_formulation_and_the_options():
    top = lagrangian.derive(lagrange_top())
    on_the_moon = lagrangian.derive(dataclasses.replace(lagrange_top(), parameters=tuple(
        dataclasses.replace(p, value=1.62) if p.name == "g" else p for p in lagrange_top().parameters)))
    keys = {plan_key(top, {}, None, ()), plan_key(on_the_moon, {}, None, ()),
            plan_key(lagrangian.derive(lagrange_top(), formulation="lagrange"), {}, None, ()),
            plan_key(top, {"tau": "off"}, None, ()), plan_key(top, {}, "/* a law */", ()),
            plan_key(top, {}, None, [("theta", top.q[1])])}
    assert len(keys) == 6 and plan_key(top, {}, None, ()) == plan_key(lagrangian.derive(lagrange_top()), {}, None, ())


@pytest.mark.slow
@pytest.mark.parametrize("spoil", ["truncated", "no checksum", "group-writable", "other content", "no library"])
def test_a_plan_that_cannot_be_trusted_or_used_is_made_again(cache, monkeypatch, spoil):
    model = planar_chain(2)
    compile_system(lagrangian.derive(model))
    path = _plan_file(cache)
    sidecar = path.with_name(path.name + ".sha256")
    if spoil == "truncated":
        path.write_text(path.read_text()[:40])
    elif spoil == "no checksum":
        sidecar.unlink()
    elif spoil == "group-writable":
        path.chmod(0o660)
    elif spoil == "other content":  # matching checksum, but not a plan `write_plan` writes
        doc = json.loads(path.read_text())
        doc["constants"] = -1
        path.write_text(json.dumps(doc))
        sidecar.write_text(_plans._digest(path) + "\n")
    else:  # the plan names a library the cache no longer has
        for library in cache.glob("lg_*.so"):
            library.unlink()
    made = []
    real = _system.generate_c
    monkeypatch.setattr(_system, "generate_c", lambda *a, **k: made.append(1) or real(*a, **k))
    system = compile_system(lagrangian.derive(model))
    assert made == [1] and system.rhs(0.0, np.full(4, 0.3), system.parameter_vector()).shape == (4,)
    assert json.loads(_plan_file(cache).read_text())["constants"] >= 0  # written anew
    assert _plans.read_plan(json.loads(path.read_text())["key"]) is not None

