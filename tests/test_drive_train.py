"""The rotor speed as a degree of freedom: main and tail rotors and the transmission on one drive
train (:mod:`mbs.drivetrain`), the equations in the independent coordinates
(:mod:`mbs.dynamics._dependent`)."""
from __future__ import annotations

from dataclasses import replace

import casadi as ca
import numpy as np
import pytest

import mbs
from mbs import Hinge, Model, scenes
from mbs.drivetrain import inertia_about_axes
from mbs.dynamics import symbolic
from mbs.models.helicopter import FULL, Config, build
from mbs.scenes import Scene

OMEGA = 44.4
ROTOR = {k: v for k, v in FULL.items() if k not in ("tail_wake", "download", "hub_drag")}


def _scene(name: str, cfg: Config, zero_cyclic: bool = False) -> Scene:
    craft = scenes.get("hover").aircraft

    def make(aircraft=None, **options):
        m = build(replace(cfg, **options), aircraft or craft, name=f"test-{name}")
        for c in ("lateral_cyclic", "longitudinal_cyclic") if zero_cyclic else ():
            m.parameters[c].default = 0.0
        return m
    make.config = cfg
    return Scene(name, name, make, omega=OMEGA, aircraft=craft)


def test_a_geared_pair_is_one_degree_of_freedom_with_the_referred_inertia():
    m = Model("gear", gravity=(0, 0, 0))
    m.add_body("a", "world", Hinge((0, 0, 1), name="angle"), mass=1.0, inertia=np.diag([1, 1, 2.0]))
    m.add_body("b", "world", Hinge((1, 0, 0), name="angle"), mass=1.0, inertia=np.diag([0.5, 0.3, 0.3]), at=(2, 0, 0))
    m.add_dependent("b.angle", lambda q, t, p: 3 * q["a.angle"])
    m.add_force(mbs.UserForce("torque", lambda s, loads: loads.add_generalized("b.angle_rate", 1.0)))
    sym = symbolic(m)
    assert sym.layout.q_names == ["a.angle"] and sym.layout.v_names == ["a.angle_rate"]
    x = np.array([0.1, 2.0])
    # I = 2 + 3² 0.5; a torque of 1 N m on the geared shaft is 3 N m on the driving one
    assert float(sym["rhs"](x, 0, [])[1]) == pytest.approx(3.0 / 6.5, rel=1e-14)
    assert float(sym["energy"](x, 0, [])[1]) == pytest.approx(0.5 * 6.5 * 4.0, rel=1e-14)


def test_a_dependent_coordinate_must_be_a_one_axis_coordinate():
    m = Model("bad", gravity=(0, 0, 0))
    m.add_body("a", "world", Hinge((0, 0, 1), name="angle"), mass=1.0)
    m.add_dependent("a.nosuch", lambda q, t, p: q["a.angle"])
    with pytest.raises(ValueError, match="'a.nosuch' is not a one-axis joint coordinate"):
        symbolic(m)


@pytest.mark.parametrize("cfg, words", [
    (dict(drive_train="stiff"), "choose None"),
    (dict(drive_train="rigid", rotors="free"), "needs rotors = 'driven'"),
    (dict(drive_train="rigid", swashplate="pitch"), "needs swashplate = None"),
    (dict(drive_train="rigid", blade_segments=8), "needs blade_segments = 0"),
])
def test_a_drive_train_is_refused_where_it_cannot_work(cfg, words):
    with pytest.raises(ValueError, match=words):
        Config(**cfg)


def _ground_run(drive_train=None) -> Scene:
    cfg = Config(fuselage="clamped", airframe_aero=False, speed=0.0, trim="hover", shaft_tilt=False,
                 drive_train=drive_train, **ROTOR)
    return _scene(f"ground-run-{drive_train}", cfg, zero_cyclic=True)


@pytest.fixture(scope="module")
def hover_trim():
    """The periodic solution of the clamped rotors at constant speed, zero cyclic, vertical shaft."""
    from mbs.analysis.trim import periodic_solution

    res = periodic_solution(_ground_run(), tol=1e-9)
    assert res.converged, res.reason
    return res


