"""The stabilizer bar (flybar, :mod:`mbs.models.helicopter.stabilizer_bar`): a teetering bar on
the main hub with paddles pitched by the cyclic, and a mixer that pitches the blades from the
bar's teeter. Checked against the closed forms of a centrally hinged teetering bar in hover:
its steady tilt equals the paddles' cyclic, 90 deg later (at resonance), and its free teeter
decays at ``(c_a + c) / 2I`` (the paddles' damping ``c_a = ρ a S Ω r³`` and its hinge's ``c``);
the mixer's blade pitch as written; the file's bad bars refused.

The aircraft is test data: the Bo105 with two blades of the same solidity
(``test_two_bladed_derivatives``) and a Hiller bar.
"""
from __future__ import annotations

import numpy as np
import pytest

from mbs import aircraft, scenes
from mbs.analysis.trim import trim
from mbs.models.helicopter.stabilizer_bar import AXIAL, aero_damping, time_constant
from test_two_bladed_derivatives import _two_bladed

BAR = {"mass": (10.0, "kg"), "inertia": (8.0, "kg m^2"), "height": (0.3, "m"), "paddle_radius": (1.2, "m"),
       "paddle_area": (0.08, "m^2"), "paddle_lift_slope": (3.5, "1/rad"), "hiller_gain": (1.0, "-")}


def _with_bar(tmp_path, name: str = "bar", **changes) -> str:
    """The two-bladed Bo105 with :data:`BAR` (``changes``: entry -> value, None removes it)."""
    entries = {**BAR, **{k: v if isinstance(v, tuple) else (v, BAR.get(k, (0, "s" if k == "time_constant" else "-"))[1])
                         for k, v in changes.items()}}
    lines = ["", "[stabilizer_bar]"] + [f'{k} = {{ value = {v}, unit = "{u}", source = "test" }}'
                                        for k, (v, u) in entries.items() if v is not None]
    path = tmp_path / f"{name}.toml"
    path.write_text(open(_two_bladed(tmp_path)).read() + "\n".join(lines) + "\n")
    return str(path)


@pytest.fixture(scope="module")
def apart(tmp_path_factory):
    """A bar that pitches no blade (hiller_gain 0; the cyclic reaches them by the direct path),
    its paddles at half the cyclic, on the rotor of the clamped fuselage (ground-run: no 2/rev
    rocking of a free fuselage to shake it): the bar alone, with no blade's pitching moment on it."""
    path = _with_bar(tmp_path_factory.mktemp("bar"), "apart", hiller_gain=0.0, bell_gain=1.0, paddle_gain=0.5,
                     paddle_cd0=0.0)
    scene = scenes.get("ground-run").with_aircraft(aircraft.load(path))
    system = scene.system()
    p = system.params(lateral_cyclic=0.01, longitudinal_cyclic=0.02)
    d = scene.aircraft.data
    omega = d["main_rotor"]["omega"]
    tau = time_constant(d["stabilizer_bar"], omega, d["environment"]["rho"])
    steps = 100
    h = 2 * np.pi / omega / steps
    revs = int(np.ceil(10 * tau * omega / (2 * np.pi)))  # ten time constants: the start's transient e^-10
    return scene, system, p, h, revs * steps, tau


def _teeter(system, run, omega):
    names = list(system.info.state_names)
    return run.x[:, names.index("stabilizer_bar.teeter")], run.x[:, names.index("stabilizer_bar.teeter_rate")] / omega


