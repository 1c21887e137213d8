"""Turboshaft engines and their governor on the drive train (:mod:`mbs.drivetrain.engine`):
Padfield's engine and rotor-speed model with the Allison 250-C20B's ratings."""
from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

from mbs import aircraft, scenes
from mbs.drivetrain.engine import Turboshaft
from mbs.drivetrain.response import linear_model, step_response
from mbs.models.helicopter import FULL, Config, build
from mbs.scenes import Scene

OMEGA = 44.4
H = 2 * np.pi / OMEGA / 100
ROTOR = {k: v for k, v in FULL.items() if k not in ("tail_wake", "download", "hub_drag")}
BO105 = aircraft.load().data
ENG = Turboshaft.of(BO105)


def _scene(name: str, cfg: Config) -> Scene:
    craft = scenes.get("hover").aircraft

    def make(aircraft=None, **options):
        return build(replace(cfg, **options), aircraft or craft, name=f"test-{name}")
    make.config = cfg
    return Scene(name, name, make, omega=OMEGA, aircraft=craft)


def test_engines_are_refused_where_they_cannot_work():
    with pytest.raises(ValueError, match="a constant-speed scene has no engine to fail"):
        Config(engines=True)
    lynx = aircraft.load("lynx")
    with pytest.raises(ValueError, match=r"no \[drive_train\] section"):
        build(Config(drive_train="rigid", engines=True), lynx)
    no_engines = type(BO105)({**BO105, "engine": {**BO105["engine"], "model": "none"}})
    with pytest.raises(ValueError, match="has no engine model"):
        build(Config(drive_train="rigid", engines=True), no_engines)


def _settled(system, p, seconds: float):
    traj = system.run(system.x0(), 0.0, H, int(round(seconds / H)), every=100, p=p)
    assert traj.ok, traj.message
    return traj


@pytest.fixture(scope="module")
def hover():
    """The rotors at hover controls on the clamped airframe (ground-run): a steady state exists
    (the free aircraft from hover's untrimmed start wanders, its power with it)."""
    sc = replace(scenes.get("ground-run"), options={**scenes.get("ground-run").options, "drive_train": "rigid",
                                               "engines": True})
    system = sc.system("compiled")
    return system, _settled(system, system.params(), 8.0)


def test_the_governor_droops_by_its_law_in_a_steady_hover(hover):
    """Steady, the lead-lag passes the error unchanged and the fuel equals the power: the speed
    error is ``droop × (power − K_θ (θ0 − θ0_min))`` (fractions of take-off power), to 1e-3."""
    system, traj = hover
    p = system.params()
    last = system.run(traj.x[-1], traj.t[-1], H, 100, p=p)  # one revolution, every step
    speed = last.column("main_hub.azimuth_rate").mean()
    share = last.column("engine1.power").mean()
    assert last.column("engine2.power").mean() == pytest.approx(share, rel=1e-12)
    collective = p[system.info.param_names.index("collective")]
    law = ENG.governor_droop * (share - ENG.anticipation * (collective - BO105["main_rotor"]["collective_min"]))
    assert (OMEGA - speed) / OMEGA == pytest.approx(law, rel=1e-3)


def test_one_engine_inoperative_the_other_takes_its_rating_and_the_failed_one_spools_down(hover):
    """Engine 1 fails at a step boundary: its power falls as the fuel and gas-generator lags in
    series, ``(τ_g e^{-t/τ_g} − τ_f e^{-t/τ_f}) / (τ_g − τ_f)`` of its power at the failure; engine 2's
    rises to its one-engine-inoperative rating (313 kW at sea level), the margin to it near 0."""
    system, traj = hover
    t_fail = traj.t[-1]
    p = system.params({"engine1_failure_time": t_fail})
    after = system.run(traj.x[-1], t_fail, H, int(6.0 / H), every=10, p=p)
    assert after.ok
    names = system.info.output_names
    y = system.history("outputs", after, p)
    p1, p0 = y[:, names.index("engine1.power")], traj.column("engine1.power")[-1] * ENG.takeoff_power
    tg, tf = ENG.gas_generator_time_constant, ENG.fuel_time_constant
    t = after.t - t_fail
    decay = (tg * np.exp(-t / tg) - tf * np.exp(-t / tf)) / (tg - tf)
    assert np.abs(p1 - p0 * decay).max() < 2e-3 * p0
    margin = y[:, names.index("engine2.oei_margin")]
    assert margin[-1] < 0.02 * ENG.oei_power and margin.min() > -1e-6 * ENG.oei_power
    assert y[-1, names.index("engine2.power")] > 0.98 * ENG.oei_power
    assert after.column("main_hub.azimuth_rate")[-1] < traj.column("main_hub.azimuth_rate")[-1]  # the rotor droops


