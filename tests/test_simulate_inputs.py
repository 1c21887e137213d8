"""``heli simulate --set NAME=VALUE`` and ``--inputs FILE``: a run with set or scheduled inputs
equals a run with the same values held step by step (one driver call per step, inputs written
by hand here), the FMU demo's input table gives the FMU's core twin's run
(:func:`fmu.hosts.run_core`), the initial speed is level flight at that speed, and the inputs
come back from the results folder (``run.json`` and the CSV columns the viewer reads)."""
from __future__ import annotations

import json

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

from mbs import cli, scenes
from mbs.inputs import InputTable, read_table, stretch_starts
from mbs.simulate import prepare, simulate

CONTROLS = ["collective", "lateral_cyclic", "longitudinal_cyclic", "tail_collective"]


def columns(csv_path):
    """The columns of a results table by name (numpy keeps the dots in the names)."""
    return np.genfromtxt(csv_path, delimiter=",", names=True, deletechars="")


def run_main(argv: list[str], capsys) -> tuple[int, str, str]:
    code = cli.main(argv)
    captured = capsys.readouterr()
    return code, captured.out, captured.err


def test_set_controls_and_parameters_equal_the_run_with_those_parameters(tmp_path, capsys):
    code, out, err = run_main(["simulate", "hover", "--set", "collective=0.25", "--set", "omega=42",
                               "--out", str(tmp_path), "--quiet", "--json", "--start", "scene"], capsys)
    assert code == 0, err
    res = json.loads(out)
    assert res["set"] == {"collective": 0.25, "omega": 42.0}
    assert res["parameters"]["collective"] == 0.25 and res["parameters"]["omega"] == 42.0
    ref = simulate("hover", 1.0, params={"collective": 0.25, "omega": 42.0})
    data = columns(tmp_path / "results.csv")
    assert data["time"][-1] == pytest.approx(2 * np.pi / 42.0, rel=1e-14)  # the revolution at the set omega
    for name in ("blade1.flap", "blade3.lag", "seesaw.teeter", "fuselage.w"):
        np.testing.assert_array_equal(data[name], ref.traj.column(name))
    assert json.loads((tmp_path / "run.json").read_text())["set"] == res["set"]


def test_set_speed_starts_in_level_flight_at_that_speed(tmp_path, capsys):
    """``speed=V``: the body velocity ``R(q0)^T (V, 0, 0)`` (the FMU's ``initial_forward_speed``):
    in the ground frame the fuselage moves at V along x, at the start's attitude; the controls
    stay the scene's (its trim at 10 m/s), which a warning says."""
    code, out, err = run_main(["simulate", "forward-flight", "--set", "speed=25", "--revs", "0.1",
                               "--out", str(tmp_path), "--quiet", "--start", "scene"], capsys)
    assert code == 0, err
    assert ("warning: --set speed=25: the run starts at 25 m/s with the attitude and controls of scene "
            "'forward-flight' at 10 m/s") in err and "starts from the periodic trim at 25 m/s" in err
    data = columns(tmp_path / "results.csv")
    q = [data[f"fuselage.q{a}"][0] for a in "wxyz"]
    v = [data[f"fuselage.{a}"][0] for a in "uvw"]
    ground = Rotation.from_quat([q[1], q[2], q[3], q[0]]).apply(v)  # body -> ground (scipy: scalar last)
    np.testing.assert_allclose(ground, [25.0, 0.0, 0.0], atol=1e-12)
    default = simulate("forward-flight", 0.01)
    assert [data[f"fuselage.q{a}"][0] for a in "wxyz"] == [default.traj.column(f"fuselage.q{a}")[0] for a in "wxyz"]


def _hand_held(t: float) -> dict:
    """The inputs of TABLE (below) at a step starting at ``t`` s, written out by hand: collective
    0.24 rad, 0.26 from 0.05 s on; longitudinal cyclic 0 until 0.02 s, then a ramp to 0.01 rad at
    0.08 s, then held."""
    ramp = np.clip((t - 0.02) / 0.06, 0.0, 1.0) * 0.01
    return {"collective": 0.26 if t >= 0.05 - 1e-15 else 0.24, "longitudinal_cyclic": float(ramp)}


