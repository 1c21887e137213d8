"""Loads along the span of elastic blades (one value per segment joint) and the charts that
show the loads: spanwise, and the engine power in the trim sweep's power chart."""
from __future__ import annotations

from dataclasses import replace

import numpy as np
import pyarrow as pa
import pytest

from mbs import scenes
from mbs.loads import files
from mbs.loads.analysis import rotor_loads
from mbs import aircraft
from mbs.models import helicopter
from mbs.models.helicopter.scenes import ELASTIC_ROTOR
from mbs.flexible.uniform_blade import blade_from_data
from mbs.models.elastic_blade import layout
from mbs.sweep import charts as sweep_charts


def test_tension_along_an_elastic_blade_is_the_centrifugal_force_outboard():
    """At the start of elastic-rotor (straight blades, coned 0.03 rad, hub turning): the pull
    at segment ``j``'s joint is the centrifugal force of the blade outboard of it,
    ``m' Ω² (R² - r_j²) / 2``, within the coning's cos² β and the weight (0.2 %)."""
    system = scenes.get("elastic-rotor").system("vm")
    y = dict(zip(system.info.output_names, system.outputs(system.x0(), 0.0)))
    d = aircraft.load().data
    blade, omega = blade_from_data(d), d["main_rotor"]["omega"]
    radii = layout(blade, 8)[0]
    for j in range(2, 9):
        pull = -y[f"blade1.station{j}.force_x"]
        assert pull == pytest.approx(blade.mass * omega**2 * (blade.tip**2 - radii[j - 1] ** 2) / 2, rel=3e-3), j


@pytest.fixture(scope="module")
def two_segments():
    """The elastic rotor with blades of 2 segments (cheap to trim), at its periodic solution."""
    cfg = replace(ELASTIC_ROTOR, blade_segments=2)

    def make(aircraft=None, **options):
        return helicopter.build(replace(cfg, **options), aircraft, name="bo105-elastic-rotor-2")
    make.config = cfg
    return rotor_loads(scenes.Scene("elastic-rotor-2", "elastic rotor, 2 segments", make, omega=44.4,
                                    aircraft=aircraft.load()))


def test_spanwise_loads_per_segment_joint_and_their_chart(two_segments, tmp_path):
    res = two_segments
    rows = res.span_rows()
    assert [r["station"] for r in rows] == ["blade1.root", "blade1.station2"]
    d = aircraft.load().data
    np.testing.assert_allclose([r["radius"] for r in rows], layout(blade_from_data(d), 2)[0], rtol=1e-12)
    assert rows[0]["flap_mean"] > rows[1]["flap_mean"] > 0  # bending grows inboard; lift bends the tips up
    written = [p.name for p in files.write(res, tmp_path)]
    assert "spanwise_elastic-rotor-2_0ms.png" in written and (tmp_path / written[-1]).stat().st_size > 10_000


def test_the_trim_sweep_power_chart_shows_the_engine_power(tmp_path, monkeypatch):
    drawn = {}

    def capture(rows, names, panels, scale, ylabel, path, title):
        drawn[path.name] = panels
        return path
    monkeypatch.setattr(sweep_charts, "_line_chart", capture)
    monkeypatch.setattr(sweep_charts, "_trim_summary", lambda rows, names, controls, power, path, what: drawn.setdefault(
        path.name, power) and path)
    rows = [{"speed": v, "status": "ok", "collective": 0.2, "roll": 0.0, "pitch": 0.0, "main_rotor.power": 3e5,
             "tail_rotor.power": 2e4, "engine.power": 3.5e5} for v in (0.0, 20.0)]
    sweep_charts.write("trim", pa.Table.from_pylist(rows), ["speed"], tmp_path)
    power = ["main_rotor.power", "tail_rotor.power", "engine.power"]
    assert drawn["trim_power.png"] == {"rotor and engine power": power}
    assert drawn["trim_summary.png"] == ["main_rotor.power", "tail_rotor.power", "engine.power"]
