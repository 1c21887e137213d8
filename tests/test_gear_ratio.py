"""The real tail-rotor gear ratio in trim, Floquet and derivatives: the common period of the
rotors (a flapping hub's blades exchanging their states after a blade passage), and the nearest
ratio that repeats for one that does not, with its error measured."""
import json
import math
import re

import numpy as np
import pytest

from aircraft_files import entries, uh60_tailed, with_tail_rotor, write
from mbs import aircraft, scenes
from mbs.aircraft.checks import periodic_gear
from mbs.analysis.derivatives import derivatives
from mbs.analysis.period import periodic_scene, rotor_period, tail_collective_error
from mbs.analysis.trim import evaluators, periodic_solution

DEG = math.pi / 180
FLAPPING = {"hub_type": ("flapping", "-"), "n_blades": (4, "-"), "flap_hinge_offset": (0.08, "m"),
            "flap_stiffness": (400.0, "N m/rad"), "cant": (20.0, "deg"), "toe": (5.0, "deg"), "delta3": (30.0, "deg"),
            "precone": (3.0, "deg")}
"""The Bo105 with a four-blade flapping tail rotor (as in tests/test_tail_rotor.py's mirror test)."""


@pytest.mark.parametrize("ratio, blades, used, revs", [
    (4.82, 5, 4.82, 10), (4.8, 5, 4.8, 1), (5.8, 4, 5.8, 5), (5.25, 1, 5.25, 4), (4.6155, 4, 60 / 13, 13)])
def test_the_periodic_gear_is_the_ratio_itself_or_the_nearest_that_repeats(ratio, blades, used, revs):
    """A ratio whose rotors repeat within 16 revolutions is kept (the Puma's 4.82 with its five
    blades after 10); the UH-60A's 4.6155 (18.462 passages of four blades per revolution,
    repeating after 500) becomes 60/13, the shortest period within 1e-4 of its speed."""
    gear = periodic_gear(ratio, blades)
    assert (gear.used, gear.revs) == (pytest.approx(used, abs=1e-15), revs)
    assert gear.exact == (used == ratio)
    if not gear.exact:
        assert gear.speed_error == pytest.approx(-2.49994e-5, rel=1e-5) and gear.exact_revs == 500
        assert periodic_gear(ratio, blades, max_revs=2).used == 4.625


# -- a flapping hub: one blade passage, the blades exchanged ------------------------------------

@pytest.fixture(scope="module")
def flapping(tmp_path_factory):
    """The Bo105 with a flapping four-blade tail rotor (5.25: 21 blade passages a revolution):
    its forward-flight scene and compiled evaluators."""
    path = tmp_path_factory.mktemp("flapping") / "plain.toml"
    sc = scenes.get("forward-flight", aircraft.load(write(with_tail_rotor(entries("bo105"), **FLAPPING), path)))
    return sc, *evaluators(sc)


def test_a_flapping_hub_repeats_after_a_blade_passage_with_its_blades_exchanged(flapping):
    """After one main-rotor revolution the tail rotor has turned 21 quarter turns: blade ``j - 1``
    is where blade ``j`` was, so ``S`` takes blade ``j - 1``'s flap to blade ``j`` and the model
    satisfies ``S f(x, t + T) = f(S x, t)`` at a generic state; the whole period is 4 revolutions."""
    sc, system, _ = flapping
    period = rotor_period(system.info, sc.omega, 5.25)
    names = system.info.state_names
    assert (period.revs, period.full_revs) == (1, 4)
    moved = {names[k]: names[i] for k, i in enumerate(period.source) if i != k}
    assert moved == {f"tail_blade{j}.{s}": f"tail_blade{(j - 2) % 4 + 1}.{s}" for j in range(1, 5)
                     for s in ("flap", "flap_rate")}
    x = system.run(system.x0(**{f"tail_blade{k}.flap": 0.01 * k for k in range(1, 5)}), 0.0, 1e-3, 37).x[-1]
    t = 0.0123
    lhs, rhs = period.apply(system.rhs(x, t + period.duration)), system.rhs(period.apply(x), t)
    assert np.abs(lhs - rhs).max() <= 1e-9 * np.abs(lhs).max()
    assert np.abs(lhs - system.rhs(x, t)).max() > 1e-3 * np.abs(lhs).max()  # the exchange matters