def test_a_bar_tilts_by_the_paddles_cyclic_a_quarter_revolution_later(apart):
    """At blade 1's azimuth 0 the bar's end A is at 90 deg, where the paddles' pitch is
    paddle_gain (θ1c cos 90° + θ1s sin 90°); at resonance the teeter lags it by 90 deg with the
    amplitude of the pitch: β = paddle_gain θ1c, β'/Ω = paddle_gain θ1s. Measured: the amplitude
    to 3e-5, the phase off by 2.2e-3 rad, of which the bar's detuning explains 1.35e-3 (its axial
    inertia, 1e-4 of its teeter inertia, lowers its teeter frequency: the phase AXIAL I Ω / c_a)."""
    scene, system, p, h, n, _ = apart
    d = scene.aircraft.data
    omega, bar, rho = d["main_rotor"]["omega"], d["stabilizer_bar"], d["environment"]["rho"]
    run = system.run(system.x0(), 0.0, h, n, every=100, p=p)  # a sample per revolution, at blade 1's azimuth 0
    beta, rate = _teeter(system, run, omega)
    cyclic = 0.5 * np.array([0.01, 0.02])
    assert AXIAL * bar["inertia"] * omega / aero_damping(bar, omega, rho) == pytest.approx(1.35e-3, rel=0.01)
    amplitude, phase = np.hypot(beta[-1], rate[-1]), np.arctan2(rate[-1], beta[-1])
    assert amplitude == pytest.approx(np.hypot(*cyclic), rel=1e-4)
    assert 0 < phase - np.arctan2(cyclic[1], cyclic[0]) < 3e-3, (beta[-1], rate[-1])
    assert np.hypot(beta[-1] - beta[-2], rate[-1] - rate[-2]) < 1e-4 * np.hypot(*cyclic)  # periodic: settled


def test_the_bars_teeter_decays_at_its_damping_over_twice_its_inertia(apart):
    """Disturbed from its periodic motion by 0.01 rad, the bar's teeter (less the undisturbed's)
    decays as exp(-t/τ), τ = 2I / (ρ a S Ω r³), to 1 % over two τ: the paddles' lift-rate damping."""
    scene, system, p, h, n, tau = apart
    omega = scene.aircraft.data["main_rotor"]["omega"]
    start = system.run(system.x0(), 0.0, h, n, every=n, p=p).x[-1]  # settled
    hit = np.array(start, float)
    hit[list(system.info.state_names).index("stabilizer_bar.teeter")] += 0.01
    span = int(2 * tau / h)
    (b0, r0), (b1, r1) = (_teeter(system, system.run(x, 0.0, h, span, every=1, p=p), omega) for x in (start, hit))
    diff = np.hypot(b1 - b0, r1 - r0)  # the amplitude of the disturbance's 1/rev
    t = np.arange(len(diff)) * h
    rate = -np.polyfit(t, np.log(diff), 1)[0]
    assert rate == pytest.approx(1 / tau, rel=0.01), (rate, 1 / tau)


def test_a_hiller_bar_changes_the_stick_not_the_rotor_the_aircraft_needs(tmp_path):
    """In a hover trim the aircraft needs the same disc tilt with or without the bar: the rotor's
    flapping within 0.01 deg, the collective and attitude within 0.05 deg of the two-bladed
    aircraft's; the cyclic that gets it differs (the bar's paddles and the blades' pitching moment
    through the mixer, on the bar). The quasi-static derivatives warn that the bar is slow."""
    from mbs.analysis.derivatives import stabilizer_bar_warning

    plain = trim(scenes.get("hover").with_aircraft(aircraft.load(_two_bladed(tmp_path))), 0.0)
    craft = aircraft.load(_with_bar(tmp_path))
    barred = trim(scenes.get("hover").with_aircraft(craft), 0.0)
    assert plain.converged and barred.converged
    assert {"bar1c", "bar1s"} <= set(barred.flapping) and "bar1c" not in plain.flapping  # the bar's tilt, reported
    for key in ("beta0", "beta1c", "beta1s"):
        assert np.degrees(abs(barred.flapping[key] - plain.flapping[key])) < 0.01, key
    assert np.degrees(abs(barred.controls["collective"] - plain.controls["collective"])) < 0.05
    assert np.degrees(abs(barred.pitch - plain.pitch)) < 0.05 and np.degrees(abs(barred.roll - plain.roll)) < 0.05
    (words,) = stabilizer_bar_warning(craft.data)
    assert words.startswith("stabilizer bar: its time constant 0.608 s is the body's")
    from mbs.analysis.derivatives import derivatives
    from mbs.commands import _derivative_lines

    lines = _derivative_lines(derivatives(scenes.get("hover").with_aircraft(craft), 0.0))
    assert any(line.startswith("  (NOT the aircraft's modes with its stabilizer bar") for line in lines), lines


