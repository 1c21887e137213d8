"""Why the Bo105 misses its DLR flight-test trims where it does: each miss of the packaged
validation (``mbs/validate/data/bo105_flight_test.toml``) measured against the effect that makes
it, with the model's aerodynamics switches and the file's data.

Flight data: Padfield, Helicopter Flight Dynamics (1996), Fig. 4.10(a)-(d) p. 203 (controls) and
Fig. 4.6(a) p. 198 (pitch attitude), digitised by the HEROES authors (GitHub Musero45/TFG,
heroesData), and the power required of Fig. 4.11 p. 203 (the same authors' PowerBo105FlightTest.m).
Padfield's Helisim trims of the same figures were not digitised in any stored source, and no
flight-test weight, CG or density altitude for these points was found; so the model is not
compared with Helisim's trims here. Model: the Bo105 file as
shipped (2200 kg, ISA sea level, every aerodynamics switch on); "ours - flight" in deg.

| miss (ours - flight)                        | cause, measured                                                     |
|---------------------------------------------|---------------------------------------------------------------------|
| collective -1.01 at 100.2 kt (-0.50 at 80.7)| too little inflow through the disc at speed, not fully explained.   |
|                                             | The flight curve rises 2.42 deg from its bucket (50 kt) to 100 kt,  |
|                                             | ours 1.26 (from 67 kt). The collective follows the disc's forward   |
|                                             | tilt, i.e. the drag: hub drag (0.25 m^2, EST) is worth +0.37 deg,   |
|                                             | 1.5 deg per m^2, so the miss is ~0.7 m^2 of flat plate on top of    |
|                                             | the model's 1.02 (S1 fuselage) + 0.25. But the same drag pitches    |
|                                             | the aircraft -3.6 deg per m^2 (-0.90 for the hub): 0.7 m^2 would    |
|                                             | put ours ~1.7 deg nose-down of the flight test at 96 kt, where ours |
|                                             | is now 0.83 nose-up. So drag can take at most ~0.35 deg of the miss;|
|                                             | the rest is not drag. Not profile drag either: cd0 0.0074 -> 0.0094 |
|                                             | (file changed) moves the collective < 0.05 deg at 0, 50, 100 kt     |
|                                             | (power +5 to +8 %, tail collective +0.3). Not weight or density:    |
|                                             | ours is already +0.40 high in hover (14.66 against 14.26; at S2's   |
|                                             | 2096 kg 14.37 against S2's 14.32), and they move the hover as much  |
|                                             | as 100 kt (2096 kg -0.29 / -0.16 deg, ISA 1000 m (rho 1.112) +0.62 /|
|                                             | +0.51 deg at 0 / 100 kt). The rotor switches move hover and 100 kt  |
|                                             | alike (uniform inflow +0.00 / -0.06, tip loss off -0.38 / -0.34,    |
|                                             | compressibility off +0.59 / +0.55, download off -0.14 / -0.01).     |
| tail collective -1.4 / -2.0 at 82.6 / 101 kt| the fin: its side force unloads the tail rotor as V^2. The fin's    |
|                                             | incidence conflicts between transcriptions of S1: S1a +0.0812 rad   |
|                                             | (the file; a third public transcription, a C++ Bo105 model, has the |
|                                             | fin's zero-lift angle -0.08116 beside the tailplane's -0.0698 for   |
|                                             | S1's +0.0698 incidence: S1a's value), S1b -0.0612; Padfield's       |
|                                             | printed table not read. With S1b's the model lands within 0.1 deg   |
|                                             | of the flight test at both                                          |
|                                             | speeds (and moves < 0.35 deg at 15-31 kt), but S1b's fin then       |
|                                             | pushes against the tail rotor, which suggests a sign-convention     |
|                                             | difference rather than the true value: the file keeps S1a's. Power  |
|                                             | adds to it: cd0 +27 % gives +0.28 deg at 100 kt.                    |
| tail collective +2.72 / +2.61 at 22.5 / 31  | one step the model lacks: the flight test drops 3.67 deg between    |
|                                             | 15.2 and 22.5 kt, ours 1.28; before (ours - flight +0.34 at 15.2)   |
|                                             | and after (22.5 -> 31 kt: both fall 1.7-1.8 deg) the two agree. The |
|                                             | main-rotor wake is modelled at the tail surfaces only (not at the   |
|                                             | tail rotor): the tail-wake switch moves ours < 0.1 deg there. The   |
|                                             | usual cause of such a step, the main rotor's wake and tip vortices  |
|                                             | passing off the tail rotor, is an interaction the model does not    |
|                                             | have. Adding the wake tube's velocity at the tail hub to the air    |
|                                             | the tail rotor sees (an experiment, not shipped) changes no trim    |
|                                             | control by 0.0005 deg at 2.4-101 kt: the tube does not reach the    |
|                                             | hub, 6.08 m aft of the shaft and about 0.1 m below the disc plane,  |
|                                             | beyond the tube's 4.91 m edge. The step needs the tip vortices'     |
|                                             | passage near the disc's rear edge, not modelled.                    |
| pitch -1.24 / +1.81 at 26.7 / 38.6 kt       | the flight data's own scatter: a cubic through all 12 flight points |
|                                             | (rms residual 0.71 deg) leaves +1.12 and -1.38 deg at these two;    |
|                                             | ours is within 0.5 deg of that curve at both.                       |
| pitch +1.03 / +1.49 at 48.1 / 67.1 kt       | the main rotor's downwash at the horizontal tail (tail-wake switch,  |
| (and +0.8 at 78-96 kt)                      | 4.5 m/s = 1.9 v_i at 100 kt: the tail sits under the rear of the    |
|                                             | disc): +0.48 to +0.57 deg nose-up at 39-96 kt; ours - flight curve  |
|                                             | at 67 / 96 kt +1.34 / +0.63 with it, +0.79 / +0.06 without. Its size|
|                                             | at a tail under the disc is the wake model's, not measured for the  |
|                                             | Bo105; the tailplane incidence also conflicts (S1 4 deg, S2 0).     |
| power +13 to +17 % at 8-27 kt               | ours is momentum theory's (Glauert's inflow with the file's kappa   |
| (out of 10 % at 8.2, 11.7, 21.7, 26.5 kt)   | 1.15, EST, and tip loss; profile power from cd0, cd2; the drag):    |
|                                             | 1.3-1.6 % below it at 20.4-26.5 kt. The flight test's main-rotor    |
|                                             | power (its power less the file's accessories, losses and ours' tail |
|                                             | rotor) is 11-17 % below it, and falls 13 % from 4 to 8.2 kt where   |
|                                             | momentum theory falls 2 %; its points scatter 8 % at 20.4 / 21.7 kt.|
|                                             | A kappa of 0.9-1.0 would be needed there, ideal momentum theory's.  |
| power -16 / -24 % at 78 / 99 kt             | with the collective at 100 kt: too little inflow through the disc.  |
|                                             | The main-rotor power the flight test needs at 99 kt is 81 kW more   |
|                                             | than ours; the collective's -1.01 deg asks for 63 kW of it as       |
|                                             | induced power (blade-element theory: d theta / d lambda = 1.5 (1 -  |
|                                             | mu^2/2) / (1 + 1.5 mu^2), 1.35 at mu 0.23; Delta lambda 0.013, more |
|                                             | than ours' whole induced inflow, 0.012). Not drag: the 0.96 m^2 of  |
|                                             | flat plate that would supply 81 kW would pitch ours 3.5 deg further |
|                                             | nose-down, where ours is 0.84 deg nose-up of the flight test at     |
|                                             | 95.8 kt. The rest (about 18 kW) is the size of the profile drag's   |
|                                             | +27 % (cd0 0.0094, +5 to +8 % power). An induced power factor of    |
|                                             | about 2.4 at mu 0.23 against the file's 1.15 is not in the model.   |

Longitudinal cyclic (within 1.5 deg everywhere; -2.36 against -3.17 at 105 kt) follows the
collective's cause: the hub drag alone moves it -0.41 deg at 100 kt.

CG: the hub-CG offset's sign is ambiguous between S1's transcriptions (the file: hub 0.08 m aft
of the CG, S1a). Measured with the other sign (file changed): pitch +0.9 deg at every speed (hover
3.05 against the flight test's 2.71, but 96 kt -2.72 against -4.34) and the hover longitudinal
cyclic 0.12 against 2.0 deg (1.9 out of the 1.5 deg tolerance; the file's sign: 0.90). The hover
cyclic keeps the file's sign, and no CG shift moves the speed-dependent misses above.
"""
from __future__ import annotations