def test_a_flapping_tail_rotor_trims_over_one_revolution_and_repeats_over_four(flapping):
    """The trim shoots over one revolution with the tail blades exchanged; run on over the whole
    period of four, the aircraft's states come back (position advanced by the flight path). The
    derivatives' held rotor is periodic over the same revolution with the same exchange."""
    from mbs.analysis.derivatives import linearise
    from mbs.analysis.held import HeldStepper

    sc, system, stepper = flapping
    res = periodic_solution(sc, 20.0, system=system, stepper=stepper)
    assert res.converged, res.reason
    assert (res.period.revs, res.period.full_revs) == (1, 4) and res.period_summary()["exchanged"]
    n = 4 * res.steps_per_rev
    x = system.run(res.x0, 0.0, res.period.revolution / res.steps_per_rev, n, every=n, p=res.params).x[-1]
    names = system.info.state_names
    keep = [i for i, s in enumerate(names) if s not in ("fuselage.x", "fuselage.y", "fuselage.z")]
    scale = np.array([max(1.0, abs(res.x0[i])) for i in keep])
    assert np.abs((x[keep] - res.x0[keep]) / scale).max() < 1e-7
    assert x[names.index("fuselage.x")] == pytest.approx(20.0 * 4 * res.period.revolution, rel=1e-7)
    d = linearise(res, system, HeldStepper(sc.model(), "rk4", "compiled"), res.radius)
    assert d.held.converged and d.held.residual < 1e-10 and d.table["N_θ0T"] != 0.0


# -- the Puma at its real 4.82 -----------------------------------------------------------------------

def _puma(tmp_path_factory, gear: float):
    path = tmp_path_factory.mktemp("puma") / f"puma_{gear}.toml"
    return scenes.get("forward-flight", aircraft.load(write(with_tail_rotor(entries("puma"), gear_ratio=(gear, "-")),
                                                            path)))


@pytest.fixture(scope="module")
def puma(tmp_path_factory):
    """The Puma's trims at 40 m/s with its tail rotor at 4.8 (the file's, one revolution) and at
    the published 4.82 (ten), the 4.82 scene and its evaluators."""
    trims, out = {}, {}
    for gear in (4.8, 4.82):
        sc = _puma(tmp_path_factory, gear)
        system, stepper = evaluators(sc)
        trims[gear] = periodic_solution(sc, 40.0, system=system, stepper=stepper)
        assert trims[gear].converged, trims[gear].reason
        out = {"scene": sc, "system": system, "stepper": stepper}
    return trims, out


def test_the_puma_trims_at_its_published_gear_ratio_over_its_ten_revolution_period(puma):
    """4.82 with five rigid tail blades: 24.1 blade passages a revolution, the rotors back in
    place after 10 revolutions; the trim shoots over them (no approximation) and converges."""
    trims, _ = puma
    res = trims[4.82]
    assert (res.period.revs, res.period.full_revs) == (10, 10) and res.period.gear.exact
    assert res.tail_collective_error == 0.0 and max(res.residuals[-1:]) < 1e-10


def test_the_speed_error_of_a_nearby_ratio_moves_the_tail_collective_as_estimated(puma):
    """The error of turning the tail rotor at a nearby ratio, measured against the exact common
    period: the Puma at 4.8 (the tail rotor 0.41 % slow) against 4.82 at 40 m/s. The tail
    collective moves by 0.024° (the report's blade-element momentum estimate 0.023°, within
    20 %); every other control and attitude by less than 3 % of that. For the UH-60A's 60/13
    (25 ppm) the same estimate is 1.3e-4° (tests below)."""
    trims, _ = puma
    moved, estimate, others = _moved(trims[4.8], trims[4.82], 4.8 / 4.82 - 1, "4.8 against 4.82 at 40 m/s")
    assert moved == pytest.approx(estimate, rel=0.2)
    assert others < 0.03 * abs(moved)


def _moved(trim, reference, eps: float, what: str) -> tuple[float, float, float]:
    """How far ``trim`` (its tail rotor ``eps`` faster) moved from ``reference``: the tail
    collective, its estimate, and the largest move of the other controls and attitudes (rad)."""
    estimate = tail_collective_error(eps, *reference.tail_thrust_coefficient)
    moved = trim.controls["tail_collective"] - reference.controls["tail_collective"]
    print(f"{what}: tail collective {moved / DEG:+.5f} deg (estimate {estimate / DEG:+.5f})")
    others = [trim.controls[k] - reference.controls[k] for k in ("collective", "lateral_cyclic", "longitudinal_cyclic")]
    return moved, estimate, float(np.abs([*others, trim.pitch - reference.pitch, trim.roll - reference.roll]).max())