def test_the_mixer_pitches_the_blades_from_the_bar(tmp_path):
    """θ_k = θ0 + bell (θ1c cos ψ_k + θ1s sin ψ_k) + hiller cos ψ_k β_bar, blade 2 opposite blade 1:
    at t = 0 (ψ_1 = 0) the outputs are θ0 ± (bell θ1c + hiller β), to round-off."""
    path = _with_bar(tmp_path, bell_gain=0.4, hiller_gain=0.7)
    system = scenes.get("hover").with_aircraft(aircraft.load(path)).system("vm")
    names, p = list(system.info.state_names), system.params()
    x = np.array(system.x0(), float)
    x[names.index("stabilizer_bar.teeter")] = 0.03
    out = dict(zip(system.info.output_names, np.asarray(system.outputs(x, 0.0, p)).ravel()))
    par = dict(zip(system.info.param_names, p))
    expected = 0.4 * par["lateral_cyclic"] + 0.7 * 0.03
    assert out["blade1.pitch"] == pytest.approx(par["collective"] + expected, abs=1e-14)
    assert out["blade2.pitch"] == pytest.approx(par["collective"] - expected, abs=1e-14)


@pytest.mark.parametrize("changes,words", [
    (dict(paddle_lift_slope=None), "stabilizer_bar.paddle_lift_slope: the paddles (paddle_area 0.08 m^2) need"),
    (dict(paddle_area=None), "stabilizer_bar: neither paddles (paddle_area) nor dampers (damping, or its time_"),
    (dict(time_constant=0.8), "stabilizer_bar.time_constant: 0.8 s, while the paddles alone damp the bar in 0.608 s"),
    (dict(time_constant=0.8, damping=(2.0, "N m s/rad")), "stabilizer_bar.time_constant: the hinge's damping is"),
    (dict(hiller_gain=-1.0), "stabilizer_bar.hiller_gain: the blades get -1 rad of cyclic per rad"),
])
def test_a_bar_that_cannot_work_is_refused_naming_why(tmp_path, changes, words):
    report = aircraft.check(_with_bar(tmp_path, **changes))
    assert any(words in p for p in report.problems), report.problems


def test_a_bar_on_four_blades_and_in_a_swashplate_scene_is_refused(tmp_path):
    four = tmp_path / "four.toml"
    four.write_text(aircraft.resolve("bo105").read_text() + "\n[stabilizer_bar]\n" + "\n".join(
        f'{k} = {{ value = {v}, unit = "{u}", source = "test" }}' for k, (v, u) in BAR.items()) + "\n")
    assert any("stabilizer_bar: on a main rotor of 4 blades" in p for p in aircraft.check(four).problems)
    with pytest.raises(ValueError, match="stabilizer_bar: its mixer sets the pitch of rigid blades"):
        scenes.get("forward-flight-swashplate").with_aircraft(aircraft.load(_with_bar(tmp_path))).model()


def test_paddles_past_their_own_advance_ratio_are_warned_of(tmp_path):
    """The bar's paddles fly at their own advance ratio V / (Ω r), which reaches reverse flow long
    before the rotor's: the test bar's (r = 1.2 m) is 1.13 at 60 m/s, where its tilt in a trim is
    -11 deg from the speed alone. A trim past 0.5 says so; at 20 m/s (0.38) nothing."""
    from mbs.models.helicopter.airframe_warnings import airframe_warnings

    d = aircraft.load(_with_bar(tmp_path)).data
    fast = [w for w in airframe_warnings({"fuselage.u": 60.0, "fuselage.w": 0.0}, d) if w.startswith("stabilizer")]
    assert len(fast) == 1 and "advance ratio V / (Omega r) = 1.13" in fast[0] and "reverse flow" in fast[0]
    assert not [w for w in airframe_warnings({"fuselage.u": 20.0, "fuselage.w": 0.0}, d) if w.startswith("stabilizer")]


