"""Sweeps as Dask tasks (mbs.sweep): schedule-independent results, worker loss, failed points, resume.

Cheap on purpose: trims of the ``hover`` scene at 0 to 5 m/s with 50 steps per revolution
(about 0.6 s a point), on one local cluster of 2 worker processes shared by the tests.
"""
from __future__ import annotations

import logging
import os
import signal

import numpy as np
import pyarrow.parquet as pq
import pytest

pytest.importorskip("distributed")
pytestmark = pytest.mark.filterwarnings("ignore:Port 8787 is already in use")

from mbs import sweep  # noqa: E402
from mbs.sweep import grid, models, table  # noqa: E402

SCENE, OPTIONS = "hover", {"steps_per_rev": 50}
SPEEDS = np.linspace(0.0, 5.0, 6)
RESULTS = ["collective", "lateral_cyclic", "longitudinal_cyclic", "tail_collective", "roll", "pitch", "thrust",
           "iterations", "max_abs_residual", "status", "message"]


def local_cluster(workers: int):
    from distributed import LocalCluster

    return LocalCluster(n_workers=workers, threads_per_worker=1, processes=True, dashboard_address=None,
                        silence_logs=logging.ERROR)


@pytest.fixture(scope="module")
def client():
    """A local cluster of 2 worker processes; the model compiled here first."""
    from distributed import Client

    models.loaded("trim", SCENE, OPTIONS)
    with local_cluster(2) as cluster, Client(cluster) as c:
        yield c


@pytest.fixture(scope="module")
def plain_loop() -> dict[float, dict]:
    """The same trims by plain calls of :func:`mbs.analysis.trim.trim`, by speed."""
    from mbs.analysis.trim import trim

    system, stepper = models.loaded("trim", SCENE, OPTIONS)
    out = {}
    for v in SPEEDS:
        res = trim(SCENE, speed=float(v), steps_per_rev=50, system=system, stepper=stepper)
        out[float(v)] = {**res.controls, "roll": res.roll, "pitch": res.pitch, "thrust": res.thrust,
                         "iterations": res.iterations, "status": "ok" if res.converged else "failed"}
    return out


def _count_compiles() -> None:
    """In a worker: count the models compiled from now on (``mbs.backends.compiled._compile_into``)."""
    import mbs.backends.compiled as compiled

    real, compiled.sweep_test_compiles = compiled._compile_into, []

    def counted(folder, *args):
        compiled.sweep_test_compiles.append(str(folder))
        return real(folder, *args)
    compiled._compile_into = counted


def _compiles() -> int:
    import mbs.backends.compiled as compiled

    return len(compiled.sweep_test_compiles)


def _same_as_loop(result, loop: dict) -> None:
    rows = result.to_pylist()
    assert [r["speed"] for r in rows] == list(loop)
    for r in rows:
        assert {k: r[k] for k in loop[r["speed"]]} == loop[r["speed"]]  # bit for bit


def _results(result) -> list[dict]:
    return result.select(["speed", *RESULTS]).to_pylist()


def test_two_workers_one_worker_and_a_plain_loop_agree_bit_for_bit(client, plain_loop):
    from distributed import Client

    client.run(_count_compiles)
    two = sweep.trim_sweep(SCENE, SPEEDS, options=OPTIONS, client=client)
    assert set(client.run(_compiles).values()) == {0}  # workers loaded the client's build, compiled nothing
    assert set(two.column("status").to_pylist()) == {"ok"}
    _same_as_loop(two, plain_loop)
    with local_cluster(1) as cluster, Client(cluster) as c:
        one = sweep.trim_sweep(SCENE, SPEEDS, options=OPTIONS, client=c)
    assert _results(one) == _results(two)
    assert _results(sweep.trim_sweep(SCENE, SPEEDS, options=OPTIONS, workers=0)) == _results(two)


def test_a_worker_killed_mid_sweep_loses_no_point(client, plain_loop):
    killed = []

    def kill_a_busy_worker(done: int, total: int) -> None:
        if done == 1 and not killed:
            busy = [w for w, keys in client.processing().items() if keys]
            busy = busy or list(client.scheduler_info()["workers"])
            pid = client.run(os.getpid, workers=busy[:1])[busy[0]]
            os.kill(pid, signal.SIGKILL)
            killed.append(pid)

    result = sweep.trim_sweep(SCENE, SPEEDS, options=OPTIONS, client=client, progress=kill_a_busy_worker)
    assert killed
    assert sweep.run_info(result)["computed"] == len(SPEEDS)
    assert set(result.column("status").to_pylist()) == {"ok"}
    _same_as_loop(result, plain_loop)


def test_a_point_that_cannot_trim_is_a_failed_row_and_the_others_complete(client, plain_loop):
    result = sweep.trim_sweep(SCENE, [0.0, 100.0, 5.0], options=OPTIONS, client=client)
    rows = {r["speed"]: r for r in result.to_pylist()}
    assert rows[100.0]["status"] == "failed"
    assert "longitudinal_cyclic" in rows[100.0]["message"] and "outside its range" in rows[100.0]["message"]
    assert rows[100.0]["collective"] is None
    assert [rows[v]["status"] for v in (0.0, 5.0)] == ["ok", "ok"]
    assert rows[5.0]["collective"] == plain_loop[5.0]["collective"]
    assert "; warning: horizontal tail: angle of attack" in rows[5.0]["message"]  # the trim's warnings, kept


