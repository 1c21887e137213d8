"""The swashplate and pitch links as local loops (mbs.models.helicopter.swashplate): couplings from
the geometry against their trigonometric values, the loop closed along a forward-flight run, the
mechanism against the driven pitch, pitch-link forces against the open tree's inverse dynamics,
and the flap frequency with δ3 against the closed form."""
from __future__ import annotations

from dataclasses import replace

import casadi as ca
import numpy as np
import pytest

from aircraft_files import entries, write
from test_floquet_closed_forms import _blade_constants, zero_cyclic_hover
import mbs
from mbs import aircraft, scenes
from mbs.analysis.floquet import analyse
from mbs.dynamics import symbolic
from mbs.joints import DrivenHinge, Params, Serial
from mbs.models.helicopter import Config, build
from mbs.models.helicopter.scenes import SCENE_CONFIGS
from mbs.models.helicopter.swashplate import Swashplate

DEG = np.pi / 180
HOVER_BLADE = Config(fuselage="none", blades=1, tail_rotor=False, airframe_aero=False, dampers=False,
                     shaft_tilt=False, speed=0.0, swashplate="pitch")
BARE_BLADE = replace(HOVER_BLADE, rotor_aero=False)


def blade_horn(tmp_path, delta3_deg: float, lean_deg: float = 0.0, height: float = 0.0):
    """The Bo105 with its pitch horn on the blade (an articulated rotor's), δ3 and link lean given."""
    raw = entries("bo105")
    sp = raw["swashplate"]
    sp.pop("ball_radius")
    sp["horn"]["value"] = "blade"
    sp["horn_height"]["value"] = height
    sp["delta3"] = {"value": delta3_deg, "unit": "deg", "source": "EST"}
    sp["link_lean"] = {"value": lean_deg, "unit": "deg", "source": "EST"}
    return aircraft.load(write(raw, tmp_path / f"bo105_d{delta3_deg:g}_l{lean_deg:g}_z{height:g}.toml"))


def pitch_function(model):
    """``f(q (flap, lag), t, p) -> (θ, ∂θ/∂(flap, lag))`` of blade 1's pitch link, by AD."""
    joint = model.bodies["blade1"].joint
    q, t, p = ca.SX.sym("q", 2), ca.SX.sym("t"), ca.SX.sym("p", len(model.parameters))
    theta = joint.loop.solve(joint, q, t, Params(list(model.parameters), p))
    return ca.Function("pitch", [q, t, p], [theta, ca.jacobian(theta, q)])


def _params(model, **values) -> np.ndarray:
    return np.array([values.get(n, par.default) for n, par in model.parameters.items()])


# -- 2. couplings from the geometry --------------------------------------------------------------

@pytest.mark.parametrize("delta3, lean", [(30.0, 0.0), (15.0, 6.0), (0.0, -4.0)])
def test_pitch_flap_and_pitch_lag_couplings_at_neutral_are_minus_d_over_h_and_minus_tan_lean(tmp_path, delta3, lean):
    """Neutral controls, zero flap and lag (the link parallel to the shaft, leaning ``lean`` in the
    span): the AD couplings of the pitch link's closed form are ``∂θ/∂β = -d/h = -tan δ3`` (the upper
    ball ``d`` outboard of the flap hinge, horn arm ``h``) and ``∂θ/∂ζ = -tan(lean)`` (lagging moves
    the ball outboard by ``h ζ`` along a leaning link), to 1e-10."""
    craft = blade_horn(tmp_path, delta3, lean)
    model = build(BARE_BLADE, craft)
    sp = craft.data["swashplate"]
    theta, slope = pitch_function(model)(np.zeros(2), 0.0, _params(model, collective=0.0, lateral_cyclic=0.0,
                                                                     longitudinal_cyclic=0.0))
    d, h = sp["horn_arm"] * np.tan(delta3 * DEG), sp["horn_arm"]
    assert abs(float(theta)) < 1e-14
    np.testing.assert_allclose(np.array(slope).ravel(), [-d / h, -np.tan(lean * DEG)], rtol=0, atol=1e-10)
    assert -d / h == pytest.approx(-np.tan(delta3 * DEG), abs=1e-15)


