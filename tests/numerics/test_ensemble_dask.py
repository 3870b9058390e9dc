"""`ensemble` on a Dask cluster: a real LocalCluster with two worker processes.

The workers receive the generated C source, compile it once each (their own compile
cache), and must return exactly what the local threads compute.
"""

import numpy as np
import pytest

xr = pytest.importorskip("xarray")
distributed = pytest.importorskip("distributed")

import lagrangian  # noqa: E402
from lagrangian.cli.main import main  # noqa: E402
from lagrangian.errors import SimulationError  # noqa: E402
from lagrangian.numerics import _ensemble, compile_system, ensemble, grid, open_ensemble  # noqa: E402


@pytest.mark.slow
def test_local_cluster_gives_the_local_results(tmp_path):
    top = compile_system(lagrangian.derive(lagrangian.lagrange_top()))
    g = grid(theta=[0.4, 0.8, 1.2], phi_dot=[20.0, 40.0, 60.0, 80.0])
    local = ensemble(top, 1.0, initial=g, n_out=11, events=["theta_dot"], workers=1)
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=":0",
                                  host="127.0.0.1") as cluster, distributed.Client(cluster) as client:
        remote = ensemble(top, 1.0, initial=g, n_out=11, events=["theta_dot"], scheduler=client, chunk_size=3)
        store = tmp_path / "remote.zarr"
        by_address = ensemble(top, 1.0, initial=g, n_out=11, events=["theta_dot"], scheduler=cluster.scheduler_address,
                              chunk_size=5, out=store)
        cli = tmp_path / "cli.zarr"
        assert main(["sweep", "zoo:lagrange_top", "--grid", "phi_dot=20:80:4", "--set", "theta=0.8", "--t-end", "1",
                     "--n-out", "11", "--event", "theta_dot", "--out", str(cli), "--scheduler",
                     cluster.scheduler_address]) == 0
    on_cli = open_ensemble(cli)
    np.testing.assert_array_equal(on_cli.state_final.values, local.sel(theta=0.8).state_final.values)
    xr.testing.assert_identical(remote.drop_attrs(), local.drop_attrs())
    xr.testing.assert_identical(by_address.drop_attrs(), local.drop_attrs())
    assert np.all(local.status.values == 0)


@pytest.mark.slow
def test_unreachable_scheduler_is_a_clear_error_before_any_work(monkeypatch, tmp_path, capsys):
    monkeypatch.setattr(_ensemble, "CONNECT_TIMEOUT", "1s")
    with pytest.raises(SimulationError, match="cannot be reached") as info:
        ensemble("no such model.toml", 1.0, scheduler="tcp://127.0.0.1:9")  # checked before the model is read
    assert "dask scheduler" in info.value.fix
    out = tmp_path / "never.zarr"
    assert main(["sweep", "zoo:lagrange_top", "--grid", "phi_dot=20:80:4", "--out", str(out), "--scheduler",
                 "tcp://127.0.0.1:9"]) == 4
    assert "cannot be reached" in capsys.readouterr().err and not out.exists()


@pytest.mark.slow
def test_a_worker_killed_during_its_chunk_has_the_chunk_run_again_and_counted_once(tmp_path):
    """A worker process dies (os._exit) while it integrates a chunk.

    Dask's scheduler gives the lost task to another worker (its nanny also starts a new
    process); the sweep must end with every member done exactly once and equal to the local
    run.  The fault is injected from the test only, by a worker plugin pickled by value:
    the first worker to start a chunk exits 0.1 s later, in the middle of the C call.
    """
    from distributed.diagnostics.plugin import WorkerPlugin

    marker, log = tmp_path / "killed", tmp_path / "started"

    class KillFirstChunk(WorkerPlugin):
        name = "kill-first-chunk"

        def transition(self, key, start, finish, **kwargs):
            import os
            import threading

            if finish != "executing" or not str(key).startswith("lagrangian-chunk-"):
                return
            with open(log, "a") as handle:  # every start of a chunk, with the process that ran it
                handle.write(f"{key} {os.getpid()}\n")
            try:  # one death in all: the nanny's new process gets this plugin too
                fd = os.open(marker, os.O_CREAT | os.O_EXCL | os.O_WRONLY)
            except FileExistsError:
                return
            os.write(fd, str(key).encode())
            os.close(fd)
            threading.Timer(0.1, os._exit, args=(1,)).start()

    top = compile_system(lagrangian.derive(lagrangian.lagrange_top()))
    g = grid(theta=[0.5, 1.0, 1.5], phi_dot=[30.0, 60.0])  # 3 chunks of 2 members, ~0.5 s each on an idle core
    t_end = 1000.0
    local = ensemble(top, t_end, initial=g, n_out=11, events=["theta_dot"], workers=1)
    reports = []
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=":0",
                                  host="127.0.0.1", death_timeout="60s") as cluster, \
            distributed.Client(cluster, timeout="60s") as client:
        client.register_plugin(KillFirstChunk())
        remote = ensemble(top, t_end, initial=g, n_out=11, events=["theta_dot"], scheduler=client, chunk_size=2,
                          out=tmp_path / "sweep.zarr", progress=lambda fraction, done: reports.append(done))
    killed = marker.read_text()
    starts = [line.split() for line in log.read_text().splitlines()]
    # The fault really happened mid-chunk: the killed chunk was started twice, in two processes.
    assert len({pid for key, pid in starts if key == killed}) == 2
    assert len({key for key, _ in starts}) == 3
    # ... and was counted once: every member done, the progress never past the member count.
    assert reports[-1] == 6 and max(reports) == 6 and reports == sorted(reports)
    assert np.all(remote.status.values == 0) and np.all(open_ensemble(tmp_path / "sweep.zarr").status.values == 0)
    xr.testing.assert_identical(remote.drop_attrs(), local.drop_attrs())