def test_resume_computes_exactly_the_deleted_points(client, tmp_path):
    first = sweep.trim_sweep(SCENE, SPEEDS[:4], options=OPTIONS, client=client, out=tmp_path)
    assert {p.name for p in tmp_path.iterdir()} >= {"results.parquet", "results.csv", "trim_controls.png",
                                                     "trim_attitude.png"}
    saved = pq.read_table(tmp_path / "results.parquet")
    pq.write_table(saved.take([0, 2]), tmp_path / "results.parquet")  # delete the rows of 1 and 3 m/s
    computed = []
    again = sweep.trim_sweep(SCENE, SPEEDS[:4], options=OPTIONS, client=client, out=tmp_path,
                             progress=lambda done, total: computed.append(total))
    assert sweep.run_info(again) == {**sweep.run_info(again), "computed": 2, "reused": 2}
    assert set(computed) == {2} and len(computed) == 2
    assert _results(again) == _results(first)
    assert sweep.run_info(sweep.trim_sweep(SCENE, SPEEDS[:4], options=OPTIONS, client=client,
                                           out=tmp_path))["computed"] == 0


def test_resume_refuses_a_folder_of_another_sweep(tmp_path):
    result = sweep.trim_sweep(SCENE, [0.0], options=OPTIONS, workers=0, out=tmp_path)
    assert result.num_rows == 1
    with pytest.raises(ValueError, match=r"holds a different sweep \(steps_per_rev: 50 there, 40 now\)"):
        sweep.trim_sweep(SCENE, [0.0], options={"steps_per_rev": 40}, workers=0, out=tmp_path)


def test_a_speed_range_takes_a_unit_as_trim_s_speed_does():
    """'heli trim --speed 60kt' worked, 'heli sweep trim --speed 0kt:100kt:3' did not (a new user):
    a unit on either end (on one, both's) or on none (m/s); the range checked in m/s."""
    from mbs.arguments import parse_speeds, speed_ends

    kt = 1852 / 3600
    for text in ("0kt:100kt:3", "0:100kt:3", "0 kt:100 kt:3"):
        assert grid.parse_range("--speed", text, speed_ends) == pytest.approx([0, 50 * kt, 100 * kt])
        assert parse_speeds(text) == pytest.approx([0, 50 * kt, 100 * kt])
    assert grid.parse_range("--speed", "0:60:3", speed_ends) == pytest.approx([0, 30, 60])
    with pytest.raises(ValueError, match=r"--speed '0:300kt:3': 300kt \(154.3 m/s\) is outside the flight speeds"):
        grid.parse_range("--speed", "0:300kt:3", speed_ends)


def test_bad_ranges_and_axes_are_named():
    with pytest.raises(ValueError, match=r"--speed '0:70' must be LO:HI:N"):
        grid.parse_range("--speed", "0:70")
    with pytest.raises(ValueError, match=r"--param 'collective' must be NAME=LO:HI:N"):
        grid.parse_axis("--param", "collective")
    with pytest.raises(ValueError, match=r"cannot sweep 'collective' in a trim sweep of 'hover'"):
        sweep.trim_sweep(SCENE, [0.0], {"collective": [0.2]}, options=OPTIONS, workers=0)
    assert grid.points({"a": np.array([1.0, 2.0]), "b": np.array([3.0])}) == [{"a": 1.0, "b": 3.0},
                                                                              {"a": 2.0, "b": 3.0}]


def test_heli_sweep_trim_writes_the_table_and_charts_and_reports_json(tmp_path, capsys):
    import json

    from mbs.cli import main

    argv = ["sweep", "trim", SCENE, "--speed", "0:0:1", "--steps-per-rev", "50", "--workers", "0", "--out",
            str(tmp_path), "--quiet", "--json"]
    assert main(argv) == 0
    res = json.loads(capsys.readouterr().out)  # stdout is the JSON object alone
    assert (res["points"], res["ok"], res["computed"], res["reused"]) == (1, 1, 1, 0)
    assert {p.rsplit("/", 1)[-1] for p in res["files"]} == {"results.parquet", "results.csv", "trim_controls.png",
                                                          "trim_attitude.png", "trim_power.png", "trim_summary.png"}
    with pytest.raises(SystemExit) as bad:
        main(argv[:4] + ["0:70"])
    assert bad.value.code == 2 and "--speed '0:70' must be LO:HI:N" in capsys.readouterr().err


def test_table_columns_are_inputs_outputs_then_status():
    t = table.build([{"speed": 1.0, "status": "failed", "message": "m", "wall_s": 0.1},
                     {"speed": 0.0, "collective": 0.2, "status": "ok", "message": "", "wall_s": 0.2}],
                    ["speed"], {"kind": "trim"})
    assert t.column_names == ["speed", "collective", "status", "message", "wall_s"]
    assert t.column("speed").to_pylist() == [0.0, 1.0]
    assert table.settings_of(t) == {"kind": "trim"}
