"""Rotor loads at the periodic trim: the rotor as a filter of the hub loads (and the 1/rev a
heavier blade brings), the hover balance of hub loads against thrust and power, the engine
power's definition, and ``heli loads``."""
import json
import sys
from dataclasses import replace

import numpy as np
import pytest

from mbs import scenes
from mbs.analysis.trim import evaluators, trim
from mbs.cli import main
from mbs.forces import PointForce
from mbs.loads.analysis import rotor_loads
from mbs.loads.outputs import COMPONENTS
from mbs import aircraft
from mbs.models import helicopter
from mbs.models.helicopter.frames import shaft_frame, tail_hub_position
from mbs.models.helicopter.scenes import SCENE_CONFIGS

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover
    import tomli as tomllib

FILTER = 1e-8  # other harmonics per steady thrust, the bound (measured: below 1e-12)


def variant(scene: str, heavier: float = 1.0, steady_tail: bool = False) -> scenes.Scene:
    """The Bo105 ``scene`` with blade 1's mass and inertia scaled by ``heavier``; with
    ``steady_tail``, its tail rotor replaced by its thrust as a steady side force at the tail
    hub (a trim control, ``tail_thrust``): then the main rotor alone makes the airframe move,
    and the periodic solution repeats every revolution."""
    craft = aircraft.load()
    d = craft.data
    cfg = replace(SCENE_CONFIGS[scene][0], tail_rotor=not steady_tail)
    name = f"{scene}{'-steady-tail' if steady_tail else ''}-blade1x{heavier:g}"

    def make(aircraft=None, **options):
        m = helicopter.build(replace(cfg, **options), d, name=f"bo105-{name}")
        if steady_tail:
            m.add_parameter("tail_thrust", 1000.0, "N", "tail-rotor thrust as a steady side force", control=True,
                            low=-5000.0, high=5000.0)
            m.add_force(PointForce("tail thrust", "fuselage", [0.0, "tail_thrust", 0.0], tail_hub_position(d)))
        blade = m.bodies["blade1"]
        blade.mass, blade.inertia = blade.mass * heavier, blade.inertia * heavier
        return m
    make.config = cfg
    return scenes.Scene(name, f"{scene} variant", make, omega=d["main_rotor"]["omega"], aircraft=craft)


@pytest.fixture(scope="module")
def identical():
    return rotor_loads(variant("forward-flight", steady_tail=True))


@pytest.fixture(scope="module")
def heavier():
    return rotor_loads(variant("forward-flight", 1.05, steady_tail=True))


def imbalance() -> float:
    """The centrifugal force of 5 % of a blade's mass, ``0.05 m Ω² r_cg`` (N)."""
    mr = aircraft.load().data["main_rotor"]
    return 0.05 * mr["blade_mass"] * mr["omega"] ** 2 * mr["radius"] / 2


def test_identical_blades_pass_only_multiples_of_the_blade_count_into_the_hub(identical):
    res = identical
    assert res.revs == 1 and res.orders[-1] == 50 and res.thrust > 2e4
    others = [k for k in range(1, 51) if k % 4]
    for c in COMPONENTS:
        name = f"main_rotor.hub.{c}"
        worst = max(res.harmonic(name, k) for k in others)
        assert worst <= FILTER * res.thrust, (name, worst / res.thrust)
        print(f"{name}: 4/rev {res.harmonic(name, 4):.3g}, largest other {worst / res.thrust:.2e} of the thrust")
    assert res.harmonic("main_rotor.hub.force_x", 4) > 1e-5 * res.thrust  # the 4/rev is there (2.1 N at 10 m/s)
    # in the rotating frame, blade 1 carries every harmonic
    assert min(res.harmonic("blade1.root.force_z", k) for k in (1, 2, 3)) > 1e-5 * res.thrust


