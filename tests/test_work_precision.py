"""``heli bench work-precision``: every method in the data file, failures marked, RK4 reaching
a hinge-angle error of 1e-6 rad on both Bo105 scenes, and the interpolation at equal error."""
import contextlib
import csv
import io
import json
import math

import pytest

from mbs.bench import work_precision as wp
from mbs.cli import main
from mbs.solvers import METHODS


@pytest.fixture(scope="module")
def quick(tmp_path_factory):
    """The quick sweeps of both scenes through the command line, one timed run per point;
    returns the output folder and the JSON object printed last."""
    out = tmp_path_factory.mktemp("wp")
    buf = io.StringIO()
    with contextlib.redirect_stdout(buf):
        code = main(["bench", "work-precision", "--quick", "--repeats", "1", "--out", str(out), "--json"])
    assert code == 0
    return out, json.loads(buf.getvalue())  # stdout is the JSON object alone


def _rows(path) -> list[dict]:
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


@pytest.mark.parametrize("scene", ["structural", "forward-flight"])
def test_chart_and_data_file_hold_every_method_and_rk4_reaches_1e_6_rad(quick, scene):
    out, printed = quick
    res = printed["scenes"][scene]
    rows = _rows(res["files"]["csv"])
    assert {r["method"] for r in rows} == set(METHODS)
    assert (out / f"work_precision_{scene}.png").stat().st_size > 20_000
    rk4 = [r for r in rows if r["method"] == "rk4" and r["status"] == "success"]
    assert min(float(r["error_rad"]) for r in rk4) < 1e-6
    # the reference agrees with the much finer RK4 run far below the errors charted
    assert res["reference"]["agreement_rad"] < 1e-9
    # RK4 converges at 4th order between 80 and 320 steps per revolution
    err = {int(float(r["value"])): float(r["error_rad"]) for r in rk4}
    assert 3.5 < math.log(err[80] / err[320], 4) < 4.5, err
    for r in rows:
        assert r["nfev"] and float(r["wall_s"]) > 0


def test_failed_runs_are_marked_not_dropped(quick):
    """RK4 at 20 steps per revolution is past the structural scene's limit (about 31)."""
    res = quick[1]["scenes"]["structural"]
    rows = _rows(res["files"]["csv"])
    failed = [r for r in rows if r["status"] != "success"]
    assert any(r["method"] == "rk4" and r["value"] == "20.0" and r["status"] == "nonfinite" for r in failed)
    assert all(r["error_rad"] == "inf" and r["message"] for r in failed)
    assert {(p["method"], p["value"]) for p in res["omissions"]} == {(r["method"], float(r["value"])) for r in failed}


def _point(err, wall, status="success"):
    return wp.Point("m", "fixed", "steps", 1.0, status, err, err, wall, 1, 0, 1, "")


def test_time_at_interpolates_log_log_between_the_bracketing_points():
    pts = [_point(1e-4, 1.0), _point(1e-8, 100.0), _point(math.inf, 0.1, "nonfinite")]
    assert wp.time_at(pts, 1e-6) == pytest.approx(10.0)
    assert wp.time_at(pts, 1e-3) == pytest.approx(1.0)
    assert wp.time_at(pts, 1e-9) is None


def test_bad_span_and_repeats_are_refused():
    with pytest.raises(ValueError, match="revs = 0.33"):
        wp.run_scene(None, "x", 0.33, 0.1)
    with pytest.raises(ValueError, match="repeats = 0"):
        wp.run_scene(None, "x", 1.0, 0.1, repeats=0)