def test_floquet_and_derivatives_of_the_puma_at_its_published_gear_ratio(puma):
    """The Floquet analysis over the 10-revolution period and the derivatives (held rotor
    periodic over 10 revolutions) at 4.82: stable rotor modes, the phugoid and the yaw
    derivatives of the tail rotor as at 4.8 (within 1 %: a 0.4 % faster tail rotor)."""
    from mbs.analysis.derivatives import linearise
    from mbs.analysis.floquet import in_fixed_frame
    from mbs.analysis.held import HeldStepper

    trims, ev = puma
    res = in_fixed_frame(trims[4.82], ev["system"], ev["stepper"])
    assert res.period_revs == 10 and res.interval_revs == 10
    assert all(m.damping > 0 for m in res.modes if m.group in ("flap", "lag", "inflow"))
    held = HeldStepper(ev["scene"].model(), "rk4", "compiled")
    d = linearise(trims[4.82], ev["system"], held, trims[4.82].radius)
    assert d.held.converged and d.summary()["period"]["revs"] == 10
    ref = derivatives(_puma_scene_48(ev["scene"]), 40.0)
    for key in ("N_r", "N_v", "N_θ0T", "Y_θ0T"):
        assert d.table[key] == pytest.approx(ref.table[key], rel=0.01), key


def _puma_scene_48(sc):
    """The scene of the same aircraft with the file's 4.8."""
    return periodic_scene(sc, max_revs=1)


@pytest.mark.parametrize("ratio, listed", [
    (5.25, {"rotor period (both rotors back in place)": 4, "period of the periodic analyses": 4}),
    (4.615, {"rotor period (both rotors back in place)": 200, "period of the periodic analyses": 13}),
    (4.615418, {"period of the periodic analyses": 13})])
def test_aircraft_check_lists_the_rotor_period_only_where_there_is_one(tmp_path, ratio, listed):
    """4.615418 repeats only after 500,000 revolutions: the check listed '995 rev' (the nearest
    fraction's) beside its own warning of more than 1000 (a new user's Prouty helicopter)."""
    raw = entries("bo105")
    raw["tail_rotor"]["gear_ratio"]["value"] = ratio
    figures = {n: v for n, v, _ in aircraft.check(write(raw, tmp_path / "gear.toml")).figures if "period" in n}
    assert figures == listed


def test_a_tail_rotor_speed_as_published_gives_the_gear_ratio(tmp_path):
    """``tail_rotor.omega`` in rpm (a report printing 954.93 rpm beside the main rotor's 206.9: a new
    user divided by hand) replaces ``gear_ratio``, its ratio to main_rotor.omega, listed as derived."""
    raw = entries("bo105")
    main_rpm = aircraft.load("bo105").data["main_rotor"]["omega"] * 60 / (2 * math.pi)
    del raw["tail_rotor"]["gear_ratio"]
    raw["tail_rotor"]["omega"] = {"value": 5.25 * main_rpm, "unit": "rpm", "source": "report"}
    path = write(raw, tmp_path / "tail_rpm.toml")
    report = aircraft.check(path)
    assert report.ok, report.problems
    assert aircraft.load(path).data["tail_rotor"]["gear_ratio"] == pytest.approx(5.25, rel=1e-12)
    assert any(e == "tail_rotor.gear_ratio" for e, *_ in report.derived)
    raw["tail_rotor"]["gear_ratio"] = {"value": 5.25, "unit": "-", "source": "report"}
    both = aircraft.check(write(raw, tmp_path / "both.toml"))
    assert any(p.startswith("tail_rotor.omega: replaces tail_rotor.gear_ratio") for p in both.problems), both.problems


# -- the UH-60A's 4.6155 -------------------------------------------------------------------------------

@pytest.fixture(scope="module")
def uh60(tmp_path_factory):
    """The Puma with the UH-60A's tail rotor (four flapping blades, δ3 35°, cant 20°, 4.6155):
    its trims at 20 m/s at 60/13 (what the periodic analyses use) and at 37/8 (the near ratio
    the trim starts from), the scene and evaluators."""
    sc = scenes.get("forward-flight", aircraft.load(uh60_tailed(tmp_path_factory.mktemp("uh60") / "uh60.toml")))
    system, stepper = evaluators(sc)
    res = periodic_solution(sc, 20.0, system=system, stepper=stepper)
    assert res.converged, res.reason
    near = periodic_solution(periodic_scene(sc, max_revs=2), 20.0)
    assert near.converged, near.reason
    return res, near, {"scene": sc, "system": system, "stepper": stepper}