@pytest.mark.parametrize("collective, lean, height", [(0.25, 0.0, 0.0), (0.3, 5.0, 0.04), (-0.1, -3.0, -0.02)])
def test_couplings_away_from_neutral_equal_their_trigonometric_values(tmp_path, collective, lean, height):
    """With collective (the plate raised ``h θ0``) the horn turns to ``θ`` and the link leans: the
    couplings are the exact ``∂θ/∂β = -(n·(e_β × r)) / (n·(e_θ × r))`` and likewise for ζ, with the
    ball ``r = (d, h cos θ - z sin θ, h sin θ + z cos θ)``, the link's direction ``n`` from the lower
    ball ``(d - L sin λ, h, z - L cos λ + h θ0)`` and the hinge axes ``e_β = -y``, ``e_ζ = -z``,
    ``e_θ = x``, written out in sines and cosines: to 1e-10 (δ3 = 30°)."""
    craft = blade_horn(tmp_path, 30.0, lean, height)
    model = build(BARE_BLADE, craft)
    sp = craft.data["swashplate"]
    f = pitch_function(model)
    theta, slope = f(np.zeros(2), 0.0, _params(model, collective=collective, lateral_cyclic=0.0,
                                               longitudinal_cyclic=0.0))
    th, (dbeta, dzeta) = float(theta), np.array(slope).ravel()
    h, z, big_l, lam = sp["horn_arm"], height, sp["link_length"], lean * DEG
    d = h * np.tan(30 * DEG)
    c, s = np.cos(th), np.sin(th)
    ball = np.array([d, h * c - z * s, h * s + z * c])
    lower = np.array([d - big_l * np.sin(lam), h, z - big_l * np.cos(lam) + h * collective])
    assert np.linalg.norm(ball - lower) == pytest.approx(big_l, abs=1e-13)  # the loop closes
    nx, ny, nz = (ball - lower) / big_l
    rx, ry, rz = ball
    turn = -ny * rz + nz * ry  # n · (x × r),  x × r = (0, -r_z, r_y)
    flap = -nx * rz + nz * rx  # n · (-y × r), -y × r = (-r_z, 0, r_x)
    lag = nx * ry - ny * rx    # n · (-z × r), -z × r = (r_y, -r_x, 0)
    assert dbeta == pytest.approx(-flap / turn, abs=1e-10)
    assert dzeta == pytest.approx(-lag / turn, abs=1e-10)
    assert abs(dbeta + np.tan(30 * DEG)) > 1e-4  # not the small-angle value


def test_a_horn_on_the_feathering_housing_has_no_coupling():
    """The Bo105's horn (on the housing inboard of the flexure): the pitch does not depend on flap
    or lag at all."""
    model = build(BARE_BLADE, aircraft.load())
    f = pitch_function(model)
    for q in ([0.0, 0.0], [0.1, -0.05]):
        _, slope = f(q, 0.013, _params(model, collective=0.3, lateral_cyclic=0.05, longitudinal_cyclic=-0.04))
        assert np.all(np.array(slope) == 0)


# -- 3. the loop closes along every run ----------------------------------------------------------

def _run(model, revs: float, p=None, every: int = 1):
    system = mbs.build(model, "compiled")
    p = system.params(p)
    traj = system.run(system.x0(), 0.0, 2 * np.pi / 44.4 / 100, int(round(100 * revs)), every=every, p=p)
    assert traj.ok, traj.message
    return system, traj, p


@pytest.mark.parametrize("horn", ["housing", "blade"])
def test_every_pitch_link_closes_at_every_sample_of_ten_revolutions_of_forward_flight(tmp_path, horn):
    """forward-flight-swashplate (the Bo105's horn on the housing) and the same with the horn on the
    blade (δ3 = 15°, lean 3°: the pitch follows flap and lag), 10 revolutions of RK4 at 100 steps
    per revolution: every link's length in the tree's motion (the blade body's ball against the
    plate's; for the housing's horn, the horn's ball) equals its length to 1e-12 m at each of the
    1001 samples (measured 1.1e-16 m and 3.3e-16 m: round-off), and every closure margin stays
    above 0.5 (measured 0.86, 0.87)."""
    craft = aircraft.load() if horn == "housing" else blade_horn(tmp_path, 15.0, 3.0)
    system, traj, p = _run(build(SCENE_CONFIGS["forward-flight-swashplate"][0], craft), 10)
    y = system.history("outputs", traj, p)
    names = system.info.output_names
    errors = y[:, [names.index(f"blade{k}.pitch_link.length_error") for k in range(1, 5)]]
    margins = y[:, [names.index(f"blade{k}.pitch_link.closure_margin") for k in range(1, 5)]]
    assert len(traj.t) == 1001 and np.abs(errors).max() <= 1e-12, np.abs(errors).max()
    assert margins.min() > 0.5
    pitch = y[:, names.index("blade1.pitch")]
    assert 0.1 < pitch.min() < pitch.max() < 0.4


