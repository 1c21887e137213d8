"""Every chart and every report says what it shows: scene, aircraft and speed; and only what
happened (the demo's inputs, the co-simulation's events), on axes that fit the run."""
from __future__ import annotations

import numpy as np
import pytest

from mbs import cli


@pytest.fixture
def titles(monkeypatch) -> list[str]:
    """The titles of the charts drawn (``Figure.suptitle`` and ``Axes.set_title``)."""
    import matplotlib.axes
    import matplotlib.figure

    seen: list[str] = []
    for cls, name in ((matplotlib.figure.Figure, "suptitle"), (matplotlib.axes.Axes, "set_title")):
        original = getattr(cls, name)
        monkeypatch.setattr(cls, name, lambda self, text, *a, _o=original, **k: (seen.append(text), _o(self, text, *a,
                                                                                                        **k))[1])
    return seen


def test_simulate_names_aircraft_scene_and_speed(tmp_path, capsys, titles):
    assert cli.main(["simulate", "hover", "--aircraft", "lynx", "--revs", "0.1", "--start", "scene", "--quiet",
                     "--out", str(tmp_path)]) == 0
    out = capsys.readouterr().out.splitlines()
    assert out[0].startswith("hover of the Westland Lynx at 0 m/s: 0.1 revolutions")
    assert out[1].startswith("start: the scene's initial state")
    assert titles == ["hover of the Westland Lynx at 0 m/s: hinge angles (rk4, 100 steps/rev)"]


def test_sweep_charts_name_the_aircraft(tmp_path, titles):
    from mbs import aircraft
    from mbs.sweep import charts, table

    puma = aircraft.load("puma")
    rows = [{"speed": v, "status": "ok", "collective": 0.2 + v / 1e3, "roll": -0.01, "pitch": 0.02} for v in (0, 10)]
    settings = {"kind": "trim", "scene": "hover", "axes": ["speed"],
                "options": {"aircraft": {"file": str(puma.path), "sha256": puma.digest}}}
    charts.write("trim", table.build(rows, ["speed"], settings), ["speed"], tmp_path)
    main = [t for t in titles if t.startswith("hover")]
    assert len(main) == 3 and all(t.startswith(f"hover of the {puma.name}, trimmed") for t in main)


def test_the_demos_title_names_only_the_inputs_that_happen():
    from fmu import demo, hosts

    table = hosts.pitch_schedule({"collective": 0.2, "lateral_cyclic": 0.0, "longitudinal_cyclic": 0.0,
                                  "tail_collective": 0.1}, 0.0014, 100)
    rev = 0.14
    assert demo._inputs_seen(table, 1.5 * rev) == "trim inputs held (the run ends before the first input)"
    assert demo._inputs_seen(table, 3 * rev) == "collective step"
    assert demo._inputs_seen(table, 10 * rev) == "collective step and longitudinal-cyclic doublet"
    assert "its start: the run ends before the rest" in demo._inputs_seen(table, 4.5 * rev)


def _cosim_run(stop: float) -> dict:
    t = np.linspace(0.0, stop, 50)
    small = 0.01 * np.sin(t)
    res = {"time": t, **{f"fuselage.{c}": small for c in ("roll", "pitch", "x", "y", "z")}}
    from fmu import controller

    res.update({c: small for c in controller.OUTPUTS})
    return res


def test_cosim_says_when_nothing_happened_and_its_axes_fit_a_short_run(tmp_path, monkeypatch, capsys):
    from fmu import cosim

    closed = _cosim_run(5.0)
    trim = {f"fuselage.{c}": 0.0 for c in ("roll", "pitch", "x", "y", "z")}
    path = cosim.plot(closed, closed, trim, tmp_path / "c.png", "MBB Bo105")
    assert path.stat().st_size > 10_000
    fake = {"stop_s": 5.0, "step_s": 0.0014, "steps": 3500, "libcosim_vs_fmpy_max_abs": 0.0, "algebraic_loops": [],
            "algebraic_loops_without_dependencies": 2, "libcosim_wall_s": 1.0, "fmpy_wall_s": 2.0, "files": {},
            "closed": {"max_attitude_deg": 0.5, "attitude_within_2deg_after_s": 0.0, "max_drift_m": 0.1},
            "open": {"attitude_beyond_2deg_s": None, "attitude_beyond_20deg_s": None, "drift_beyond_5m_s": 4.25},
            "fmpy_ssp_runner": {"completed": False, "refused": ["collective = 0.0 is below its range"], "error": None}}
    monkeypatch.setattr(cosim, "run", lambda *a, **k: fake)
    assert cli.main(["cosim", "--stop", "5", "--out", str(tmp_path / "o"), "--json"]) == 0
    err = capsys.readouterr().err
    assert "None" not in err and "attitude beyond 2 deg not within the 5 s run" in err and "at 4.25 s" in err
    assert err.startswith("MBB Bo105, hover")


def test_cosim_plot_autoscales(tmp_path, monkeypatch):
    from fmu import cosim

    drawn = []
    monkeypatch.setattr(cosim.atomic, "savefig", lambda fig, path, **k: drawn.append([a.get_ylim() for a in fig.axes]))
    closed = _cosim_run(5.0)
    cosim.plot(closed, closed, {f"fuselage.{c}": 0.0 for c in ("roll", "pitch", "x", "y", "z")}, tmp_path / "c.png")
    attitude, position = drawn[0][0], drawn[0][1]
    assert max(map(abs, attitude)) < 1.0 and max(map(abs, position)) < 0.1  # the small motion fills them (±25, ±60)
