"""The air of the aerodynamics: the ISA, and the one hook through which every aerodynamic element
reads the air's density, speed of sound and velocity (:mod:`mbs.environment`)."""
from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

from mbs import scenes
from mbs.dynamics import symbolic
from mbs.environment import atmosphere as isa
from mbs.models.helicopter import with_aero
from mbs.models.helicopter.air_options import with_environment

# ISO 2533 / ICAO standard atmosphere tables: altitude (m), temperature (K), pressure (Pa), density (kg/m^3)
ISA_TABLE = [(0.0, 288.15, 101325.0, 1.2250), (1000.0, 281.65, 89874.6, 1.1116), (2000.0, 275.15, 79495.2, 1.0065),
             (5000.0, 255.65, 54019.9, 0.73612), (11000.0, 216.65, 22632.1, 0.36392),
             (15000.0, 216.65, 12044.6, 0.19367), (20000.0, 216.65, 5474.89, 0.088035)]


@pytest.mark.parametrize("h, t, p, rho", ISA_TABLE)
def test_isa_against_the_standard_tables(h, t, p, rho):
    c = isa.conditions(h)
    assert c.temperature == pytest.approx(t, abs=1e-9)
    assert c.pressure == pytest.approx(p, rel=5e-6)
    assert c.density == pytest.approx(rho, rel=5e-5)


def test_isa_sea_level_speed_of_sound_viscosity_and_offset():
    assert isa.speed_of_sound(0.0) == pytest.approx(340.294, abs=5e-4)
    assert isa.viscosity(0.0) == pytest.approx(1.7894e-5, rel=1e-4)
    hot = isa.conditions(2000.0, 20.0)
    assert hot.pressure == isa.pressure(2000.0) and hot.temperature == pytest.approx(295.15)
    assert hot.density == pytest.approx(isa.pressure(2000.0) / (isa.R * 295.15), rel=1e-15)


def test_sea_level_isa_differs_from_the_file_in_the_last_digits_so_the_file_stays_the_default():
    d = scenes.get("hover").aircraft.data["environment"]
    assert isa.density(0.0) != d["rho"] and abs(isa.density(0.0) - d["rho"]) < 1e-7
    assert isa.speed_of_sound(0.0) != d["speed_of_sound"] and abs(isa.speed_of_sound(0.0) - d["speed_of_sound"]) < 0.01
    assert "altitude" not in scenes.get("hover").model().parameters  # the default scene keeps the file's values


@pytest.mark.parametrize("h, dt", [(-1000.1, 0.0), (20000.5, 0.0), (0.0, 61.0), (float("nan"), 0.0)])
def test_isa_refuses_what_it_does_not_model(h, dt):
    with pytest.raises(ValueError, match="outside"):
        isa.conditions(h, dt)


def _functions(scene, **air):
    sym = symbolic(with_environment(scene, **air).model())
    return sym, sym.layout


def _ht(sym, x, p_over: dict):
    names = list(sym.model.parameters)
    p = np.array([p_over.get(n, q.default) for n, q in sym.model.parameters.items()])
    assert set(p_over) <= set(names)
    return np.asarray(sym["parts"](x, 0.013, p)[2]).ravel()


@pytest.mark.parametrize("tail", ["fixed", "stabilator"])
def test_every_aerodynamic_load_scales_with_the_isa_density(tail, tmp_path):
    """At equal temperature (so equal speed of sound) the generalized forces are linear in the
    density, and extrapolated to zero density they are those of the same tree without any
    aerodynamics: no element keeps a load of its own density. A stabilator (a scheduled tail
    with interference tables) kept the file's density at altitude."""
    from test_empennage import _file

    sc = scenes.get("forward-flight")
    sc = sc if tail == "fixed" else sc.with_aircraft(_file(tmp_path, 0.0))
    sym, lay = _functions(sc, altitude=0.0)
    x = _x0(sym)
    rhos, hts = [], []
    for h in (0.0, 1500.0, 4000.0):
        over = {"altitude": h, "temperature_offset": isa.LAPSE * h}  # T = 288.15 K at every altitude
        rhos.append(isa.density(h, isa.LAPSE * h))
        hts.append(_ht(sym, x, over))
    slope = (hts[1] - hts[0]) / (rhos[1] - rhos[0])
    assert np.abs(hts[2] - hts[0] - slope * (rhos[2] - rhos[0])).max() < 1e-9 * np.abs(hts[0]).max()
    bare = symbolic(replace(sc, options={**sc.options, "rotor_aero": False, "airframe_aero": False,
                                         "inflow": "uniform", "tip_loss": False, "compressibility": False,
                                         "tail_wake": False, "download": False, "hub_drag": False}).model())
    nq, nv = lay.nq, lay.nv
    x_bare = np.r_[x[:nq + nv]]
    at_zero = hts[0] - slope * rhos[0]
    own = {n: q.default for n, q in sym.model.parameters.items()}
    p_bare = np.array([own[n] for n in bare.model.parameters])  # the same controls
    ht_bare = np.asarray(bare["parts"](x_bare, 0.013, p_bare)[2]).ravel()
    assert np.abs(at_zero - ht_bare).max() < 1e-8 * np.abs(hts[0]).max()


def _x0(sym):
    from mbs.backends.info import initial_state

    return initial_state(sym)