import math

import numpy as np
import pytest

KNOT = 0.514444  # m/s
ALL_ON = "pitt-peters,tip-loss,compressibility,tail-wake,download,hub-drag"
SHIPPED_KT = (2.402, 4.021, 8.185, 15.23, 20.42, 21.69, 22.53, 26.5, 26.65, 31.02, 38.59, 67.09, 77.86, 82.62,
              95.78, 99.22, 100.2, 101.0)
NO_TAIL_WAKE_KT = (15.23, 22.53, 38.59, 67.09, 95.78)
FIN = 'incidence = { value = 0.0812, unit = "rad", source = "S1a"'
FIN_S1B = 'incidence = { value = -0.0612, unit = "rad", source = "S1b"'


def flight(quantity: str) -> dict[float, float]:
    """The DLR flight test's ``quantity`` (deg) by speed (kt, as printed) from Padfield's figures."""
    from mbs.validate import load

    series = next(s for s in load("bo105_flight_test").of_kind("trim") if s.quantity == quantity and "P1" in s.source)
    return {round(float(v), 2): float(x) for v, x in zip(series.shown_speed, series.value)}


def trims(speeds_kt, aero: str = ALL_ON, aircraft=None) -> dict[float, dict[str, float]]:
    """Our trims (controls and pitch in deg; main-rotor, tail-rotor and engine power in kW, thrust
    in N, the main rotor's induced inflow ratio) by speed (kt)."""
    from mbs import aircraft as craft, scenes
    from mbs.models.helicopter import with_aero
    from mbs.validate.ours import run

    scene = with_aero(scenes.get("forward-flight", aircraft=craft.load(aircraft or "bo105")), aero)
    model = run(scene, [v * KNOT for v in speeds_kt], [])
    out = {}
    for v in speeds_kt:
        point = model.at(v * KNOT)
        assert point.ok, f"{v} kt: {point.problem}"
        t = point.trim
        out[round(v, 2)] = {**{k: math.degrees(x) for k, x in t.controls.items()}, "pitch": math.degrees(t.pitch),
                            "power": t.output_means["main_rotor.power"] / 1e3,
                            "tail_power": t.output_means["tail_rotor.power"] / 1e3,
                            "engine_power": t.output_means["engine.power"] / 1e3,
                            "thrust": t.output_means["main_rotor.thrust"],
                            "inflow": t.output_means["main_rotor.inflow_ratio"]}
    return out