# -- 4. the mechanism against the driven pitch ---------------------------------------------------

def housing_pitch_law(sp: Swashplate, ball_radius: float, psi0: float):
    """The pitch of a blade (at azimuth ψ0 at t = 0) whose horn on the housing is held by its link,
    as a function of time and the pilot inputs, written out for the Bo105's geometry (ball at
    ``(r_b, h cos θ, h sin θ)`` in the blade's rotating frame, link of length L to the lower ball
    ``B`` of the plate): ``h (B_y cos θ + B_z sin θ) = ((r_b - B_x)² + h² + B_y² + B_z² - L²) / 2``."""
    h, big_l = sp.arm, sp.length

    def angle(t, p):
        b = sp.lower_ball(sp.plate_from_pitch(p["collective"], p["lateral_cyclic"], p["longitudinal_cyclic"]),
                          p["omega"] * t + psi0)
        k = ((ball_radius - b[0]) ** 2 + h**2 + b[1] ** 2 + b[2] ** 2 - big_l**2) / 2
        return ca.atan2(b[2], b[1]) + ca.acos(k / (h * ca.sqrt(b[1] ** 2 + b[2] ** 2)))
    return angle


def test_the_mechanism_flies_as_the_driven_pitch_given_the_mechanism_s_pitch_law():
    """forward-flight-actuators (the Bo105's horn on the housing: δ3 = 0, no pitch-lag coupling, the
    control system rigid), its actuator inputs mapped to pilot pitch inputs by the inverse of the
    exact linear mixing, against today's forward-flight model whose driven pitch hinges follow the
    link's pitch written out independently (:func:`housing_pitch_law`): every hinge angle to 1e-8
    over 2 revolutions (measured 9e-17 rad; every state 5e-14).

    Against today's harmonic pitch law with those pitch inputs the hinge angles differ by 1.8e-3
    rad: a rigid horn's pitch is not harmonic in the azimuth (``sin θ`` follows the plate's height,
    and the link leans as the horn turns), here 3.3e-3 rad of higher harmonics at the trim's 14°
    collective. No rigid mechanism reproduces the harmonic law exactly."""
    d = aircraft.load().data
    sp = Swashplate.of(d)
    forward = SCENE_CONFIGS["forward-flight"][0]
    mechanism = build(SCENE_CONFIGS["forward-flight-actuators"][0])
    actuators = [mechanism.parameters[f"actuator{i}"].default for i in (1, 2, 3)]
    pitch = dict(zip(("collective", "lateral_cyclic", "longitudinal_cyclic"),
                     sp.pitch_from_plate(*np.linalg.solve(sp.mixing(), actuators))))
    twin = build(forward)
    for k in range(4):
        joint = twin.bodies[f"blade{k + 1}"].joint
        law = housing_pitch_law(sp, d["swashplate"]["ball_radius"], 2 * np.pi * k / 4)
        joint.parts = (*joint.parts[:2], DrivenHinge((1, 0, 0), law, name="pitch"))
    runs = {name: _run(model, 2, p) for name, model, p in (("mechanism", mechanism, None), ("twin", twin, pitch),
                                                             ("harmonic", build(forward), pitch))}
    names = runs["mechanism"][0].info.state_names
    hinges = [i for i, n in enumerate(names) if n.startswith("blade") and n.split(".")[1] in ("flap", "lag")]
    assert names == runs["twin"][0].info.state_names and len(hinges) == 8
    x = {name: traj.x for name, (_, traj, _) in runs.items()}
    assert np.abs(x["mechanism"][:, hinges] - x["twin"][:, hinges]).max() <= 1e-8
    assert np.abs(x["mechanism"] - x["twin"]).max() <= 1e-9
    assert 5e-4 < np.abs(x["mechanism"][:, hinges] - x["harmonic"][:, hinges]).max() < 5e-3


# -- 5. pitch-link loads -------------------------------------------------------------------------