def _clamped(engines: bool) -> Scene:
    cfg = Config(fuselage="clamped", airframe_aero=False, speed=0.0, trim="hover",
                 drive_train="rigid" if engines else None, engines=engines, **ROTOR)
    return _scene(f"clamped-{engines}", cfg)


def _mean_torque(system, p, revs: int = 15) -> float:
    traj = system.run(system.x0(), 0.0, H, 100 * revs, every=1, p=p)
    y = system.history("outputs", traj, p)[-100:]
    names = system.info.output_names
    return float((y[:, names.index("main_rotor.torque")]
                  + BO105["tail_rotor"]["gear_ratio"] * y[:, names.index("tail_rotor.torque")]).mean())


def test_a_collective_step_droops_and_recovers_as_the_engine_models_linear_response():
    """Rotors on the clamped airframe at hover thrust, governor on, a 0.01 rad collective step:
    the rotor speed's droop and its time, and the new steady speed, against the linear model of
    the same engine, governor and drive-train inertia with the rotors' steady torque derivatives
    (from constant-speed runs): within 10 %; and the time it takes to recover (10 % of the droop
    left) within 15 %."""
    engine_scene = _clamped(True)
    system = engine_scene.system("compiled")
    p = system.params()
    theta = p[system.info.param_names.index("collective")]
    settled = _settled(system, p, 10.0)
    omega0 = settled.column("main_hub.azimuth_rate")[-1]
    step = system.run(settled.x[-1], settled.t[-1], H, int(4.0 / H), every=1,
                      p=system.params({"collective": theta + 0.01}))
    droop = step.column("main_hub.azimuth_rate") - omega0
    t = step.t - settled.t[-1]
    constant = _clamped(False).system("compiled")

    def torque(omega, collective):
        return _mean_torque(constant, constant.params({"omega": omega, "collective": collective}))
    q0 = torque(omega0, theta)
    q_omega = (torque(omega0 + 0.2, theta) - torque(omega0 - 0.2, theta)) / 0.4
    q_theta = (torque(omega0, theta + 0.002) - torque(omega0, theta - 0.002)) / 0.004
    inertia = _inertia(system, settled.x[-1], p)
    a, b = linear_model(ENG, inertia, omega0, q0, q_omega, q_theta, OMEGA)
    linear = step_response(a, b, 0.01, t)[:, 0]
    i, j = np.argmin(droop), np.argmin(linear)
    assert droop[i] == pytest.approx(linear[j], rel=0.10)
    assert t[i] == pytest.approx(t[j], rel=0.10)
    print(f"droop {droop[i]:.4f} rad/s at {t[i]:.3f} s, recovered in {recovery_time(t, droop):.2f} s; linear model "
          f"{linear[j]:.4f} rad/s at {t[j]:.3f} s, {recovery_time(t, linear):.2f} s")
    assert recovery_time(t, droop) == pytest.approx(recovery_time(t, linear), rel=0.15)


def _inertia(system, x, p) -> float:
    from mbs.drivetrain import inertia_about_axes

    origins, turns = system.poses(x, 0.0, p)
    bodies = {b["name"]: _Body(b) for b in system.info.bodies}
    poses = {b["name"]: (origins[k], turns[k]) for k, b in enumerate(system.info.bodies)}
    return inertia_about_axes(poses, bodies, BO105)


class _Body:
    def __init__(self, b: dict):
        self.name, self.parent, self.mass = b["name"], b["parent"], b["mass"]
        self.com, self.inertia = np.array(b["com"]), np.array(b["inertia"])


def recovery_time(t: np.ndarray, droop: np.ndarray) -> float:
    """Time (s) from the step until the speed's deviation is back within 10 % of its peak above its
    final value (the droop's recovery)."""
    i, final = np.argmin(droop), droop[-1]
    band = 0.1 * (final - droop[i])
    back = np.flatnonzero(droop[i:] > final - band)
    return float(t[i + back[0]]) if back.size else float("inf")