TABLE = ("time,collective,longitudinal_cyclic\n0,0.24,0\n0.02,0.24,0\n0.05,0.24,0.005\n0.05,0.26,0.005\n"
         "0.08,0.26,0.01\n")


def test_an_input_table_equals_the_run_with_the_inputs_held_step_by_step(tmp_path):
    """A jump (0.05 s, between two step starts) and a ramp, rows every 3rd step: every recorded
    row equals a run of one driver call per step with the inputs of :func:`_hand_held`."""
    path = tmp_path / "inputs.csv"
    path.write_text(TABLE)
    run = prepare("hover", 1.0, inputs=read_table(path), every=3)
    sim = run.execute()
    system, h, n = run.system, run.h, run.steps
    x, rows = run.x0, [run.x0]
    for k in range(n):
        x = system.run(x, k * h, h, 1, p=system.params(run.p, **_hand_held(k * h))).x[-1]
        rows.append(x)
    kept = [k for k in range(n + 1) if k % 3 == 0 or k == n]
    np.testing.assert_allclose(sim.traj.t, np.array(kept) * h, rtol=1e-15)
    np.testing.assert_allclose(sim.traj.x, np.array(rows)[kept], rtol=0, atol=1e-12)
    for name in ("collective", "longitudinal_cyclic"):  # the results columns: the inputs from each row on
        held = [_hand_held(min(k, n - 1) * h)[name] for k in kept]
        np.testing.assert_allclose(sim.columns()[name], held, rtol=0, atol=1e-15)
    assert any("the jump at t = 0.05 s acts at the next step start" in w for w in run.warnings)


def test_the_fmu_demos_input_table_gives_the_run_of_the_fmus_core_twin(tmp_path, capsys):
    """:func:`fmu.hosts.pitch_schedule` (a collective step and a cyclic doublet, switches on the
    communication grid) written as CSV and run by ``heli simulate --inputs`` equals
    :func:`fmu.hosts.run_core`, the FMU's computation with the core (communication step 2 h,
    two sub-steps each)."""
    hosts = pytest.importorskip("fmu.hosts")
    sc = scenes.get("forward-flight")
    system = sc.system()
    p = system.params()
    h = sc.revolution(system, p) / sc.steps_per_rev
    defaults = {n: float(p[system.info.param_names.index(n)]) for n in CONTROLS}
    table = hosts.pitch_schedule(defaults, 2 * h, 50, revs=(0.2, 0.4, 0.5, 0.6))
    path = tmp_path / "demo_inputs.csv"
    np.savetxt(path, np.column_stack([table[n] for n in table.dtype.names]), delimiter=",",
               header=",".join(table.dtype.names), comments="", fmt="%.17g")
    code, out, err = run_main(["simulate", "forward-flight", "--inputs", str(path), "--out", str(tmp_path / "run"),
                               "--quiet", "--json", "--start", "scene"], capsys)
    assert code == 0, err
    assert "warning" not in err
    twin = hosts.run_core("forward-flight", hosts.grid(100 * h, 2 * h), table, max_step=h,
                          names=system.info.state_names)
    data = columns(tmp_path / "run" / "results.csv")
    np.testing.assert_allclose(data["time"][2::2], twin["time"], rtol=1e-14)
    for name in system.info.state_names:
        np.testing.assert_allclose(data[name][2::2], twin[name], rtol=0, atol=1e-11, err_msg=name)
    res = json.loads(out)
    assert res["inputs"]["columns"] == CONTROLS and res["inputs"]["rows"] == hosts.table_rows(table)
    assert data["collective"][0] == defaults["collective"]
    assert data["collective"][-1] == pytest.approx(defaults["collective"] + 0.02, abs=1e-15)