def test_a_blade_5_percent_heavier_brings_its_centrifugal_force_as_a_1_per_rev(identical, heavier):
    """Blade 1 5 % heavier: on the clamped airframe (ground-run) the hub carries the extra
    mass's centrifugal force ``0.05 m Ω² r_cg`` (6.98 kN) as a 1/rev in-plane force; in free
    flight the airframe gives way and the soft in-plane rotor partly centres itself: less, and
    elliptic (pitch and roll inertias differ; measured 0.67 and 0.36 of it along x and y with the
    airframe light in roll, the whole aircraft's inertia less the rotors'). The identical rotor
    has none."""
    clamped = rotor_loads(variant("ground-run", 1.05))
    for c in "xy":
        assert clamped.harmonic(f"main_rotor.hub.force_{c}", 1) == pytest.approx(imbalance(), rel=5e-3)
    inplane = [heavier.harmonic(f"main_rotor.hub.force_{c}", 1) for c in "xy"]
    assert all(0.25 * imbalance() < f < imbalance() for f in inplane), (inplane, imbalance())
    assert inplane[0] != pytest.approx(inplane[1], rel=0.1)  # elliptic
    assert identical.harmonic("main_rotor.hub.force_x", 1) <= FILTER * identical.thrust
    print(f"1/rev hub force with blade 1 5 % heavier: clamped x {clamped.harmonic('main_rotor.hub.force_x', 1):.0f}, "
          f"y {clamped.harmonic('main_rotor.hub.force_y', 1):.0f} N; free flight x {inplane[0]:.0f} N, "
          f"y {inplane[1]:.0f} N ({inplane[0] / heavier.thrust:.3f}, {inplane[1] / heavier.thrust:.3f} of the "
          f"thrust; 0.05 m Ω² r_cg = {imbalance():.0f} N), "
          f"moments x {heavier.harmonic('main_rotor.hub.moment_x', 1):.0f}, "
          f"y {heavier.harmonic('main_rotor.hub.moment_y', 1):.0f} N m")


def test_with_the_tail_rotor_its_vibration_reaches_the_main_hub_only_through_the_airframe():
    """forward-flight as it is: the two-bladed tail rotor (5.25 times faster) shakes the
    airframe at its 2/rev (10.5/rev of the main rotor) and 4/rev (21/rev); the main rotor's
    hub loads carry that and its combinations with 4/rev, nothing else."""
    res = rotor_loads("forward-flight")
    tail = ({10.5 + 4 * k for k in range(-3, 4)} | {21.0 + 4 * k for k in range(-5, 4)}
            | {42.0 + 4 * k for k in range(-10, 2)})
    for c in COMPONENTS:
        name = f"main_rotor.hub.{c}"
        other = max(res.harmonic(name, o) for o in res.orders
                    if o > 0 and o % 4 and not any(abs(o - t) < 1e-9 for t in tail))
        assert other <= FILTER * res.thrust, (name, other / res.thrust)
    assert res.harmonic("main_rotor.hub.force_y", 10.5) > 1e-5 * res.thrust


# -- hover: hub loads against the trim's thrust and power -----------------------------------------

@pytest.fixture(scope="module")
def hover():
    """The hover trim at 200 steps per revolution (RK4's error in the period means, O(h⁴),
    is 1.1e-9 of the torque at 100) over its whole period, with the outputs and poses."""
    sc = scenes.get("hover")
    system, stepper = evaluators(sc)
    res = trim("hover", system=system, stepper=stepper, steps_per_rev=200)
    per = res.period
    n = per.full_revs * res.steps_per_rev
    traj = system.run(res.x0, 0.0, per.revolution / res.steps_per_rev, n, every=1, p=res.params)
    y = system.history("outputs", traj, res.params)[1:]
    return res, system, traj, {k: y[:, i] for i, k in enumerate(system.info.output_names)}


def rotor_mass(info) -> float:
    return sum(b["mass"] for b in info.bodies if b["name"] == "main_hub" or b["name"].startswith("blade"))


def test_hover_mean_hub_force_along_the_shaft_is_the_thrust_less_the_rotors_weight(hover):
    res, system, traj, y = hover
    d = aircraft.load().data
    shaft = shaft_frame(d["main_rotor"]["shaft_tilt"])[:, 2]  # up the shaft, body axes
    hub = np.column_stack([y[f"main_rotor.hub.force_{c}"] for c in "xyz"]) @ shaft
    i = system.info.body_names.index("fuselage")
    gravity = np.array([system.poses(x, t, res.params)[1][i].T @ system.info.gravity for x, t in
                        zip(traj.x[1:], traj.t[1:])]) @ shaft * rotor_mass(system.info)
    assert hub.mean() == pytest.approx(res.thrust + gravity.mean(), rel=1e-9)
    assert -gravity.mean() / res.thrust == pytest.approx(0.0735, abs=5e-4)  # the weight: 7 % of the thrust