@pytest.fixture(scope="module")
def shipped():
    return trims(SHIPPED_KT)


@pytest.fixture(scope="module")
def no_tail_wake():
    return trims(NO_TAIL_WAKE_KT, "pitt-peters,tip-loss,compressibility,download,hub-drag")


@pytest.fixture(scope="module")
def no_hub_drag():
    return trims((100.2,), "pitt-peters,tip-loss,compressibility,tail-wake,download")


@pytest.fixture(scope="module")
def fin_s1b(tmp_path_factory):
    """The Bo105 with S1b's fin incidence (-0.0612 rad) in place of S1a's, nothing else changed."""
    from mbs import aircraft as craft

    text = craft.resolve("bo105").read_text()
    assert text.count(FIN) == 1, "the file's fin incidence is no longer S1a's 0.0812 rad: revisit this test"
    path = tmp_path_factory.mktemp("fin") / "bo105_fin_s1b.toml"
    path.write_text(text.replace(FIN, FIN_S1B))
    return trims((15.23, 22.53, 82.62, 101.0), aircraft=str(path))


def test_collective_at_100_kt_is_not_weight_density_nor_only_drag(shipped, no_hub_drag):
    """Ours - flight: +0.40 in hover, -1.01 at 100.2 kt; the flight curve's rise from 50 to 100 kt
    is twice ours; hub drag 0.25 m^2 is worth +0.37 deg (1.5 deg/m^2), so the miss is ~0.7 m^2 of
    drag, which would pitch ours -2.5 deg (-3.6 deg/m^2): 1.7 deg nose-down of the flight test at
    96 kt, where ours is 0.83 nose-up. Drag explains at most a third of the miss (0.23 m^2, 0.35 deg)."""
    fc, ours = flight("collective"), {v: t["collective"] for v, t in shipped.items()}
    miss = ours[100.2] - fc[100.2]
    print(f"collective at 100.2 kt: ours {ours[100.2]:.2f}, flight {fc[100.2]:.2f}, miss {miss:+.2f}")
    assert -1.2 < miss < -0.8
    hub = ours[100.2] - no_hub_drag[100.2]["collective"]
    area = -miss / (hub / 0.25)
    print(f"hub drag 0.25 m^2: {hub:+.2f} deg, {no_hub_drag[100.2]['power'] - shipped[100.2]['power']:+.1f} kW; "
          f"the miss is {area:.2f} m^2 of flat plate")
    assert 0.25 < hub < 0.5 and 0.5 < area < 0.9
    # but drag that large would pitch ours far nose-down of the flight test at 96 kt
    pitch_per_area = (shipped[100.2]["pitch"] - no_hub_drag[100.2]["pitch"]) / 0.25
    room = shipped[95.78]["pitch"] - flight("pitch")[95.78]
    print(f"drag pitches {pitch_per_area:+.2f} deg/m^2; room at 95.8 kt {room:+.2f} deg")
    assert pitch_per_area < -3.0 and 0.5 < room < 1.2
    assert room + pitch_per_area * area < -1.0
    # from the bucket to 100 kt ours rises little more than half as much as the flight test
    # (flight 50.1 -> 100.2 kt: +2.42 deg; ours 67.1 -> 100.2 kt, its bucket: +1.26)
    assert ours[100.2] - ours[67.09] < 0.6 * (fc[100.2] - fc[50.09])
    # heavier or higher would lift the 100 kt collective, but ours is already high in hover (2.4 kt)
    assert ours[2.4] - fc[0.1] > 0.2