def test_compressibility_reads_the_isa_speed_of_sound():
    """Two air states of equal density and different temperature: the rotor's thrust differs by
    the Mach number with compressibility on, not at all without it."""
    h1, dt1 = 1000.0, 0.0
    rho = isa.density(h1, dt1)
    dt2 = isa.pressure(2000.0) / (isa.R * rho) - isa.standard_temperature(2000.0)  # same density at 2000 m
    assert isa.density(2000.0, dt2) == pytest.approx(rho, rel=1e-14)
    thrust = {}
    for switches in ("full", "pitt-peters,tip-loss"):
        sc = with_aero(scenes.get("hover"), switches)
        sym = symbolic(with_environment(sc, altitude=0.0).model())
        x, names = _x0(sym), list(sym.model.parameters)
        out = []
        for h, dt in ((h1, dt1), (2000.0, dt2)):
            p = np.array([{"altitude": h, "temperature_offset": dt}.get(n, q.default)
                          for n, q in sym.model.parameters.items()])
            y = np.asarray(sym["outputs"](x, 0.0, p)).ravel()
            out.append(y[list(sym.model.outputs).index("main_rotor.thrust")])
        thrust[switches] = out
    assert abs(thrust["full"][0] / thrust["full"][1] - 1) > 1e-4
    assert thrust["pitt-peters,tip-loss"][0] == pytest.approx(thrust["pitt-peters,tip-loss"][1], rel=1e-13)


def _equal_density_thrusts(sc) -> list[float]:
    """The main rotor's thrust of ``sc`` in the ISA at 1000 m and at 2000 m warmer to the same density."""
    rho = isa.density(1000.0, 0.0)
    dt2 = isa.pressure(2000.0) / (isa.R * rho) - isa.standard_temperature(2000.0)
    sym = symbolic(with_environment(sc, altitude=0.0).model())
    x, out = _x0(sym), []
    for h, dt in ((1000.0, 0.0), (2000.0, dt2)):
        p = np.array([{"altitude": h, "temperature_offset": dt}.get(n, q.default)
                      for n, q in sym.model.parameters.items()])
        out.append(float(np.asarray(sym["outputs"](x, 0.0, p)).ravel()[list(sym.model.outputs).index(
            "main_rotor.thrust")]))
    return out


def test_airfoil_tables_read_the_isa_speed_of_sound(tmp_path):
    """The rotors' sections as C81 tables (sampled from the analytic sections): at equal density and
    different temperature the thrust differs by the Mach number with the tables' Mach dependence, by
    as much as the analytic section's compressibility makes it differ, and not at all without it."""
    from mbs import aircraft
    from mbs.aero.tables.sample import with_sampled_tables

    craft = with_sampled_tables(aircraft.load(), tmp_path)
    hover = scenes.get("hover")
    tables = _equal_density_thrusts(hover.with_aircraft(craft))
    analytic = _equal_density_thrusts(hover)
    flat = _equal_density_thrusts(with_aero(hover.with_aircraft(craft), "pitt-peters,tip-loss"))
    assert abs(tables[0] / tables[1] - 1) > 1e-4
    assert tables[0] / tables[1] == pytest.approx(analytic[0] / analytic[1], rel=1e-3)
    assert flat[0] == pytest.approx(flat[1], rel=1e-13)


def test_a_steady_wind_is_galilean_every_element_sees_the_air_velocity():
    """Forward flight (every aerodynamics switch on) in a steady wind W, the aircraft moving at its
    still-air velocity plus W: every acceleration and inflow rate equals the still-air one."""
    from mbs import _rotation as rot

    sc = scenes.get("forward-flight")
    still = symbolic(sc.model())
    windy = symbolic(with_environment(sc, wind=(-4.0, 2.5, 1.0)).model())
    x = _x0(still)
    lay = still.layout
    q = x[[lay.q_names.index(f"fuselage.q{k}") for k in "wxyz"]]
    r = np.array(rot.quat_to_matrix(q), dtype=float)
    x_w = x.copy()
    uvw = [lay.nq + lay.v_names.index(f"fuselage.{k}") for k in "uvw"]
    x_w[uvw] += r.T @ np.array([-4.0, 2.5, 1.0])
    p_still = np.array([p.default for p in still.model.parameters.values()])
    p_windy = np.array([p.default for p in windy.model.parameters.values()])
    f0 = np.asarray(still["rhs"](x, 0.02, p_still)).ravel()
    f1 = np.asarray(windy["rhs"](x_w, 0.02, p_windy)).ravel()
    rates = slice(lay.nq, None)  # accelerations and inflow rates; the positions' rates differ by W
    f_moved = np.asarray(windy["rhs"](x, 0.02, p_windy)).ravel()
    assert np.abs(f_moved[rates] - f0[rates]).max() > 1e-2 * np.abs(f0[rates]).max()  # the wind acts
    assert np.abs(f1[rates] - f0[rates]).max() < 1e-9 * np.abs(f0[rates]).max()


@pytest.mark.parametrize("scene, air, words", [
    ("structural", dict(altitude=1000.0), "does not model"),
    ("single-blade", dict(wind=(1.0, 0.0, 0.0)), "does not model"),
    ("hover", dict(altitude=25000.0), "outside the ISA's range"),
    ("hover", dict(wind=(0.0, 70.0, 0.0)), "within ±60"),
])
def test_the_air_is_refused_where_it_cannot_work(scene, air, words):
    with pytest.raises(ValueError, match=words):
        with_environment(scenes.get(scene), **air)