def test_hover_mean_shaft_torque_times_omega_is_the_main_rotor_power(hover):
    """The drive's torque balances the aerodynamic torque and the weight's moment about the
    shaft (the shaft leans with the attitude: the blades' cyclic lag moves the rotor's centre
    of mass off it, 0.047 N m, 6e-6 of the torque); times Ω, the power."""
    res, system, traj, y = hover
    info, omega = system.info, system.params(res.params)[system.info.param_names.index("omega")]
    hub, g = info.body_names.index("main_hub"), np.array(info.gravity)
    weight_moment = []
    for x, t in zip(traj.x[1:], traj.t[1:]):
        pos, rot = system.poses(x, t, res.params)
        m = sum(b["mass"] * np.cross(pos[k] + rot[k] @ b["com"] - pos[hub], g) @ rot[hub][:, 2]
                for k, b in enumerate(info.bodies) if b["name"].startswith("blade"))
        weight_moment.append(m)
    shaft = y["main_rotor.shaft_torque"].mean() * omega
    assert shaft == pytest.approx(y["main_rotor.power"].mean() - omega * np.mean(weight_moment), rel=1e-9)
    assert y["main_rotor.shaft_power"].mean() == pytest.approx(shaft, rel=1e-14)
    # the torque on the airframe about the shaft is the drive's, reversed
    d = aircraft.load().data
    axis = shaft_frame(d["main_rotor"]["shaft_tilt"])[:, 2]
    on_airframe = np.column_stack([y[f"main_rotor.hub.moment_{c}"] for c in "xyz"]) @ axis
    np.testing.assert_allclose(on_airframe, -y["main_rotor.shaft_torque"], rtol=1e-10, atol=1e-10 * shaft / omega)


def test_engine_power_is_the_shaft_power_over_the_efficiency_plus_the_accessories(hover):
    _, _, _, y = hover
    engine = tomllib.loads(aircraft.packaged()["bo105"].read_text())["engine"]
    eta, accessory = engine["transmission_efficiency"]["value"], engine["accessory_power"]["value"]
    assert engine["transmission_efficiency"]["source"] == "EST" and engine["accessory_power"]["source"] == "EST"
    expected = (y["main_rotor.shaft_power"] + y["tail_rotor.shaft_power"]) / eta + accessory
    np.testing.assert_allclose(y["engine.power"], expected, rtol=1e-13)
    assert 3e5 < y["engine.power"].mean() < 5e5


# -- the command -------------------------------------------------------------------------------------

def test_heli_loads_reports_tables_and_writes_its_files(tmp_path, capsys):
    assert main(["loads", "hover", "--quiet", "--json", "--out", str(tmp_path)]) == 0
    captured = capsys.readouterr()
    res = json.loads(captured.out)  # stdout is the one JSON object; the tables go to stderr
    assert "main-rotor hub loads on the airframe" in captured.err and "blade 1 root loads" in captured.err
    rows = {r["output"]: r for r in res["hub"]["main_rotor"]}
    assert set(rows) == {f"main_rotor.hub.{c}" for c in COMPONENTS}
    assert rows["main_rotor.hub.force_z"]["mean"] < -1.9e4  # the rotor lifts the airframe (z down)
    assert {r["output"] for r in res["power"]} >= {"engine.power", "main_rotor.shaft_power"}
    names = sorted(p.split("/")[-1] for p in res["files"])
    assert names == ["harmonics_hover_0ms.csv", "hub_harmonics_main_rotor_hover_0ms.png",
                     "hub_harmonics_tail_rotor_hover_0ms.png", "loads_hover_0ms.csv"]
    table = np.loadtxt(tmp_path / "harmonics_hover_0ms.csv", delimiter=",", skiprows=1)
    assert table.shape[0] == 201 and table[4, 0] == 1.0  # orders in quarter revolutions (4-rev period)