def test_tail_collective_at_speed_turns_on_the_fin_incidence(shipped, fin_s1b):
    """S1a's fin incidence (+0.0812 rad, the file): ours 1.35 and 2.02 deg low at 82.6 and 101 kt;
    S1b's (-0.0612): +0.07 and -0.09, and < 0.35 deg different at 15-23 kt."""
    ft = flight("tail_collective")
    for v in (82.62, 101.0):
        s1a, s1b = shipped[v]["tail_collective"] - ft[v], fin_s1b[v]["tail_collective"] - ft[v]
        print(f"tail collective at {v} kt: S1a fin {s1a:+.2f}, S1b fin {s1b:+.2f}")
        assert s1a < -1.2 and abs(s1b) < 0.3
    for v in (15.23, 22.53):
        assert abs(fin_s1b[v]["tail_collective"] - shipped[v]["tail_collective"]) < 0.35


def test_tail_collective_at_23_31_kt_is_one_step_the_model_lacks(shipped, no_tail_wake):
    """The flight test drops 3.67 deg from 15.2 to 22.5 kt, ours 1.28; ours - flight +0.34 before,
    +2.72 and +2.61 after (both fall 1.7-1.8 deg to 31 kt); the tail-wake switch moves ours < 0.1."""
    ft = flight("tail_collective")
    off = {v: shipped[v]["tail_collective"] - ft[v] for v in (15.23, 22.53, 31.02)}
    print("tail collective ours - flight:", {v: round(d, 2) for v, d in off.items()})
    assert abs(off[15.23]) < 0.6
    assert off[22.53] - off[15.23] > 2.0
    assert abs(off[31.02] - off[22.53]) < 0.3
    for v in (15.23, 22.53):
        assert abs(no_tail_wake[v]["tail_collective"] - shipped[v]["tail_collective"]) < 0.2