def test_the_viewer_reads_the_inputs_back_from_the_results_folder(tmp_path, capsys):
    from viewer import from_results
    from viewer.series import input_panels

    path = tmp_path / "inputs.csv"
    path.write_text(TABLE)
    assert run_main(["simulate", "hover", "--inputs", str(path), "--out", str(tmp_path / "run"), "--quiet"],
                    capsys)[0] == 0
    meta = json.loads((tmp_path / "run" / "run.json").read_text())
    assert meta["inputs"]["file"] == str(path) and "linear between rows" in meta["inputs"]["interpolation"]
    rec = from_results(tmp_path / "run")
    data = columns(tmp_path / "run" / "results.csv")
    for name in ("collective", "longitudinal_cyclic"):
        np.testing.assert_array_equal(rec.P[:, rec.info.param_names.index(name)], data[name])
    assert "longitudinal_cyclic" in input_panels(rec)["cyclic pitch (rad)"]


def test_rows_after_the_end_of_the_run_are_said(tmp_path, capsys):
    path = tmp_path / "inputs.csv"
    path.write_text("time,collective\n0,0.24\n10,0.25\n")
    code, out, err = run_main(["simulate", "hover", "--inputs", str(path), "--revs", "0.5", "--out", str(tmp_path),
                               "--quiet"], capsys)
    assert code == 0
    assert f"warning: --inputs {path}: 1 row(s) after the end of the run (t = 0.0707" in err


@pytest.mark.parametrize("seed", range(20))
def test_stretches_hold_what_the_table_gives_at_every_step(seed):
    """The stretches of equal inputs (:func:`mbs.inputs.stretch_starts`) of random tables with
    jumps, ramps, flat parts and rows off the step grid: at every step the table's value equals
    the value at the start of its stretch."""
    rng = np.random.default_rng(seed)
    t = np.sort(np.round(rng.uniform(0, 1.0, 8), 2 if seed % 2 else 4))
    t = np.r_[0.0, np.repeat(t, rng.integers(1, 3, len(t)))]
    values = rng.choice([0.1, 0.2, 0.3], size=(len(t), 2))
    table = InputTable(t, ["a", "b"], values)
    h, n = 0.0137, 90
    starts = stretch_starts(table, h, n)
    at_steps = table.at(h * np.arange(n))
    owner = np.searchsorted(starts, np.arange(n), side="right") - 1
    np.testing.assert_array_equal(at_steps, table.at(h * starts)[owner])


@pytest.mark.parametrize("table, line", [
    ("time,omega\n0,44.4\n0.5,40\n", 3),          # a ramp: azimuth omega(t) t would turn the rotor too slowly
    ("time,omega\n0,44.4\n0.1,44.4\n0.1,40\n", 4),  # a step: omega(t) t would jump the azimuth back
])
def test_an_omega_column_that_changes_is_refused(tmp_path, capsys, table, line):
    """The driven hubs turn at ``omega t``: a rotor speed changing within a run would be
    integrated wrong, so the column is refused with what to do instead (before anything is
    built); a constant column is the run of ``--set omega``."""
    path = tmp_path / "omega.csv"
    path.write_text(table)
    code, out, err = run_main(["simulate", "ground-run", "--inputs", str(path), "--out", str(tmp_path / "o")], capsys)
    lines = err.strip().splitlines()
    assert code == 2 and len(lines) == 1, err
    assert f"column 'omega' changes from 44.4 to 40 (line {line})" in lines[0]
    assert "--set omega=VALUE" in lines[0] and "heli sweep simulate ground-run --param omega=LO:HI:N" in lines[0]
    assert not (tmp_path / "o").exists()


def test_a_constant_omega_column_is_refused_for_set(tmp_path, capsys):
    """Even a constant column: the step and the revolutions of --revs are the rotor speed's."""
    path = tmp_path / "omega.csv"
    path.write_text("time,omega\n0,40\n1,40\n")
    code, out, err = run_main(["simulate", "ground-run", "--inputs", str(path)], capsys)
    assert code == 2 and "column 'omega' is an input table column" in err and "--set omega=VALUE" in err
