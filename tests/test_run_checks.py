"""Nothing silently wrong in ``heli simulate`` and ``heli view``: a step too coarse is said with the
step that would do (the step-doubling estimate checked against a fine reference), a run's time
and size are said first and a too large one refused, progress shows the time left, a --revs
that is no whole number of steps is said, every results column has its unit, and a results
folder of an --aero or --aircraft run opens as that model."""
from __future__ import annotations

import json
import re

import numpy as np
import pytest

from mbs import cli, run_cost, scenes
from mbs.simulate import prepare, simulate


def run_main(argv: list[str], capsys) -> tuple[int, str, str]:
    code = cli.main(argv)
    captured = capsys.readouterr()
    return code, captured.out, captured.err


# -- the step ---------------------------------------------------------------------------------------------

def test_a_coarse_step_is_said_with_the_step_that_would_do(tmp_path, capsys):
    """forward-flight at 10 steps/rev (the tail rotor's teeter and inflow go wild) reported
    success before; now a warning names the state, the estimate and the step that would do."""
    code, out, err = run_main(["simulate", "forward-flight", "--steps-per-rev", "10", "--out", str(tmp_path),
                               "--quiet", "--start", "scene"], capsys)
    assert code == 0
    warning = [line for line in err.splitlines() if "warning" in line]
    assert len(warning) == 1 and warning[0].startswith(
        "heli simulate: warning: 10 rk4 steps per revolution are too coarse: estimated step error")
    named = re.search(r"of the range of (\S+) over", warning[0]).group(1)
    suggested = int(re.search(r"use --steps-per-rev (\d+) or more", warning[0]).group(1))
    assert named.startswith(("seesaw.", "tail_rotor.")) and 40 <= suggested <= 100  # measured 70-80
    assert "result: the run reached its end time (but the step is too coarse: see the warning)" in out
    step = json.loads((tmp_path / "run.json").read_text())["step_error"]
    assert not step["ok"] and step["suggested_steps_per_rev"] == suggested and step["ratio"] > 1
    code, out, err = run_main(["simulate", "forward-flight", "--steps-per-rev", str(suggested), "--out",
                               str(tmp_path), "--quiet", "--start", "scene"], capsys)
    assert "warning" not in err and json.loads((tmp_path / "run.json").read_text())["step_error"]["ok"]