def test_pitch_link_force_times_its_arm_is_the_moment_about_the_feathering_axis(tmp_path):
    """A blade with its horn on the blade (δ3 = 30°, lean 5°: the link couples pitch, flap and lag),
    hover aerodynamics, at a state one revolution into a run. The link's force (the output, from
    the backward Newton-Euler reactions over its arm ``-∂ℓ/∂θ``) against the open tree's inverse
    dynamics (the same blade with a free pitch hinge, the link cut, moved as the loop moves it:
    ``τ = Mt u' - ht`` with the loop model's accelerations and the pitch's rate and acceleration by
    AD of the link's closed form): the force times its arm equals ``τ_θ``, the moment the blade
    needs about its feathering axis, to 1e-9; and the force's generalized forces on flap and lag,
    ``-F ∂ℓ/∂β`` and ``-F ∂ℓ/∂ζ``, equal ``τ_β``, ``τ_ζ`` (the loop's equations of motion are the
    open tree's with the link's force), to 1e-9 of the largest. Measured: 683 N of compression on an
    arm of -0.116 m, τ = (45.4, 10.1, 79.2) N m (flap, lag, pitch), agreement to 2e-14."""
    craft = blade_horn(tmp_path, 30.0, 5.0)
    model = build(HOVER_BLADE, craft)
    system, traj, p = _run(model, 1.0)
    x, t = traj.x[-1], traj.t[-1]
    names = system.info.output_names
    y = system.outputs(x, t, p)
    force, arm = y[names.index("blade1.pitch_link.force")], y[names.index("blade1.pitch_link.arm")]
    accel = system.rhs(x, t, p)[2:4]

    joint = model.bodies["blade1"].joint
    q, v, a, ts = ca.SX.sym("q", 2), ca.SX.sym("v", 2), ca.SX.sym("a", 2), ca.SX.sym("t")
    ps = ca.SX.sym("p", len(model.parameters))
    par = Params(list(model.parameters), ps)
    theta = joint.loop.solve(joint, q, ts, par)
    rate = ca.jtimes(theta, ca.vertcat(q, ts), ca.vertcat(v, 1))
    accel_theta = ca.jtimes(rate, ca.vertcat(q, v, ts), ca.vertcat(v, a, 1))
    q_all = ca.SX.sym("q_all", 3)
    grad = ca.jacobian(joint.loop.residual(joint, q_all, ts, par), q_all)
    pitch = ca.Function("pitch", [q, v, a, ts, ps], [theta, rate, accel_theta])
    th, th_dot, th_ddot = (float(z) for z in pitch(x[0:2], x[2:4], accel, t, p))
    dl = np.array(ca.Function("dl", [q_all, ts, ps], [grad])([x[0], x[1], th], t, p)).ravel()

    open_tree = build(HOVER_BLADE, craft)
    open_tree.outputs.clear()
    open_tree.bodies["blade1"].joint = Serial(*joint.parts)
    sym = symbolic(open_tree)
    assert sym.layout.q_names == ["blade1.flap", "blade1.lag", "blade1.pitch"]
    x_open = np.r_[x[0:2], th, x[2:4], th_dot, x[4:]]
    _, mt, ht, _ = sym["parts"](x_open, t, p)
    tau = np.array(mt) @ np.r_[accel, th_ddot] - np.array(ht).ravel()
    assert force * arm == pytest.approx(tau[2], rel=1e-9)
    np.testing.assert_allclose(-force * dl, tau, rtol=0, atol=1e-9 * np.abs(tau).max())
    assert abs(arm) == pytest.approx(0.12 * np.cos(5 * DEG), rel=0.05) and abs(tau[0]) > 1.0


# -- 6. Floquet: the flap frequency with δ3 ------------------------------------------------------

def _hover_flap(craft):
    """The single blade in hover (single-blade-aero, zero cyclic) with the pitch set by its link:
    its periodic solution, flap mode exponent (per rev), the coupling ``K_P = -∂θ/∂β`` and the pitch there."""
    sc = replace(scenes.get("single-blade-aero").with_aircraft(craft), options={"swashplate": "pitch"})
    model, system, stepper, sol = zero_cyclic_hover(sc)
    flap = [m for m in analyse(sol, system, stepper).modes if m.name.startswith("flap") and m.exponent.imag > 0]
    assert len(flap) == 1
    theta, slope = pitch_function(model)([sol.state["blade1.flap"], sol.state["blade1.lag"]], 0.0, sol.params)
    return sol, system, flap[0].exponent / craft.omega, -float(np.array(slope)[0, 0]), float(theta)


