"""Tail rotors as published: the shaft's cant, δ3 hinges, precone, flapping hubs of any number of
blades, the mirror image of a clockwise aircraft; against closed forms and the AD's own
kinematics."""
import math
from pathlib import Path

import casadi as ca
import numpy as np
import pytest

from aircraft_files import entries, mirrored, uh60_tailed, with_tail_rotor, write
from mbs import aircraft, scenes
from mbs.aircraft import mass
from mbs.aircraft.derived import tail_flap_frequency
from mbs.models.helicopter import Config, build
from mbs.models.helicopter import frames as fr

DEG = math.pi / 180


def _load(tmp_path: Path, name: str = "puma", **tail) -> aircraft.Aircraft:
    return aircraft.load(write(with_tail_rotor(entries(name), **tail), tmp_path / f"{name}_tail.toml"))


# -- cant: the thrust's lift and side components -------------------------------------------------

@pytest.mark.parametrize("cant, toe", [(20.0, 0.0), (20.0, 6.0)])
def test_a_canted_tail_rotor_s_thrust_has_the_closed_form_lift_and_side_components(tmp_path, cant, toe):
    """The Puma's five rigid tail blades on a shaft canted by Γ (and toed by τ), the airframe
    clamped: at every step the tail rotor's load on the airframe, less its weight, is its
    blade-element thrust along ``(cos Γ sin τ, s cos Γ cos τ, −sin Γ)`` (``s = −1``: to port
    under the Puma's clockwise rotor): lift ``T sin Γ``, side force ``T cos Γ cos τ``, to
    round-off (the five blades' in-plane loads cancel)."""
    craft = _load(tmp_path, cant=(cant, "deg"), toe=(toe, "deg"))
    system = scenes.get("ground-run", craft).system()
    p = system.params()
    traj = system.run(system.x0(), 0.0, 2 * math.pi / craft.omega / 100, 30, p=p)
    y = system.history("outputs", traj, p)[1:]
    names = system.info.output_names
    force = y[:, [names.index(f"tail_rotor.hub.force_{c}") for c in "xyz"]]
    thrust = y[:, names.index("tail_rotor.thrust")]
    weight = mass.rotor_masses(craft.data)[1] * craft.data["environment"]["g"]
    g, t = cant * DEG, toe * DEG
    axis = np.array([math.cos(g) * math.sin(t), -math.cos(g) * math.cos(t), -math.sin(g)])
    assert fr.main_sense(craft.data) == -1 and thrust.min() > 1000.0
    np.testing.assert_allclose(force - [0, 0, weight], thrust[:, None] * axis, rtol=0, atol=1e-10 * thrust.max())
    np.testing.assert_allclose(fr.tail_frame(craft.data)[:, 2], axis, rtol=0, atol=1e-15)


# -- δ3: pitch-flap coupling from the hinge geometry --------------------------------------------

def _blade_angles(model, blade: str, hub_frame_of_blade: np.ndarray, sense: int):
    """``f(q, t) -> (∂θ/∂β, β, θ)``: flap ``β`` (tip up along the thrust axis) and pitch ``θ``
    (nose up) of ``blade`` relative to the hub at the hinge coordinate ``q`` (rad), from the AD of
    the model's own joints (the teeter hinge and the blade's joint composed for a teetering hub)."""
    from mbs.joints import Params, compose

    q, t = ca.SX.sym("q"), ca.SX.sym("t")
    params = Params(list(model.parameters), ca.vertcat(*[p.default for p in model.parameters.values()]))
    body = model.bodies[blade]
    chain = [body] if body.parent == "tail_hub" else [model.bodies[body.parent], body]
    motion = None
    for b in chain:
        joint = b.joint
        nq = joint.nq
        rel = joint.relative(q if nq else ca.SX(0, 1), ca.SX.zeros(nq), t, params)
        placed = compose(_placement(b), rel)
        motion = placed if motion is None else compose(motion, placed)
    r = ca.mtimes(ca.DM(hub_frame_of_blade.T), motion.rotation)  # in the blade's azimuth frame
    flap, pitch = ca.asin(r[2, 0]), sense * ca.atan2(r[2, 1], r[2, 2])
    return ca.Function("angles", [q, t], [ca.jacobian(pitch, q) / ca.jacobian(flap, q), flap, pitch])