def test_the_uh60a_gear_ratio_trims_at_60_13_and_says_so(uh60):
    """4.6155 repeats only after 500 revolutions: the trim turns the tail rotor at 60/13 (25 ppm
    slow) over 13 revolutions, converges, and its report and JSON say which ratio, the speed
    error and the estimated error of the tail collective (1.4e-4°)."""
    from mbs.commands import _trim_lines

    res, _, _ = uh60
    per = res.period_summary()
    assert per["revs"] == 13 and per["gear_ratio"] == 4.6155 and per["gear_ratio_used"] == pytest.approx(60 / 13)
    assert per["tail_speed_error"] == pytest.approx(-2.49994e-5, rel=1e-5)
    assert 0 < per["tail_collective_error"] < 5e-6
    line = next(x for x in _trim_lines(res) if "approximation" in x)
    assert "4.6155 repeats the rotors only every 500" in line and "4.6153846 instead (period 13" in line
    error = float(re.search(r"estimated error of the tail collective ([+-][\d.e-]+) deg", line).group(1))
    assert 0 < error < 2e-4  # the tail rotor 0.0025 % slow: a ten-thousandth of a degree
    json.dumps(res.summary())


def test_the_uh60a_trim_moves_from_its_near_ratio_as_the_estimate_says(uh60):
    """Measured error of the nearby ratio: from 37/8 (the tail rotor 0.206 % fast) to 60/13
    (25 ppm slow) the tail collective moves by what the report's estimate gives for the
    difference of their speed errors (within 20 %), the other controls and attitudes by less
    than 10 % of it: 60/13's own error, 82 times smaller than 37/8's, is 1.3e-4° on the tail
    collective and less than 1.3e-5° elsewhere."""
    res, near, _ = uh60
    eps_near, eps = near.period.gear.speed_error, res.period.gear.speed_error
    assert eps_near == pytest.approx(2.0583e-3, rel=1e-4)
    moved, estimate, others = _moved(near, res, eps_near - eps, "37/8 against 60/13 at 20 m/s")
    assert moved == pytest.approx(estimate, rel=0.2)
    assert others < 0.1 * abs(moved)


def test_floquet_and_derivatives_of_the_uh60a_tail_rotor(uh60):
    """Floquet over the 13-revolution period (the tail blades' flap modes among the modes, heavily
    damped) and the derivatives: the canted tail rotor's collective gives heave and pitch as well
    as yaw (``Z_θ0T``, ``M_θ0T`` negative: the tail lifts, the nose drops)."""
    from mbs.analysis.derivatives import linearise
    from mbs.analysis.floquet import in_fixed_frame
    from mbs.analysis.held import HeldStepper

    res, _, ev = uh60
    flo = in_fixed_frame(res, ev["system"], ev["stepper"])
    assert flo.period_revs == 13 and flo.summary()["period"]["gear_ratio_used"] == pytest.approx(60 / 13)
    tail = [m for m in flo.modes if m.group == "tail rotor"]
    assert len(tail) >= 4 and all(m.damping > 10.0 for m in tail)
    held = HeldStepper(periodic_scene(ev["scene"]).model(), "rk4", "compiled")
    d = linearise(res, ev["system"], held, res.radius)
    assert d.held.converged
    assert d.table["Z_θ0T"] < 0 and d.table["M_θ0T"] < 0 and abs(d.table["N_θ0T"]) > 1.0


def test_a_run_starts_from_the_trim_of_a_gear_ratio_that_does_not_repeat(tmp_path, capsys):
    """A new user's R22 (tail tip speed 622 ft/s: gear ratio 6.4076) trimmed, but 'heli simulate'
    then stopped checking the trim it had just made, naming the gear ratio; the engine failure
    the same. The trim's check runs over the period it was trimmed over: a forward-flight run
    starts from the trim and a second run from the stored one; the engine failure from its
    governed trim."""
    from mbs.cli import main

    text = aircraft.resolve("bo105").read_text().replace('gear_ratio = { value = 5.25,', 'gear_ratio = { value = 5.2513,')
    path = tmp_path / "odd_gear.toml"
    path.write_text(text)
    for k in range(2):
        assert main(["simulate", "forward-flight", "--aircraft", str(path), "--revs", "1", "--out",
                     str(tmp_path / f"ff{k}")]) == 0
        err = capsys.readouterr().err
        assert ("trimming it now" if k == 0 else "starting from the periodic trim") in err, err
    assert main(["simulate", "engine-failure", "--aircraft", str(path), "--revs", "2", "--out",
                 str(tmp_path / "ef")]) == 0
    assert "trimmed in" in capsys.readouterr().err