def test_delta3_raises_the_flap_frequency_as_the_aerodynamic_spring_predicts(tmp_path):
    """Floquet at the hover periodic solution of one blade whose horn is on the blade, δ3 = 0° and
    30°. Pitch-flap coupling ``θ = -K_P β`` turns the flap equation's pitch moment into a spring:
    ``ν² = ν0² + (γ*/8) K_P`` (Johnson, Helicopter Theory, 1980: flap dynamics with pitch-flap
    coupling, ``K_P = tan δ3``; ``γ*`` the strips' Lock number of test_floquet_closed_forms).
    With the exact coupling of the link at each trim (``K_P`` by AD: -0.0044 at 0°, 0.590 at 30°,
    about ``tan δ3 / cos θ0`` at the blade's 13.6° pitch), ``|λ|²`` (per rev², the undamped flap frequency
    squared) rises by the predicted 0.374 within 5 % (measured 0.381, +1.7 %; with ``K_P = tan δ3``
    the estimate is 0.364, +4.6 %). The same flap equation coupled with the dynamic inflow
    (test_floquet_closed_forms) gives both flap exponents within 1 % (measured 0.2-0.4 %)."""
    results = {d3: _hover_flap(blade_horn(tmp_path, d3)) for d3 in (0.0, 30.0)}
    (sol0, system0, lam0, kp0, _), (_, _, lam30, kp30, theta30) = results[0.0], results[30.0]
    k = _blade_constants(system0, sol0)
    gamma_star = k["rho"] * k["a"] * k["c"] * 4 * k["S"][3] / k["I"]
    assert kp30 == pytest.approx(np.tan(30 * DEG) / np.cos(theta30), rel=0.01) and abs(kp0) < 0.01
    shift = abs(lam30) ** 2 - abs(lam0) ** 2
    assert shift == pytest.approx(gamma_star / 8 * (kp30 - kp0), rel=0.05)
    assert shift == pytest.approx(gamma_star / 8 * np.tan(30 * DEG), rel=0.06)
    for (sol, system, lam, kp, _) in results.values():
        expected = _flap_with_inflow(_blade_constants(system, sol), kp)
        assert lam.real == pytest.approx(expected.real, rel=0.01) and lam.imag == pytest.approx(expected.imag, rel=0.01)


def _flap_with_inflow(k: dict, kp: float) -> complex:
    """The flap exponent (per rev) of test_floquet_closed_forms' flap equation with the dynamic
    inflow, plus the pitch-flap coupling ``θ = -K_P β`` in the flap moment and the thrust."""
    half = 0.5 * k["rho"] * k["a"] * k["c"] * k["omega"]
    c, d, e = (half * k["S"][n] for n in (3, 2, 1))
    m_app, area, w = 8 / 3 * k["rho"] * k["R"] ** 3, np.pi * k["R"] ** 2, k["omega"]
    a = np.array([[0, 1, 0],
                  [-k["nu"] ** 2 * w**2 - kp * c * w / k["I"], -c / k["I"], -k["kappa"] * d / k["I"]],
                  [-kp * d * w / m_app, -d / m_app, -(k["kappa"] * e + 4 * k["rho"] * area * k["v"]) / m_app]])
    lam = np.linalg.eigvals(a)
    return lam[np.argmax(lam.imag)] / w


# -- the FMU with actuator displacements as inputs --------------------------------------------

