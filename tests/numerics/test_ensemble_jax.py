"""`ensemble(..., backend="jax")`: the JAX export's rhs, vmapped, integrated by diffrax (the GPU route),
checked on CPU against the compiled C path (an independent integrator: its own Dormand-Prince 8
and step control, its own generated code)."""

import numpy as np
import pytest

xr = pytest.importorskip("xarray")
pytest.importorskip("jax")
pytest.importorskip("diffrax")

import lagrangian  # noqa: E402
from lagrangian.cli.main import main  # noqa: E402
from lagrangian.errors import SimulationError  # noqa: E402
from lagrangian.numerics import ensemble, open_ensemble  # noqa: E402


@pytest.mark.slow
def test_jax_backend_agrees_with_the_c_path(tmp_path):
    """Tops of several angles, spins and g: the final states, the extremes and the kept trajectories
    agree with the C batch integrator to 1e-8 of each member's state size at rtol = atol = 1e-10."""
    eom = lagrangian.derive(lagrangian.lagrange_top())
    initial = {"theta": np.array([0.3, 0.7, 1.1, 1.5, 0.9]), "phi_dot": np.array([20.0, 35.0, 50.0, 80.0, 60.0])}
    parameters = {"g": np.array([9.81, 3.0, 9.81, 20.0, 1.0])}
    common = dict(initial=initial, parameters=parameters, n_out=21, rtol=1e-10, atol=1e-10, keep="trajectories")
    c = ensemble(eom, 2.0, workers=1, **common)
    store = tmp_path / "tops.zarr"
    j = ensemble(eom, 2.0, backend="jax", chunk_size=2, out=store, **common)  # 3 chunks, the last one padded
    assert np.all(j.status.values == 0) and np.all(j.t_final.values == 2.0)
    scale = 1.0 + np.abs(c.trajectory.values).max(axis=(1, 2))  # per member: the size of its state (~80 here)
    for name in ("state_final", "state_min", "state_max", "trajectory"):
        error = np.abs(j[name].values - c[name].values).reshape(len(scale), -1).max(axis=1) / scale
        assert error.max() < 1e-8, (name, error)
    assert np.abs(j.state_final.values - c.state_final.values).max() > 0  # two integrators, not one
    np.testing.assert_array_equal(j.g.values, parameters["g"])
    assert (j.steps.values > 10).all() and (j.rhs_calls.values > j.steps.values).all()
    assert "drift" not in j and "event_time" not in j  # what the JAX path does not compute
    xr.testing.assert_identical(open_ensemble(store), j.load())


@pytest.mark.slow
def test_sweep_on_the_jax_backend(tmp_path):
    """`lagrangian sweep --backend jax` writes the same members as the C sweep, to the tolerance."""
    runs = {}
    for backend in ("c", "jax"):
        out = tmp_path / f"{backend}.nc"
        assert main(["sweep", "zoo:lagrange_top", "--grid", "phi_dot=20:80:3", "--set", "theta=0.8", "--t-end",
                     "0.5", "--n-out", "6", "--backend", backend, "--out", str(out)]) == 0
        runs[backend] = xr.open_dataset(out, engine="h5netcdf").load()
    assert runs["jax"].status.values.tolist() == [0, 0, 0]
    assert '"backend": "jax"' in runs["jax"].attrs["lagrangian_run"]
    np.testing.assert_allclose(runs["jax"].state_final.values, runs["c"].state_final.values, rtol=1e-9, atol=1e-9)
    with pytest.raises(SystemExit):  # argparse's own refusal of an unknown backend
        main(["sweep", "zoo:lagrange_top", "--grid", "phi_dot=20:80:3", "--backend", "cuda", "--out",
              str(tmp_path / "x.nc")])


def test_jax_backend_refuses_what_it_cannot_do():
    with pytest.raises(SimulationError, match="without events"):
        ensemble("examples/lagrange_top.toml", 1.0, backend="jax", events=["theta_dot"])
    with pytest.raises(SimulationError, match="without events"):
        ensemble("examples/lagrange_top.toml", 1.0, backend="jax", method="gauss-legendre")
    with pytest.raises(SimulationError, match="ensemble backends are 'c', 'jax'"):
        ensemble("examples/lagrange_top.toml", 1.0, backend="cuda")