def test_heli_loads_sweep_writes_the_vibratory_chart(tmp_path, capsys):
    assert main(["loads", "forward-flight", "--sweep", "20:40:2", "--quiet", "--json", "--out", str(tmp_path)]) == 0
    res = json.loads(capsys.readouterr().out.strip().splitlines()[-1])
    assert [r["speed"] for r in res["rows"]] == [20.0, 40.0] and all(r["status"] == "ok" for r in res["rows"])
    assert all(r["main_rotor.hub.force_z.4/rev"] > 0 and r["engine.power"] > 2e5 for r in res["rows"])
    assert sorted(p.split("/")[-1] for p in res["files"]) == ["vibratory_hub_loads_forward-flight.csv",
                                                               "vibratory_hub_loads_forward-flight.png"]


@pytest.mark.parametrize("argv, message", [
    (["loads", "--speed", "10", "--sweep", "0:10:2"], "give --speed or --sweep, not both"),
    (["loads", "--sweep", "0:10"], "expected LO:HI:N"),
    (["loads", "structural"], "scene 'structural' has no periodic solution for its loads"),
    (["loads", "ground-resonance"], "scene 'ground-resonance' declares no rotor loads outputs"),
])
def test_heli_loads_refuses_bad_input_in_one_line(argv, message, capsys):
    try:
        status = main(argv)
    except SystemExit as exc:  # refused while the command line is parsed
        status = exc.code
    assert status == 2
    err = capsys.readouterr().err
    assert message in err and "Traceback" not in err and len(err.strip().splitlines()) == 1


def _refuse_nan(constant):
    raise AssertionError(f"{constant} in the JSON output (not JSON)")


def test_heli_loads_of_the_modal_rotor_without_a_tail_rotor_is_strict_json(tmp_path, capsys):
    """The modal elastic rotor's loads: a hub with no other rotor has no fractional orders, shown
    as a dash and given as null (it was NaN, which is no JSON); the hub's thrust carries the
    rotor's own 4/rev and nothing at other harmonics (identical blades); the modal blade's
    moments along the span are reported."""
    assert main(["loads", "elastic-rotor-modal", "--quiet", "--json", "--out", str(tmp_path)]) == 0
    captured = capsys.readouterr()
    res = json.loads(captured.out, parse_constant=_refuse_nan)
    rows = {r["output"]: r for r in res["hub"]["main_rotor"]}
    fz = rows["main_rotor.hub.force_z"]
    assert fz["fractional_order"] is None and fz["fractional"] == 0.0
    assert fz["mean"] < -1.5e4 and fz["other"] < 1e-8 * abs(fz["mean"])
    assert "nan" not in captured.err
    # the modal blade's moments along the span: at its root and the 8-segment blade's seven joint radii, the
    # mean flap bending moment falling outwards over the inner stations (the blade droops less
    # than its thrust bends it up)
    span = res["span"]
    assert [r["station"] for r in span] == ["blade1.root"] + [f"blade1.station{j}" for j in range(2, 9)]
    assert all(a["radius"] < b["radius"] for a, b in zip(span, span[1:]))
    assert span[0]["flap_mean"] > span[1]["flap_mean"] > span[2]["flap_mean"] > span[3]["flap_mean"] > 0
    assert "blade 1 along the span" in captured.err


def test_the_loads_benchmarks_model_without_its_loads_outputs_evaluates():
    """'heli bench loads' stopped at KeyError 'main_rotor.shaft_torque': its model without the loads
    outputs kept engine.torque, which reads them. Every output that reads a loads output is one."""
    from mbs import scenes
    from mbs.backends import build
    from mbs.loads.bench import LOADS

    bare = scenes.get("forward-flight").model()
    removed = [n for n in bare.outputs if LOADS.search(n)]
    for name in removed:
        del bare.outputs[name]
    assert {"engine.power", "engine.torque", "main_rotor.shaft_torque"} <= set(removed)
    system = build(bare, "vm")
    assert np.all(np.isfinite(system.outputs(system.x0(), 0.0, system.params())))