def test_the_fmu_of_forward_flight_actuators_takes_the_actuators_and_equals_the_core(tmp_path):
    """``heli fmu build --scenes forward-flight-actuators``: the FMU's inputs are the three
    actuator displacements (m) and the tail collective; with actuator 1 raised 5 mm after half a
    revolution, fmpy's run equals the core's (the same steps with the inputs held) to 1e-9 in the
    blade pitch, link force, actuator force and flap, and the step reaches the blade pitch."""
    from fmu import build as fmu_build, hosts
    from test_fmu import assert_close, host

    path, _ = fmu_build.ensure_fmu(("forward-flight-actuators",))
    system = scenes.get("forward-flight-actuators").system()
    inputs = [q for q in system.info.parameters if q["control"]]
    assert [q["name"] for q in inputs] == ["actuator1", "actuator2", "actuator3", "tail_collective"]
    assert inputs[0]["unit"] == "m"
    dt = 2 * np.pi / 44.4 / 100
    start = {q["name"]: q["default"] for q in inputs}
    table = np.zeros(3, dtype=[("time", float)] + [(n, float) for n in start])
    for row, (t, lift) in enumerate(((0.0, 0.0), (50 * dt, 0.0), (50 * dt, 0.005))):
        table[row]["time"] = t
        for n, v in start.items():
            table[row][n] = v + (lift if n == "actuator1" else 0.0)
    names = ["blade1.pitch", "blade1.pitch_link.force", "actuator1.force", "actuator1.displacement", "blade1.flap"]
    stop = 150 * dt
    run = host("fmpy", {"fmu": str(path), "stop": stop, "dt": dt, "table": hosts.table_rows(table), "names": names,
                        "block": ["mbs", "casadi", "scipy"]}, tmp_path)
    ref = hosts.run_core("forward-flight-actuators", hosts.grid(stop, dt), table, names=names)
    assert_close(run, ref, names, rtol=1e-9, atol=1e-9)
    pitch = np.asarray(run["blade1.pitch"])
    assert run["actuator1.displacement"][-1] == pytest.approx(start["actuator1"] + 0.005, abs=1e-12)
    assert np.abs(np.diff(pitch)).max() > 0.01  # the actuator's step moved the blades


# -- the elastic pitch link ----------------------------------------------------------------------

def _stiffness(tmp_path, factor: float):
    raw = entries("bo105")
    raw["swashplate"]["link_stiffness"]["value"] *= factor
    return aircraft.load(write(raw, tmp_path / f"bo105_link{factor:g}.toml"))


def test_elastic_links_tend_to_the_rigid_loop_as_their_stiffness_grows(tmp_path):
    """One blade in hover with its pitch a state and its link a spring (``pitch_link="elastic"``,
    starting unstretched), against the rigid loop: over one revolution (RK4, 400 steps) the flap
    and lag differ by 1.2e-3 rad at the file's 2e6 N/m and by a quarter of that at 4x (measured
    4.0x less), the pitch likewise (3.8x), and the link force averaged over the revolution is the
    rigid link's to 2 % (the unstretched start rings at the link's 9/rev and 18/rev)."""
    def run(craft, link):
        system, traj, p = _steps(build(replace(HOVER_BLADE, pitch_link=link), craft))
        y, names = system.history("outputs", traj, p), system.info.output_names
        return traj, y[:, names.index("blade1.pitch")], y[:, names.index("blade1.pitch_link.force")]

    rigid = run(aircraft.load(), "rigid")
    hinges = {}
    for factor in (1.0, 4.0):
        traj, pitch, force = run(_stiffness(tmp_path, factor), "elastic")
        assert traj.info.state_names[:3] == ["blade1.flap", "blade1.lag", "blade1.pitch"]
        hinges[factor] = (np.abs(traj.x[-1, :2] - rigid[0].x[-1, :2]).max(), np.abs(pitch - rigid[1]).max())
        assert force.mean() == pytest.approx(rigid[2].mean(), rel=0.02)
    assert 1e-4 < hinges[1.0][0] < 3e-3 and 3.3 < hinges[1.0][0] / hinges[4.0][0] < 4.7
    assert 3.3 < hinges[1.0][1] / hinges[4.0][1] < 4.7


def _steps(model, steps: int = 400):
    system = mbs.build(model, "compiled")
    p = system.params()
    traj = system.run(system.x0(), 0.0, 2 * np.pi / 44.4 / steps, steps, p=p)
    assert traj.ok, traj.message
    return system, traj, p


def test_the_swashplate_is_refused_where_it_cannot_work():
    """One line each: an aircraft without [swashplate], free rotors, elastic blades, options that
    would do nothing without the swashplate, an unknown mode."""
    cases = [(lambda: build(HOVER_BLADE, aircraft.load("lynx")), "has no \\[swashplate\\] section"),
             (lambda: replace(HOVER_BLADE, rotors="free"), "needs rotors = 'driven'"),
             (lambda: replace(HOVER_BLADE, blade_segments=4), "needs blade_segments = 0"),
             (lambda: Config(loop_solver="newton"), "loop_solver applies to the swashplate"),
             (lambda: Config(pitch_link="elastic"), "pitch_link applies to the swashplate"),
             (lambda: replace(HOVER_BLADE, pitch_link="elastic", loop_solver="newton"), "no loop to solve"),
             (lambda: Config(swashplate="yes"), "swashplate = 'yes'")]
    for make, words in cases:
        with pytest.raises(ValueError, match=words):
            make()


