"""The viewer's scene as a user sees it: distinct colours for every blade, a camera outside the
model, the run's aircraft file found where it moved (``heli view --aircraft``), the aircraft of
a live run (``heli view --simulate SCENE --aircraft``), and a unit for every column of every
scene's results."""
from __future__ import annotations

import shutil

import numpy as np
import pytest

from mbs import aircraft, cli, scenes
from mbs.dynamics import Layout
from mbs.results import column_units
from mbs.simulate import simulate, write
from aircraft_files import edited
from viewer.motion import motion
from viewer.scene import build_scene, posed_extent


def run(argv, capsys) -> tuple[int, str]:
    try:
        code = cli.main(argv)
    except SystemExit as exc:  # a mistake found while parsing
        code = exc.code
    return code, capsys.readouterr().err


def test_six_blades_have_six_colours(tmp_path):
    craft = aircraft.load(edited(tmp_path / "six.toml", **{"main_rotor.n_blades": 6}))
    info = scenes.get("hover", craft).system("vm").info
    scene = build_scene(info)
    blades = [scene.colors[f"blade{k}"] for k in range(1, 7)]
    assert len(set(blades)) == 6  # the model's four colours repeated blade 1's for blade 5
    four = build_scene(scenes.get("hover").system("vm").info)
    assert [four.colors[f"blade{k}"] for k in range(1, 5)] == blades[:4]  # a four-bladed rotor unchanged


def test_the_modal_scenes_camera_starts_outside_the_rotor(tmp_path):
    """The flexible blades' sections sit along the span through their joints, not their
    offsets: the camera's distance follows the posed model (the rotor radius, 4.9 m), not the
    hub (0.6 m)."""
    sim = simulate("elastic-rotor-modal", 0.05)
    write(sim, tmp_path)
    mo = motion(tmp_path, None, None, 1)
    scene = build_scene(mo.recording.system.info)
    radius = aircraft.load().data["main_rotor"]["radius"]
    assert scene.extent < 1.0 and posed_extent(scene, mo.local[0]) == pytest.approx(radius, rel=0.02)


@pytest.mark.parametrize("name", list(scenes.all_scenes()))
def test_every_state_of_every_scene_has_a_unit(name):
    model = scenes.get(name).model()
    lay, units = Layout.of(model), column_units(model)
    assert [n for n in [*lay.q_names, *lay.v_names, *lay.z_names] if not units.get(n)] == []


def test_view_finds_a_moved_aircraft_file_with_aircraft(tmp_path, capsys):
    first = tmp_path / "here" / "bo105.toml"
    first.parent.mkdir()
    shutil.copy(aircraft.packaged()["bo105"], first)
    out = tmp_path / "run"
    assert run(["simulate", "hover", "--aircraft", str(first), "--revs", "0.1", "--start", "scene", "--quiet",
                "--out", str(out)], capsys)[0] == 0
    moved = tmp_path / "there" / "bo105.toml"
    moved.parent.mkdir()
    shutil.move(first, moved)
    code, err = run(["view", str(out)], capsys)
    assert code == 2 and "cannot be loaded" in err and "give its new place with --aircraft FILE" in err
    code, err = run(["view", str(out), "--aircraft", "lynx"], capsys)
    assert code == 2 and "--aircraft" in err and "is not the aircraft file the run was made with" in err
    code, err = run(["view", str(out), "--aircraft", str(moved), "--html", str(tmp_path / "v.html")], capsys)
    assert code == 0, err
    assert (tmp_path / "v.html").stat().st_size > 10_000


def test_view_simulate_takes_the_aircraft(monkeypatch, capsys):
    from viewer import commands

    seen = {}
    monkeypatch.setattr(commands, "_live_simulation", lambda args: seen.setdefault("args", args) and 0)
    assert cli.main(["view", "--simulate", "hover", "--aircraft", "lynx"]) == 0
    assert seen["args"].aircraft.name == "Westland Lynx"
    code, err = run(["view", "--simulate", "hover", "--aircraft", "nosuch.toml"], capsys)
    assert code == 2 and "--aircraft" in err and "no such file" in err


def test_run_json_gives_modal_coordinates_their_unit():
    units = column_units(scenes.get("elastic-rotor-modal").model())
    assert units["blade1.flap2"] == "rad" and units["blade1.torsion_rate"] == "rad/s"
    swash = column_units(scenes.get("forward-flight-swashplate").model())
    assert swash["blade1.flap"] == "rad" and swash["blade1.lag_rate"] == "rad/s"  # they had none either


def test_swashplate_scenes_plot_blade_pitch_and_actuators():
    from viewer.motion import from_simulation
    from viewer.series import panels

    sim = simulate("forward-flight-actuators", 0.1)
    rec = from_simulation(sim)
    shown = {p.title: p for p in panels(rec, np.arange(len(rec.t)))}
    pitch = shown["blade pitch set by the pitch links (deg)"]
    actuators = shown["swashplate actuator displacements, up (mm)"]
    assert pitch.names == [f"blade{k}.pitch" for k in range(1, 5)] and actuators.names == [
        f"actuator{k}.displacement" for k in range(1, 4)]
    i = sim.system.info.output_names.index("actuator2.displacement")
    assert actuators.values[0, 1] == pytest.approx(1e3 * sim.outputs[0, i], rel=1e-12)
    j = sim.system.info.output_names.index("blade3.pitch")
    assert pitch.values[-1, 2] == pytest.approx(np.degrees(sim.outputs[-1, j]), rel=1e-12)


@pytest.mark.parametrize("horn", ["housing", "blade"])
def test_the_swashplate_and_pitch_links_are_drawn_where_the_model_has_them(tmp_path, horn):
    """Each link's rod joins its balls, exactly the link's length apart (rigid links) at every key;
    with the horn on the blade its upper ball is the blade's own point ``ball`` carried by the
    blade's pose (flap, lag and pitch), through the viewer's transforms; the plate passes through
    the lower balls; the page holds a node for each link and the plate."""
    from test_swashplate import blade_horn

    from viewer import export_html
    from viewer.export import data_in
    from viewer.motion import from_simulation
    from viewer.swashplate import mechanism

    craft = aircraft.load() if horn == "housing" else blade_horn(tmp_path, 15.0, 3.0)
    scene = scenes.get("forward-flight-swashplate", craft)
    sim = simulate(scene, 0.3)
    rec = from_simulation(sim)
    mo = motion(rec, None)
    mech = mechanism(rec, mo.t)
    sp = craft.data["swashplate"]
    for blade in mech.lower:
        assert np.abs(np.linalg.norm(mech.upper[blade] - mech.lower[blade], axis=1) - sp["link_length"]).max() < 1e-12
    if horn == "blade":
        from mbs.models.helicopter.swashplate import Swashplate

        ball = np.r_[Swashplate.of(craft.data).ball(1), 1.0]
        i = rec.info.body_names.index("blade2")
        carried = np.array([(local[i] @ ball)[:3] for local in mo.local])
        np.testing.assert_allclose(mech.upper["blade2"], carried, atol=1e-12)
    balls = np.stack(list(mech.lower.values()), axis=1)
    assert np.abs(np.einsum("kbi,ki->kb", balls - mech.centre[:, None], mech.normal)).max() < 1e-12
    page = export_html(sim, tmp_path / "v.html", revs=None)
    paths = [n["path"] for n in data_in(page.path)["arrows"]]
    assert sum("/swashplate/blade" in p for p in paths) == 4 and any(p.endswith("/swashplate/plate") for p in paths)
    assert mechanism(from_simulation(simulate("forward-flight", 0.05)), mo.t[:1]) is None