def _flight_pitch_curve():
    fp = flight("pitch")
    speeds = np.array(list(fp))
    return fp, np.poly1d(np.polyfit(speeds, np.array(list(fp.values())), 3))


def test_pitch_at_27_and_39_kt_is_the_flight_datas_scatter(shipped):
    """A cubic through the 12 flight points leaves +1.12 and -1.38 deg at 26.7 and 38.6 kt (rms
    residual 0.71 deg); ours is within 0.5 deg of that curve at both."""
    fp, curve = _flight_pitch_curve()
    for v, sign in ((26.65, 1), (38.59, -1)):
        scatter, ours = fp[v] - curve(v), shipped[v]["pitch"] - curve(v)
        print(f"pitch at {v} kt: flight - curve {scatter:+.2f}, ours - curve {ours:+.2f}")
        assert sign * scatter > 1.0 and abs(ours) < 0.6


def test_pitch_from_48_kt_is_nose_up_by_the_downwash_at_the_tail(shipped, no_tail_wake):
    """The tail-wake downwash adds +0.48 to +0.57 deg nose-up at 39-96 kt; ours - flight curve at
    67 and 96 kt +1.34 and +0.63 with it, +0.79 and +0.06 without."""
    _, curve = _flight_pitch_curve()
    for v in (38.59, 67.09, 95.78):
        wake = shipped[v]["pitch"] - no_tail_wake[v]["pitch"]
        print(f"pitch at {v} kt: tail wake {wake:+.2f}; ours - flight curve {shipped[v]['pitch'] - curve(v):+.2f}, "
              f"without the wake {no_tail_wake[v]['pitch'] - curve(v):+.2f}")
        assert 0.35 < wake < 0.8
    assert shipped[67.09]["pitch"] - curve(67.09) > 1.0
    assert all(abs(no_tail_wake[v]["pitch"] - curve(v)) < 0.9 for v in (67.09, 95.78))


def momentum_power(speed_kt: float, thrust: float) -> float:
    """Main-rotor power (kW) of the Bo105 file's rotor at ``thrust`` (N) in level flight by
    momentum and blade-element theory: kappa T v_i with Glauert's induced velocity
    (v^4 + V^2 v^2 = v_h^4, v_h^2 = T / (2 rho A B^2), B the tip-loss factor), the profile power
    (sigma delta / 8) rho A (Omega R)^3 (1 + 4.65 mu^2) with delta the section drag at the mean
    angle of attack 6 C_T / (sigma a), and the fuselage's and hub's drag times V."""
    from mbs import aircraft

    d = aircraft.load("bo105").data
    rotor, rho, fuselage = d["main_rotor"], d["environment"]["rho"], d["fuselage_aero"]
    area, tip, v = math.pi * rotor["radius"] ** 2, rotor["radius"] * rotor["omega"], speed_kt * KNOT
    sigma = rotor["n_blades"] * rotor["chord"] / (math.pi * rotor["radius"])
    vh2 = thrust / (2 * rho * area * rotor["tip_loss"] ** 2)
    induced = math.sqrt((-v**2 + math.sqrt(v**4 + 4 * vh2**2)) / 2)
    ct = thrust / (rho * area * tip**2)
    delta = rotor["cd0"] + rotor["cd2"] * (6 * ct / (sigma * rotor["lift_slope"])) ** 2
    profile = sigma * delta / 8 * rho * area * tip**3 * (1 + 4.65 * (v / tip) ** 2)
    flat_plate = -fuselage["X"][0] / (0.5 * rho * fuselage["v_ref"] ** 2) + d["hub_drag"]["flat_plate_area"]
    return (rotor["kappa"] * thrust * induced + profile + flat_plate * 0.5 * rho * v**3) / 1e3