def _placement(body):
    from mbs.joints import Fixed

    return Fixed(at=tuple(body.at), frame=tuple(map(tuple, body.frame))).relative(None, None, None, None)


@pytest.mark.parametrize("hub, upper", [("flapping", "aft"), ("flapping", "forward"), ("teetering", "aft")])
def test_delta3_hinges_pitch_the_blade_down_by_tan_delta3_per_flap(tmp_path, hub, upper):
    """δ3 = 35°: flapping up by β (the tip along the thrust axis) pitches the blade nose down by
    ``tan δ3 β``: ``∂θ/∂β = −tan δ3`` from the AD of the model's hinge kinematics, to 1e-12, on
    every blade of a four-blade flapping hub and both blades of the Bo105's seesaw (the second
    blade flaps down and pitches up), either sense of rotation, at the tail collective."""
    name = "bo105" if hub == "teetering" else "puma"
    tail = {"hub_type": (hub, "-"), "delta3": (35.0, "deg"), "upper_blade": (upper, "-")}
    if hub == "flapping":
        tail.update(n_blades=(4, "-"), flap_hinge_offset=(0.1, "m"))
    craft = _load(tmp_path, name, **tail)
    model = build(Config(), craft)
    sense = fr.tail_sense(craft.data)
    n = craft.data["tail_rotor"]["n_blades"]
    for k, psi in enumerate(fr.blade_azimuths(n)):
        angles = _blade_angles(model, f"tail_blade{k + 1}", fr.rz(sense * psi), sense)
        ratio, beta, theta = (float(v) for v in angles(0.0, 0.0))
        assert ratio == pytest.approx(-math.tan(35 * DEG), abs=1e-12)
        assert beta == pytest.approx(0.0, abs=1e-15)
        assert theta == pytest.approx(model.parameters["tail_collective"].default, abs=1e-12)


# -- a flapping hub's flap frequency ---------------------------------------------------------------

@pytest.mark.parametrize("delta3, pitch", [(0.0, 0.0), (0.0, 12.0), (35.0, 0.0)])
def test_a_four_blade_flapping_tail_rotor_s_flap_frequency_is_the_closed_form(tmp_path, delta3, pitch):
    """Four blades on flap hinges at 0.12 m with 1500 N m/rad springs (δ3 skewing the hinge),
    the hub turning at 4.6155 × 27 rad/s in vacuum without gravity: the eigenvalues of the
    model's AD Jacobian at the undeformed rotor are ``±i ν Ω_T`` for every blade with ``ν`` the
    closed form of :func:`mbs.aircraft.derived.tail_flap_frequency` (centrifugal stiffness of
    the box blade about the skewed hinge, offset, spring), to round-off."""
    from mbs.dynamics import symbolic
    from mbs.linearize import rhs_jacobian

    craft = aircraft.load(uh60_tailed(tmp_path / "uh60.toml", delta3=(delta3, "deg")))
    cfg = Config(fuselage="none", rotor_aero=False, airframe_aero=False, dampers=False)
    model = build(cfg, craft)
    model.gravity = np.zeros(3)
    sym = symbolic(model)
    names = sym.layout.q_names
    p = {k: q.default for k, q in model.parameters.items()} | {"tail_collective": pitch * DEG}
    jac = np.array(rhs_jacobian(sym["rhs"])(np.zeros(sym.layout.nx), 0.0, list(p.values())))
    tr, omega = craft.data["tail_rotor"], craft.omega
    nu = tail_flap_frequency(tr, omega, pitch * DEG)
    rate = tr["gear_ratio"] * omega
    for k in range(4):
        i = names.index(f"tail_blade{k + 1}.flap")
        block = jac[np.ix_([i, len(names) + i], [i, len(names) + i])]  # (flap, flap rate) of one blade
        assert np.abs(np.delete(jac[len(names) + i], [i, len(names) + i])).max() < 1e-9 * rate**2  # uncoupled
        lam = np.linalg.eigvals(block)
        np.testing.assert_allclose(np.sort(lam.imag) / rate, [-nu, nu], rtol=1e-12)
        assert np.abs(lam.real).max() < 1e-12 * rate
    assert 1.05 < nu < 1.2


# -- clockwise and counter-clockwise ---------------------------------------------------------------

