"""`lagrangian.ensemble`: many members in batched compiled calls.

The reference for every member is `simulate` on that member alone: the batch runs the same
integrator from the same control block, so states and event times must agree to the last
bit and the drift (reduced in NumPy over the batch instead of per trajectory) to rounding.
"""

from pathlib import Path

import numpy as np
import pytest

xr = pytest.importorskip("xarray")
pytest.importorskip("zarr")

import lagrangian  # noqa: E402
from lagrangian.errors import OutputError, SimulationError  # noqa: E402
from lagrangian.numerics import compile_system, ensemble, grid, open_ensemble, simulate  # noqa: E402
from lagrangian.numerics._batch import STATUS  # noqa: E402


@pytest.fixture(scope="module")
def top():
    return compile_system(lagrangian.derive(lagrangian.lagrange_top()))


@pytest.mark.slow
def test_each_member_equals_simulate_on_that_member(top):
    g = grid(theta=[0.3, 0.9], phi_dot=[30.0, 80.0], g=[9.81, 1.62])
    ds = ensemble(top, 1.5, initial=g, n_out=31, events=["theta_dot"], workers=2, chunk_size=3)
    assert ds.status.dims == ("theta", "phi_dot", "g") and ds.status.shape == (2, 2, 2)
    assert (ds.status == 0).all()
    for theta in g.axes[0][1]:
        for spin in g.axes[1][1]:
            for gravity in g.axes[2][1]:
                tr = simulate(top, 1.5, initial={"theta": theta, "phi_dot": spin}, parameters={"g": gravity},
                              n_out=31, events=["theta_dot"])
                m = ds.sel(theta=theta, phi_dot=spin, g=gravity)
                y = np.concatenate([tr.q, tr.qd], axis=1)
                np.testing.assert_array_equal(m.state_final.values, y[-1])
                np.testing.assert_array_equal(m.state_min.values, y.min(axis=0))
                np.testing.assert_array_equal(m.state_max.values, y.max(axis=0))
                assert m.event_time.item() == tr.events[0].t
                assert m.event_count.item() == len(tr.events)
                assert int(m.steps) == tr.steps and int(m.rhs_calls) == tr.rhs_calls
                for name in tr.integrals:
                    assert m.drift.sel(integral=name).item() == pytest.approx(tr.drift[name], rel=1e-9, abs=1e-18)


def test_kept_trajectories_equal_simulate_and_gauss_legendre_too(top):
    spins = np.array([40.0, 60.0])
    for method, kw in (("dop853", {}), ("gauss-legendre", {"dt": 1e-3})):
        ds = ensemble(top, 0.5, initial={"phi_dot": spins, "theta": 0.7}, n_out=11, keep="trajectories",
                      method=method, workers=1, **kw)
        assert ds.trajectory.dims == ("member", "time", "state")
        np.testing.assert_array_equal(ds.phi_dot.values, spins)
        for k, spin in enumerate(spins):
            tr = simulate(top, 0.5, initial={"phi_dot": spin, "theta": 0.7}, n_out=11, method=method, **kw)
            np.testing.assert_array_equal(ds.trajectory.values[k], np.concatenate([tr.q, tr.qd], axis=1))
            np.testing.assert_array_equal(ds.time.values, tr.t)


def test_kept_trajectories_too_big_for_memory_are_refused_before_the_run(top):
    # 2000 members × 10⁵ times × 6 states × 8 bytes = 9.6 GB: over the cap of 8 GiB (or a quarter of the memory).
    spins = np.linspace(10.0, 50.0, 2000)
    with pytest.raises(SimulationError, match=r"Keeping 2000 trajectories of 100000 times would take about") as err:
        ensemble(top, 1.0, initial={"phi_dot": spins, "theta": 0.7}, n_out=100_000, keep="trajectories", workers=1)
    assert ".zarr" in err.value.fix


def test_a_failing_member_is_flagged_and_the_others_go_on(top):
    # theta = 0: the Euler angles are singular (M loses rank); a fast spin needs more steps than allowed.
    ds = ensemble(top, 1.0, initial={"theta": [0.0, 0.5, 0.5], "phi_dot": [50.0, 20.0, 400.0]}, max_steps=200,
                  n_out=5, workers=1)
    names = [STATUS[int(c)] for c in ds.status.values]
    assert names == ["singular", "ok", "step-limit"]
    assert np.isnan(ds.drift.values[0]).all() and np.isfinite(ds.drift.values[1]).all()
    assert ds.t_final.values[1] == 1.0 and 0 < ds.t_final.values[2] < 1.0
    assert "pending ok stopped blow-up step-limit singular" in ds.status.attrs["flag_meanings"]