def flight_rotor_power(shipped, speed_kt: float) -> float:
    """The flight test's main-rotor power (kW) at ``speed_kt``: its power required less the file's
    accessory power, times its transmission efficiency, less ours' tail-rotor power."""
    from mbs import aircraft
    from mbs.validate import load

    engine = aircraft.load("bo105").data["engine"]
    series = next(s for s in load("bo105_flight_test").of_kind("trim") if s.quantity == "engine.power")
    power = next(float(x) for v, x in zip(series.shown_speed, series.value) if abs(v - speed_kt) < 1e-6)
    return (power - engine["accessory_power"] / 1e3) * engine["transmission_efficiency"] \
        - shipped[round(speed_kt, 2)]["tail_power"]


def test_power_at_20_to_27_kt_is_momentum_theorys_and_the_flight_test_below_it(shipped):
    """Ours within 2.5 % of momentum theory at 20.4, 21.7 and 26.5 kt (measured -1.3 to -1.6 %);
    the flight test's main-rotor power 11-17 % below momentum theory there, and its fall from 4 to
    8.2 kt (13 %) six times momentum theory's (2 %)."""
    for v in (20.42, 21.69, 26.5):
        closed, ours = momentum_power(v, shipped[v]["thrust"]), shipped[v]["power"]
        flight = flight_rotor_power(shipped, v)
        print(f"{v} kt: ours {ours:.1f} kW, momentum theory {closed:.1f}, flight {flight:.1f} ({flight / closed:.2f})")
        assert ours == pytest.approx(closed, rel=0.025)
        assert 0.8 < flight / closed < 0.91
    fall = 1 - flight_rotor_power(shipped, 8.185) / flight_rotor_power(shipped, 4.021)
    glauert = 1 - momentum_power(8.185, shipped[round(8.185, 2)]["thrust"]) \
        / momentum_power(4.021, shipped[round(4.021, 2)]["thrust"])
    print(f"4 -> 8.2 kt: flight -{100 * fall:.1f} %, momentum theory -{100 * glauert:.1f} %")
    assert fall > 4 * glauert


def test_power_at_99_kt_is_the_collectives_missing_inflow_not_drag(shipped, no_hub_drag):
    """The flight test needs 81 kW more main-rotor power than ours at 99 kt; the collective's
    -1.01 deg at 100 kt asks for 63 kW of it as induced power (Delta lambda = Delta theta /
    (1.5 (1 - mu^2/2) / (1 + 1.5 mu^2))); drag supplying it (0.96 m^2) would pitch ours 3.5 deg
    further nose-down, 2.6 deg past the flight test's attitude at 95.8 kt."""
    from mbs import aircraft

    rotor = aircraft.load("bo105").data["main_rotor"]
    v, tip = 99.22, rotor["radius"] * rotor["omega"]
    gap = flight_rotor_power(shipped, v) - shipped[v]["power"]
    mu = v * KNOT / tip
    slope = 1.5 * (1 - mu**2 / 2) / (1 + 1.5 * mu**2)
    miss = math.radians(flight("collective")[100.2] - shipped[100.2]["collective"])
    induced = shipped[v]["thrust"] * miss / slope * tip / 1e3
    print(f"99.2 kt: flight needs {gap:+.1f} kW at the main rotor; the collective's miss asks for {induced:.1f} kW "
          f"(Delta lambda {miss / slope:.4f}, ours' induced inflow {shipped[v]['inflow']:.4f})")
    assert 70 < gap < 95 and 0.6 < induced / gap < 0.95
    assert miss / slope > 0.8 * shipped[v]["inflow"]
    # as drag: the hub's 0.25 m^2 is worth its power and its nose-down pitch per m^2
    hub_kw = shipped[100.2]["power"] - no_hub_drag[100.2]["power"]
    per_area = (shipped[100.2]["pitch"] - no_hub_drag[100.2]["pitch"]) / 0.25
    area = gap / (hub_kw / 0.25)
    room = shipped[95.78]["pitch"] - flight("pitch")[95.78]
    print(f"as drag: {area:.2f} m^2, pitching ours {per_area * area:+.2f} deg; "
          f"ours - flight pitch at 95.8 kt {room:+.2f}")
    assert area > 0.8 and room + per_area * area < -2.0
    assert shipped[77.86]["engine_power"] < 0.9 * 264.8 and shipped[v]["engine_power"] < 0.8 * 351.7