def test_power_cut_at_hover_trim_decays_the_rotor_speed_at_q_over_i(hover_trim):
    """At the hover trim, engine torque cut: the drive train's rotor speed (its momentum over its
    inertia, ``Ω = p/I``) falls at ``dΩ/dt = −Q/I``, ``Q`` the aerodynamic torque of the main
    rotor plus the gear ratio times the tail rotor's, ``I`` the drive train's inertia summed from
    the bodies (main rotor and transmission about the shaft, tail rotor about its own times the
    gear ratio squared): to 1e-6."""
    sc = _ground_run("rigid")
    model = sc.model()
    sym = symbolic(model)
    lay, d = sym.layout, sc.aircraft.data
    free = dict(zip(hover_trim.state_names, hover_trim.x0))
    x = np.array([free.get(n, 0.0) for n in lay.state_names])
    x[lay.state_names.index("main_hub.azimuth_rate")] = OMEGA  # counter-clockwise: sense +1
    p = np.array([q.default for q in model.parameters.values()])
    for n, v in zip(hover_trim.state_names, hover_trim.x0):
        assert n in lay.state_names, n
    p[list(model.parameters).index("drive_torque")] = 0.0  # the cut
    i_psi = lay.nq + lay.v_names.index("main_hub.azimuth_rate")
    xs, ts = ca.SX.sym("x", lay.nx), ca.SX.sym("t")
    mt = sym["parts"](xs, ts, p)[1]
    momentum = ca.mtimes(mt, xs[lay.nq:lay.nq + lay.nv])[i_psi - lay.nq]
    rate = ca.Function("rate", [xs, ts], [ca.jacobian(momentum, xs), ca.jacobian(momentum, ts), mt[i_psi - lay.nq,
                                                                                                   i_psi - lay.nq]])
    xdot = np.asarray(sym["rhs"](x, 0.0, p)).ravel()
    dp_dx, dp_dt, mt_psi = (np.asarray(a, dtype=float) for a in rate(x, 0.0))
    dp = float((dp_dx @ xdot).item() + dp_dt.item())
    origins, turns = (np.asarray(a) for a in _poses(sym, x, p))
    poses = {b.name: (origins[i], turns[i]) for i, b in enumerate(lay.bodies)}
    inertia = inertia_about_axes(poses, {b.name: b for b in lay.bodies}, d)
    y = dict(zip(model.outputs, np.asarray(sym["outputs"](x, 0.0, p)).ravel()))
    torque = y["main_rotor.torque"] + d["tail_rotor"]["gear_ratio"] * y["tail_rotor.torque"]
    assert inertia == pytest.approx(mt_psi.item(), rel=1e-12)  # the closed form is the mass matrix's
    assert dp / inertia == pytest.approx(-torque / inertia, rel=1e-6)
    hub = xdot[i_psi]  # the hub alone: its blades lag (soft in-plane), so it decelerates faster at first
    assert hub < dp / inertia < 0


def _poses(sym, x, p):
    a = np.asarray(sym["poses"](x, 0.0, p)).ravel().reshape(-1, 12)
    return a[:, :3], a[:, 3:].reshape(-1, 3, 3)


@pytest.mark.parametrize("drive_train", ["rigid", "flexible"])
def test_the_free_drive_train_conserves_energy_to_rk4_order(drive_train):
    """Aerodynamics off, no drive torque, free fuselage: the drive train, blades, tail rotor and
    (flexible) the main shaft's spring exchange energy; RK4's energy error falls by at least 14
    (16 at fourth order) when the step halves from 1/200 to 1/400 revolution."""
    cfg = Config(rotor_aero=False, airframe_aero=False, dampers=False, drive_train=drive_train)
    system = _scene(f"structural-{drive_train}", cfg).system("compiled")
    x0 = system.x0()
    x0[system.info.state_names.index("main_hub.azimuth_rate")] = OMEGA * 1.05  # the shaft winds up (flexible)
    errors = []
    for n in (200, 400):
        traj = system.run(x0, 0.0, 2 * np.pi / OMEGA / n, 3 * n)
        e = system.history("energy", traj)[:, -1]
        errors.append(np.abs(e / e[0] - 1).max())
    assert errors[0] / errors[1] >= 14, errors
    assert errors[1] < 1e-8, errors