MIRROR = {"fuselage.y": -1, "fuselage.qx": -1, "fuselage.qz": -1, "fuselage.v": -1, "fuselage.p": -1,
          "fuselage.r": -1}
TAIL = {"hub_type": ("flapping", "-"), "n_blades": (4, "-"), "flap_hinge_offset": (0.08, "m"),
        "flap_stiffness": (400.0, "N m/rad"), "cant": (20.0, "deg"), "toe": (5.0, "deg"), "delta3": (30.0, "deg"),
        "precone": (3.0, "deg")}


def test_a_mirrored_aircraft_with_a_canted_flapping_tail_rotor_flies_the_mirrored_motion(tmp_path):
    """The Bo105 with a four-blade flapping tail rotor (hinge offset, spring, precone, δ3, cant and
    toe) and its mirror image in the x-z plane (main rotor clockwise, tail rotor on the other
    side, thrusting the other way): one revolution of forward flight from mirrored states is the
    mirror image, to round-off: the same main and tail blade flap, lag and inflow, lateral motion
    reversed, the tail rotor's hub loads with their lateral parts reversed."""
    raw = with_tail_rotor(entries("bo105"), **TAIL)
    plain = aircraft.load(write(raw, tmp_path / "plain.toml"))
    mirror = aircraft.load(mirrored(tmp_path / "mirror.toml", raw=raw))
    sys_a, sys_b = (scenes.get("forward-flight", c).system() for c in (plain, mirror))
    names = sys_a.info.state_names
    assert list(sys_b.info.state_names) == list(names) and "tail_blade4.flap" in names
    flip = np.array([MIRROR.get(n, 1) for n in names])
    x0, p = sys_a.x0(**{f"tail_blade{k}.flap": 0.01 * k for k in range(1, 5)}), sys_a.params()
    h = 2 * math.pi / plain.omega / 100
    a = sys_a.run(x0, 0.0, h, 100, every=100, p=p).x[-1]
    b = sys_b.run(flip * x0, 0.0, h, 100, every=100, p=p).x[-1]
    np.testing.assert_allclose(flip * b, a, rtol=1e-10, atol=1e-10)
    tail = [names.index(f"tail_blade{k}.flap") for k in range(1, 5)]
    assert np.abs(a[tail] - x0[tail]).max() > 1e-3  # the tail blades flap
    ya = sys_a.history("outputs", sys_a.run(x0, 0.0, h, 10, p=p), p)
    yb = sys_b.history("outputs", sys_b.run(flip * x0, 0.0, h, 10, p=p), p)
    lateral = ("fin.sidewash", ".hub.force_y", ".hub.moment_x", ".hub.moment_z")
    sideways = np.array([-1.0 if n.endswith(lateral) else 1.0 for n in sys_a.info.output_names])
    scale = np.maximum(1.0, np.abs(ya).max(axis=0))
    np.testing.assert_allclose(sideways * yb / scale, ya / scale, rtol=0, atol=1e-10)


# -- the trim with a canted tail rotor -------------------------------------------------------------

@pytest.fixture(scope="module")
def hover_trims(tmp_path_factory):
    """The Puma's hover trims without and with a 20° cant (rigid five-blade tail rotor), the
    paper's aerodynamics (no download or wake on the airframe: the rotors alone change)."""
    from mbs.analysis.trim import periodic_solution
    from mbs.models.helicopter.config import with_aero

    out = {}
    for cant in (0.0, 20.0):
        path = tmp_path_factory.mktemp("cant") / f"puma_cant{cant:g}.toml"
        craft = aircraft.load(write(with_tail_rotor(entries("puma"), cant=(cant, "deg")), path))
        res = periodic_solution(with_aero(scenes.get("forward-flight", craft), "none"), 0.0)
        assert res.converged, res.reason
        out[cant] = (craft, res)
    return out