def test_a_clockwise_rotor_s_mechanism_is_the_mirror_image(tmp_path):
    """The Bo105 with its horn on the blade (δ3 = 15°, lean 3°: every coupling on) mirrored in its
    x-z plane (clockwise, tail rotor on the other side; the [swashplate] entries read the same,
    azimuths counted in the sense of rotation): one revolution of forward-flight-swashplate from the
    mirrored state is the mirror of the counter-clockwise one, and the blade pitch, link and actuator
    loads are the same, to 1e-10."""
    from aircraft_files import mirrored, tomllib
    from test_aircraft import MIRROR

    raw, mirror_raw = entries("bo105"), tomllib.loads(mirrored(tmp_path / "mirror_base.toml").read_text())
    for rr in (raw, mirror_raw):
        sp = rr["swashplate"]
        sp.pop("ball_radius")
        sp["horn"]["value"] = "blade"
        sp["delta3"] = {"value": 15.0, "unit": "deg", "source": "EST"}
        sp["link_lean"] = {"value": 3.0, "unit": "deg", "source": "EST"}
    plain = aircraft.load(write(raw, tmp_path / "ccw.toml"))
    mirror = aircraft.load(write(mirror_raw, tmp_path / "cw.toml"))
    assert mirror.data["main_rotor"]["rotation"] == "clockwise"
    cfg = SCENE_CONFIGS["forward-flight-swashplate"][0]
    sys_a, sys_b = mbs.build(build(cfg, plain), "compiled"), mbs.build(build(cfg, mirror), "compiled")
    names = sys_a.info.state_names
    assert list(sys_b.info.state_names) == names
    flip = np.array([MIRROR.get(n, 1) for n in names])
    x0, p, h = sys_a.x0(), sys_a.params(), 2 * np.pi / 44.4 / 100
    a, b = sys_a.run(x0, 0.0, h, 100, p=p), sys_b.run(flip * x0, 0.0, h, 100, p=p)
    np.testing.assert_allclose(flip * b.x[-1], a.x[-1], rtol=1e-10, atol=1e-10)
    out = sys_a.info.output_names
    keep = [i for i, n in enumerate(out) if n.endswith((".pitch", ".pitch_link.force", ".pitch_link.arm"))
            or n.startswith("actuator")]
    assert len(keep) == 18
    ya, yb = sys_a.history("outputs", a, p)[:, keep], sys_b.history("outputs", b, p)[:, keep]
    scale = np.maximum(1.0, np.abs(ya).max(axis=0))
    np.testing.assert_allclose(yb / scale, ya / scale, rtol=0, atol=1e-10)


def test_the_fmu_names_a_pitch_link_that_cannot_close(tmp_path):
    """An aircraft whose actuators can raise the plate beyond its short horns' reach (0.05 m arm,
    0.08 m stroke): with every actuator set to the top of its stroke the FMU discards the step with
    one message naming the link and the time, keeps its state, and steps on once the actuators
    are back."""
    from fmu import build as fmu_build
    from test_fmu import host

    raw = entries("bo105")
    raw["swashplate"]["horn_arm"]["value"] = 0.05
    path, _ = fmu_build.ensure_fmu(("forward-flight-actuators",), aircraft=str(write(raw, tmp_path / "short.toml")))
    dt = 2 * np.pi / 44.4 / 100
    case = {"name": "beyond reach", "set": {f"actuator{i}": 0.08 for i in (1, 2, 3)}, "step": 0.2,
            "fix": {f"actuator{i}": 0.0 for i in (1, 2, 3)}}
    res = host("errors", {"fmu": str(path), "dt": dt, "cases": [case]}, tmp_path)["beyond reach"]
    assert res["init_status"] == 0 and res["first_step"] == 0 and res["step_status"] == 2, res
    text = [m for _, m in res["messages"] if "cannot close" in m]
    assert len(text) == 1 and "loop blade" in text[0] and ".pitch_link cannot close at t = " in text[0], text
    assert "closure margin -" in text[0] and "the step was discarded" in text[0]
    assert res["recovered_status"] == 0