def test_the_bars_mass_is_the_aircrafts_and_its_warning_reaches_the_validation(tmp_path):
    """A new user's UH-1H flew 1.1 % heavier with its bar: the bar's 32 kg came on top of the
    published whole-aircraft mass. The bar is part of the main rotor: the model's bodies weigh the
    file's mass with or without it, and the whole aircraft's inertia about the CG is the file's.
    Its derivatives' warning was missing from 'heli validate', which shows the derivatives'."""
    from mbs.aircraft import mass
    from mbs.validate.files import load
    from mbs.validate.report import lines
    from mbs.validate.runner import validate

    path = _with_bar(tmp_path)
    craft = aircraft.load(path)
    model = scenes.get("hover").with_aircraft(craft).model()
    assert sum(b.mass for b in model.bodies.values()) == pytest.approx(craft.data["aircraft"]["mass"], rel=1e-12)
    assert craft.data["aircraft"]["inertia"] == "whole-aircraft"
    whole = mass.whole_aircraft(craft.data).about(np.zeros(3))
    assert np.allclose(whole, mass.published_inertia(craft.data), rtol=0, atol=1e-9)
    plain = aircraft.load(_two_bladed(tmp_path)).data
    assert mass.airframe(craft.data).mass == pytest.approx(mass.airframe(plain).mass - BAR["mass"][0], abs=1e-9)
    data = tmp_path / "data.toml"
    data.write_text(f'[validation]\naircraft = "{path}"\nscene = "hover"\nspeed_unit = "m/s"\n'
                    '[[derivative]]\nquantity = "Z_w"\nunit = "1/s"\nspeed = [0]\nvalue = [-0.3]\nsource = "T"\n')
    text = "\n".join(lines(validate(load(data))))
    assert "stabilizer bar: its time constant 0.608 s is the body's" in text, text


def test_a_bars_published_time_constant_gives_its_hinge_damping(tmp_path):
    """The UH-1H's data give its Bell bar as a time constant, 3.3 s. Given as printed, the hinge's
    damping is 2 I / τ less the paddles' (none on a Bell bar), and the bar's time constant, the
    model's hinge damping and its free decay (the decay test's measure) come back to it."""
    from mbs.models.helicopter.stabilizer_bar import hinge_damping

    bell = aircraft.load(_with_bar(tmp_path, "bell", paddle_area=None, paddle_lift_slope=None, time_constant=3.3,
                                   inertia=27.2, bell_gain=1.0, hiller_gain=0.5)).data
    omega, rho = bell["main_rotor"]["omega"], bell["environment"]["rho"]
    bar = bell["stabilizer_bar"]
    assert hinge_damping(bar, omega, rho) == pytest.approx(2 * 27.2 / 3.3, rel=1e-12)
    assert time_constant(bar, omega, rho) == pytest.approx(3.3, rel=1e-12)
    model = scenes.get("hover").with_aircraft(aircraft.load(_with_bar(tmp_path, "bell2", paddle_area=None,
                                                                      paddle_lift_slope=None, time_constant=3.3,
                                                                      inertia=27.2, bell_gain=1.0))).model()
    assert model.bodies["stabilizer_bar"].joint.damping == pytest.approx(2 * 27.2 / 3.3, rel=1e-12)
    figures = {name: value for name, value, _ in aircraft.check(_with_bar(tmp_path, "bell3", paddle_area=None,
                                                                         paddle_lift_slope=None, time_constant=3.3,
                                                                         inertia=27.2, bell_gain=1.0)).figures}
    assert figures["stabilizer bar hinge damping (from its time constant)"] == pytest.approx(2 * 27.2 / 3.3)
    hiller = aircraft.load(_with_bar(tmp_path, "hiller", time_constant=0.4)).data["stabilizer_bar"]
    assert time_constant(hiller, omega, rho) == pytest.approx(0.4, rel=1e-12)
    assert hinge_damping(hiller, omega, rho) == pytest.approx(2 * 8.0 / 0.4 - aero_damping(hiller, omega, rho))


def test_floquet_reads_the_bars_mode_as_the_tilt_of_its_plane(apart):
    """The bar's teeter is in the rotating frame, where a tilt held in space is a 1/rev motion: a
    new user's X-Cell bar mode read 0.9996/rev in the fixed-frame table. Read as the tilt of its
    plane (β, β'/Ω turned by its azimuth), the clamped bar's mode is the closed form's subsidence:
    Re λ = -1/τ to 1e-3, its frequency under 1e-3/rev (the slender bar's detuning)."""
    from mbs.analysis.floquet import floquet

    scene = apart[0]
    d = scene.aircraft.data
    omega, tau = d["main_rotor"]["omega"], apart[-1]
    res = floquet(scene, speed=0.0)
    (bar,) = [m for m in res.modes if m.name == "stabilizer bar"]
    assert bar.exponent.real == pytest.approx(-1 / tau, rel=1e-3)
    assert abs(bar.exponent.imag) < 1e-3 * omega