def test_a_canted_tail_rotor_lifts_the_tail_the_main_rotor_carries_less_and_the_nose_drops(hover_trims):
    """Hover, Puma, the tail rotor canted 20°: its side force still balances the torque (within
    3 %), so its thrust grows by 1/cos Γ and it lifts ``L = T sin Γ`` (1351 N) at the tail. The main
    rotor carries that much less (its hub force within 5 % of ``-L``: -1320 N; the collective
    0.16° lower), and the tail lift's nose-down moment ``|x_T| L`` tilts the fuselage nose down,
    the disc staying level, until the thrust's arm from the hub above the CG and the hub's flap
    springs balance it: ``Δθ = -|x_T| L / (T h + N/2 (K_β + e S Ω²))`` = -3.238°, the trim's
    -3.224°, within 3 %."""
    (craft, plain), (_, canted) = hover_trims[0.0], hover_trims[20.0]
    d = craft.data
    mr, tr = d["main_rotor"], d["tail_rotor"]
    gamma = 20 * DEG
    tail = canted.output_means["tail_rotor.thrust"]
    lift = tail * math.sin(gamma)
    side_plain, side_canted = plain.output_means["tail_rotor.thrust"], tail * math.cos(gamma)
    assert side_canted == pytest.approx(side_plain, rel=0.03)
    hub = [np.linalg.norm([r.output_means[f"main_rotor.hub.force_{c}"] for c in "xyz"]) for r in (plain, canted)]
    main_change = hub[1] - hub[0]
    e, m = mr["flap_hinge_offset"], mr["blade_mass"]
    hub_spring = mr["n_blades"] / 2 * (mr["flap_stiffness"] + e * m * (mr["radius"] - e) / 2 * mr["omega"] ** 2)
    thrust = plain.output_means["main_rotor.thrust"]
    expected = -abs(tr["hub_x"]) * lift / (thrust * -mr["hub_z"] + hub_spring)
    print(f"cant 20 deg: tail lift {lift:.0f} N, main-rotor thrust {main_change:+.0f} N, collective "
          f"{(canted.controls['collective'] - plain.controls['collective']) / DEG:+.3f} deg, pitch "
          f"{(canted.pitch - plain.pitch) / DEG:+.3f} deg (closed form {expected / DEG:+.3f})")
    assert main_change == pytest.approx(-lift, rel=0.05)
    assert canted.controls["collective"] < plain.controls["collective"]
    assert canted.pitch - plain.pitch == pytest.approx(expected, rel=0.03)


def test_aircraft_check_reports_the_tail_rotor_s_flap_frequency_gear_and_an_idle_precone(tmp_path, capsys):
    """``heli aircraft check`` of the UH-60A's tail rotor: its blades' flap frequency (the closed
    form), the gear ratio the periodic analyses use instead of 4.6155 and its period; a precone on
    a flapping hub without a spring is named as doing nothing."""
    from mbs import cli

    path = uh60_tailed(tmp_path / "uh60.toml", precone=(2.0, "deg"), flap_stiffness=(0.0, "N m/rad"))
    report = aircraft.check(path)
    figures = {n: v for n, v, _ in report.figures}
    tr = aircraft.load(path).data["tail_rotor"]
    assert figures["tail-rotor flap frequency"] == pytest.approx(tail_flap_frequency(tr, 27.0), rel=1e-12)
    assert figures["period of the periodic analyses"] == 13 and tr["gear_ratio"] == 4.6155
    assert cli.main(["aircraft", "check", str(path)]) == 0
    out = capsys.readouterr().out
    assert ("tail_rotor.gear_ratio: tail-rotor gear ratio 4.6155 repeats the rotors only every 500 main-rotor "
            "revolutions; the periodic analyses turn the tail rotor at 4.6153846 instead (period 13 revolutions, "
            "tail-rotor speed -0.0025 %); simulations keep 4.6155") in out
    assert "tail_rotor.precone: 2 deg on a flapping hub without a flap spring does nothing" in out


def test_a_teetering_tail_rotor_of_three_blades_is_said_with_the_entries_it_lacks(tmp_path):
    """Three blades on a teetering hub without its seesaw entries: the blade count and the missing
    entries in one check (a new user was asked for the seesaw first, then told it takes 2 blades)."""
    raw = entries("bo105")
    raw["tail_rotor"]["n_blades"]["value"] = 3
    for key in ("seesaw_mass", "seesaw_size"):
        del raw["tail_rotor"][key]
    problems = aircraft.check(write(raw, tmp_path / "three.toml")).problems
    assert 'tail_rotor.n_blades: a teetering tail rotor has 2 blades, not 3; use hub_type = "flapping" or "rigid" ' \
           "for more" in problems
    assert any(p.startswith("tail_rotor.seesaw_mass: missing") for p in problems), problems