@pytest.mark.parametrize("steps_per_rev", [25, 50])
def test_the_step_error_estimate_is_the_error_against_a_fine_reference(steps_per_rev):
    """The Richardson estimate of the worst state's error over the first revolution is within
    25 % of its error against RK4 at 1600 steps/rev; the suggested step passes the check."""
    run = prepare("forward-flight", 1.0, steps_per_rev)
    est = run.check_step()
    ref = simulate("forward-flight", 1.0, 1600, system=run.system)
    i = run.system.info.state_names.index(est.state)
    coarse = run.system.run(run.x0, 0.0, run.h, steps_per_rev, p=run.p).x[:, i]
    true = np.abs(coarse - ref.traj.x[:: 1600 // steps_per_rev, i]).max()
    assert est.error == pytest.approx(true, rel=0.25)
    if not est.ok:
        assert prepare("forward-flight", 1.0, est.suggested_steps_per_rev).check_step().ok


# -- time and size ---------------------------------------------------------------------------------------

def test_the_size_estimate_is_the_size_written(tmp_path, capsys):
    run = prepare("hover", 3.0, every=2)
    cost = run.cost()
    assert (cost.steps, cost.rows) == (300, 151)
    code, out, err = run_main(["simulate", "hover", "--revs", "3", "--every", "2", "--out", str(tmp_path), "--quiet",
                               "--json"], capsys)
    written = (tmp_path / "results.csv").stat().st_size
    assert json.loads(out)["cost"]["rows"] == 151 == len((tmp_path / "results.csv").read_text().splitlines()) - 1
    assert cost.size_bytes == pytest.approx(written, rel=0.1)


def test_a_run_beyond_the_size_limit_is_refused_with_the_every_that_fits(tmp_path, capsys):
    argv = ["simulate", "hover", "--revs", "20", "--max-gb", "0.0005", "--out", str(tmp_path), "--quiet"]
    code, out, err = run_main(argv, capsys)
    assert code == 2 and list(tmp_path.iterdir()) == []
    assert re.search(r"results.csv would be about \d\.\d+ MB \(2001 rows of \d+ columns\) and the run would take about",
                     err) and "more than --max-gb 0.0005" in err
    every = int(err.split("--every ")[1].split()[0])
    code, out, err = run_main([*argv, "--every", str(every)], capsys)
    assert code == 0 and (tmp_path / "results.csv").stat().st_size <= 0.0005e9


def test_a_long_run_says_its_time_and_size_first(tmp_path, capsys, monkeypatch):
    monkeypatch.setattr(run_cost, "SAY_ABOVE_S", 0.0)
    code, out, err = run_main(["simulate", "hover", "--out", str(tmp_path), "--quiet"], capsys)
    assert code == 0
    said = [line for line in err.splitlines() if line.startswith("heli simulate: 100 steps, about ")]
    assert len(said) == 1 and re.search(r"results.csv about \d+ kB \(101 rows of \d+ columns\)", said[0]), said


class _Terminal(__import__("io").StringIO):
    def isatty(self) -> bool:
        return True


def test_progress_into_a_file_is_a_line_a_tenth_without_carriage_returns(monkeypatch):
    """A new user's redirected 'heli trim' output held long lines of redrawn bars: into a file or
    a pipe the bar is a whole line at each tenth done and at the end, and nothing is erased."""
    import io

    from mbs import _progress

    clock = iter(float(t) for t in range(100))
    monkeypatch.setattr(_progress.time, "perf_counter", lambda: next(clock))
    stream = io.StringIO()
    bar = _progress.Progress("sweep", stream=stream)
    for done in range(0, 21):
        bar(done, 20)
    _progress.clear()
    lines = stream.getvalue().splitlines()
    assert "\r" not in stream.getvalue() and len(lines) == 11, lines
    assert lines[-1].startswith("sweep [") and "100.0%" in lines[-1]


def test_progress_shows_the_time_left(monkeypatch):
    import io

    from mbs import _progress

    clock = iter([0.0, 5.0, 7.0, 9.0])
    monkeypatch.setattr(_progress.time, "perf_counter", lambda: next(clock))
    stream = _Terminal()
    bar = _progress.Progress("simulate hover", stream=stream)
    bar(0, 100)  # after 5 s of set-up
    bar(25, 100)  # 2 s for a quarter: 6 s left
    assert "25.0%" in stream.getvalue() and "about 6 s left" in stream.getvalue()
    bar(100, 100)
    assert stream.getvalue().endswith("\n") and stream.getvalue().count("left") == 1


def test_progress_does_not_count_the_set_up_as_work_to_come(monkeypatch):
    """A trim's first iteration reports after a minute of compiling; its next one a second later:
    about 17 s left for the 17 iterations to come, not 17 minutes; a bar left unfinished (the trim
    converged early) is erased before the next line."""
    import io

    from mbs import _progress

    clock = iter([0.0, 60.0, 61.0, 62.0])
    monkeypatch.setattr(_progress.time, "perf_counter", lambda: next(clock))
    stream = _Terminal()
    bar = _progress.Progress("trim hover", stream=stream)
    bar(1, 20)
    bar(2, 20)
    assert "about 18 s left" in stream.getvalue() and "min" not in stream.getvalue()
    bar(3, 20)
    _progress.clear()
    assert stream.getvalue().endswith("\r" + " " * bar.width + "\r")


def test_revs_that_are_no_whole_number_of_steps_are_said(tmp_path, capsys):
    code, out, err = run_main(["simulate", "hover", "--revs", "1.234", "--out", str(tmp_path), "--quiet"], capsys)
    assert code == 0
    assert ("warning: --revs 1.234 is 123.4 steps at 100 steps per revolution: running 123 steps (1.23 revolutions)"
            in err)
    meta = json.loads((tmp_path / "run.json").read_text())
    assert meta["revs"] == 1.23 and meta["steps"] == 123


# -- units --------------------------------------------------------------------------------------------------

def test_every_results_column_has_its_unit_in_run_json(tmp_path, capsys):
    assert run_main(["simulate", "hover", "--out", str(tmp_path), "--quiet"], capsys)[0] == 0
    units = json.loads((tmp_path / "run.json").read_text())["units"]
    header = (tmp_path / "results.csv").read_text().split("\n", 1)[0].split(",")
    assert list(units) == header and all(units.values())
    assert {k: units[k] for k in ("time", "fuselage.x", "fuselage.qw", "fuselage.u", "fuselage.p", "blade1.flap",
                                  "blade1.lag_rate", "seesaw.teeter", "main_rotor.inflow", "main_rotor.thrust",
                                  "main_rotor.torque", "main_rotor.power", "total_energy")} == {
        "time": "s", "fuselage.x": "m", "fuselage.qw": "1", "fuselage.u": "m/s", "fuselage.p": "rad/s",
        "blade1.flap": "rad", "blade1.lag_rate": "rad/s", "seesaw.teeter": "rad", "main_rotor.inflow": "m/s",
        "main_rotor.thrust": "N", "main_rotor.torque": "N m", "main_rotor.power": "W", "total_energy": "J"}
    ground = prepare("ground-resonance", 0.1).units  # a slider: metres
    assert ground["fuselage.lateral"] == "m" and ground["fuselage.lateral_rate"] == "m/s"
    assert ground["fuselage.roll"] == "rad" and ground["lag_damping"] == "N m s/rad"


# -- heli view: the run's own model, problems before any work ------------------------------------------------

@pytest.mark.parametrize("extra", [["--aero", "none"], ["--aircraft", "lynx"]])
def test_view_opens_the_model_the_run_was_made_with(extra, tmp_path, capsys):
    from viewer import from_results

    assert run_main(["simulate", "hover", "--revs", "0.2", *extra, "--out", str(tmp_path), "--quiet", "--start", "scene"],
                    capsys)[0] == 0
    rec = from_results(tmp_path)
    data = (tmp_path / "results.csv").read_text().split("\n", 1)[0].split(",")
    assert rec.info.state_names == data[1:1 + rec.info.nx]
    want = scenes.get("hover").with_aircraft("lynx") if extra[0] == "--aircraft" else None
    if want is not None:
        assert rec.info.bodies[0]["mass"] == want.system("vm").info.bodies[0]["mass"] != \
            scenes.get("hover").system("vm").info.bodies[0]["mass"]


def test_view_refuses_a_diverged_run_before_building_anything(tmp_path, capsys, monkeypatch):
    code, out, err = run_main(["simulate", "forward-flight", "--steps-per-rev", "7", "--revs", "3",
                               "--out", str(tmp_path), "--quiet", "--start", "scene"], capsys)
    assert code == 1 and "non-finite" in out

    def no_build(*args, **kwargs):
        raise AssertionError("the model was built")

    monkeypatch.setattr(scenes.Scene, "system", no_build)
    code, out, err = run_main(["view", str(tmp_path)], capsys)
    assert code == 2 and "the run stopped before its end (the state became non-finite" in err