@pytest.mark.slow
def test_blow_up_is_flagged():
    # x'' = x^3 is solved by x = sqrt(2)/(c - t): from x = 2, x' = 2 sqrt(2) it reaches infinity at
    # t = c = sqrt(2)/2, a blow-up, while the member from x = 0.1 (x' = 0.1^2/sqrt(2)) stays small over 1 s.
    model = lagrangian.parse_model("""
        [model]
        name = "runaway"
        [parameters]
        m = { value = 1.0 }
        [coordinates]
        x = { initial = 2.0, rate = 2.0 }
        [frames]
        R0 = { axes = ["x0", "y0", "z0"] }
        [particles.p]
        mass = "m"
        position = "x*R0.x"
        [loads]
        push = { potential = "-m*x^4/4" }
        """)
    ds = ensemble(model, 1.0, initial={"x": [0.1, 2.0], "x_dot": [0.01 / 2**0.5, 2 * 2**0.5]}, n_out=5,
                  rtol=1e-8, atol=1e-8, workers=1)
    assert [STATUS[int(c)] for c in ds.status.values][0] == "ok"
    assert STATUS[int(ds.status.values[1])] in ("blow-up", "step-underflow")
    assert ds.t_final.values[1] == pytest.approx(2**-0.5, abs=1e-6)


def test_terminal_event_stops_the_member(top):
    stop = lagrangian.EventSpec("theta max", "theta_dot", direction=-1, terminal=True)
    ds = ensemble(top, 2.0, initial={"phi_dot": [40.0, 60.0]}, events=[stop], n_out=21, workers=1)
    tr = simulate(top, 2.0, initial={"phi_dot": 60.0}, events=[stop], n_out=21)
    assert [STATUS[int(c)] for c in ds.status.values] == ["stopped", "stopped"]
    assert ds.t_final.values[1] == tr.events[0].t and tr.t[-1] <= tr.events[0].t
    np.testing.assert_array_equal(ds.state_final.values[1, :3], tr.events[0].q)


@pytest.mark.slow
def test_zarr_store_streams_and_resume_finishes_pending_members(top, tmp_path):
    import zarr

    g = grid(theta=[0.4, 0.8, 1.2], phi_dot=[30.0, 60.0])
    whole = ensemble(top, 0.5, initial=g, n_out=11, workers=1)
    store = tmp_path / "sweep.zarr"
    first = ensemble(top, 0.5, initial=g, n_out=11, workers=2, chunk_size=2, out=store)
    xr.testing.assert_identical(first.drop_attrs(), whole.drop_attrs())
    flat = xr.open_zarr(store)  # plain xarray reads it: one member dimension, the swept names as coordinates
    assert flat.status.dims == ("member",) and flat.theta.dims == ("member",)
    np.testing.assert_array_equal(flat.state_final.values, whole.state_final.values.reshape(6, -1))
    # An interruption leaves members pending (status -1, their rows unwritten): resume finishes them.
    arrays = zarr.open_group(str(store), mode="r+")
    arrays["status"][2:5] = -1
    arrays["state_final"][2:5] = np.nan
    assert (open_ensemble(store).status == -1).sum() == 3
    resumed = ensemble(top, 0.5, initial=g, n_out=11, workers=1, out=store, resume=True)  # its chunks, not ours
    xr.testing.assert_identical(resumed.drop_attrs(), whole.drop_attrs())
    with pytest.raises(OutputError, match="already exists"):
        ensemble(top, 0.5, initial=g, n_out=11, chunk_size=2, out=store)
    with pytest.raises(OutputError, match="t_end"):
        ensemble(top, 0.7, initial=g, n_out=11, chunk_size=2, out=store, resume=True)


def test_resume_refuses_a_store_whose_run_record_is_not_json_text(top, tmp_path):
    import zarr

    store = tmp_path / "other.zarr"
    for record in (None, 7):  # absent, or written by another tool as a number: not the sweep's JSON text
        group = zarr.open_group(str(store), mode="w")
        if record is not None:
            group.attrs["lagrangian_run"] = record
        with pytest.raises(OutputError, match="is not a store written by"):
            ensemble(top, 0.5, initial=grid(theta=[0.4, 0.8]), n_out=11, out=store, resume=True)


@pytest.mark.slow
def test_netcdf_round_trip(top, tmp_path):
    path = tmp_path / "sweep.nc"
    ds = ensemble(top, 0.3, initial=grid(phi_dot=[20.0, 40.0, 60.0]), n_out=5, events=["theta_dot"], out=path)
    back = open_ensemble(path)
    xr.testing.assert_identical(back.drop_attrs(), ds.drop_attrs())
    with xr.open_dataset(path, engine="h5netcdf") as plain:
        assert plain.status.dims == ("member",)


def test_bad_members_are_clear_errors(top):
    with pytest.raises(SimulationError, match="`spin` in `initial` is not a coordinate or a rate"):
        ensemble(top, 1.0, initial={"spin": [1.0]})
    with pytest.raises(SimulationError, match="has 2 values, but the ensemble has 3 members"):
        ensemble(top, 1.0, initial={"theta": [0.1, 0.2], "phi_dot": [1.0, 2.0, 3.0]})
    with pytest.raises(SimulationError, match="grid axis `nope`"):
        ensemble(top, 1.0, initial=grid(nope=[1.0]))
    with pytest.raises(SimulationError, match="not finite"):
        ensemble(top, 1.0, parameters={"g": [1.0, np.inf]})
    with pytest.raises(SimulationError, match="compiled integrators"):
        ensemble(top, 1.0, method="RK45")
    with pytest.raises(OutputError, match=".zarr"):
        ensemble(top, 1.0, out="x.csv")
    examples = Path(__file__).resolve().parents[2] / "examples"
    with pytest.raises(SimulationError, match="complementary constraints"):
        ensemble(examples / "pendulum_tension.toml", 1.0)
