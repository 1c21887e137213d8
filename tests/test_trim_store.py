"""Stored trims: keyed by aircraft file, scene and speed; read back by ``heli simulate``, which
starts an aircraft that flies from its periodic trim (trimmed and stored on first use).

The "new aircraft" here is a copy of the Bo105's file outside the package (the template's
values, under a name of its own would be compiled afresh): it has no stored trims beside it,
so its model starts from the closed-form estimate, as a new aircraft's does.
"""
from __future__ import annotations

import json
import shutil

import numpy as np
import pytest

from mbs import _rotation as rot
from mbs import aircraft, cli, scenes
from mbs.results import read_results
from mbs.trims import store
from mbs.trims.entry import scene_identity


@pytest.fixture
def home(tmp_path, monkeypatch):
    """An empty user data folder (the default trim file's) and working folder."""
    monkeypatch.setenv("XDG_DATA_HOME", str(tmp_path / "share"))
    monkeypatch.chdir(tmp_path)
    return tmp_path


def run(argv, capsys) -> tuple[int, str, str]:
    code = cli.main(argv)
    out = capsys.readouterr()
    return code, out.out, out.err


def roll_deg(folder) -> np.ndarray:
    c, _ = read_results(folder)
    q = np.c_[c["fuselage.qw"], c["fuselage.qx"], c["fuselage.qy"], c["fuselage.qz"]]
    return np.degrees([rot.quat_to_euler(x)[0] for x in q])


def test_a_new_aircraft_flies_from_its_periodic_trim_trimmed_on_first_use(home, capsys):
    craft = shutil.copy(aircraft.packaged()["bo105"], home / "bo105.toml")
    argv = ["simulate", "forward-flight", "--aircraft", str(craft), "--revs", "5", "--quiet"]
    code, _, err = run([*argv, "--out", "first"], capsys)
    assert code == 0, err
    assert "no stored periodic trim of forward-flight at 10 m/s of the MBB Bo105 (bo105.toml); trimming it now" in err
    assert f"stored in {store.default_file()}" in err
    start = json.loads((home / "first" / "run.json").read_text())["initial_state"]
    assert start["from"] == "periodic trim" and start["computed_now"] and start["check_residual"] < 1e-8
    assert start["file"] == str(store.default_file()) and len(start["state"]) == 35  # 16 positions, 15 velocities, 4 inflows
    roll = roll_deg(home / "first")
    assert np.abs(roll - start["roll_deg"]).max() < 0.5  # measured 6e-6 deg; from the estimate -2.9 to +6.1 deg
    code, _, err = run([*argv, "--out", "again"], capsys)  # read back: no second trim
    assert code == 0 and "starting from the periodic trim of forward-flight at 10 m/s" in err and "trimming" not in err
    again = json.loads((home / "again" / "run.json").read_text())["initial_state"]
    assert not again["computed_now"] and again["key"] == start["key"] and again["state"] == start["state"]


def test_the_scenes_own_start_is_said_to_be_untrimmed(home, capsys):
    craft = shutil.copy(aircraft.packaged()["bo105"], home / "bo105.toml")
    code, _, err = run(["simulate", "forward-flight", "--aircraft", str(craft), "--revs", "5", "--start", "scene",
                        "--quiet", "--out", "est"], capsys)
    assert code == 0 and "starts from the closed-form trim estimate, not a trim" in err
    start = json.loads((home / "est" / "run.json").read_text())["initial_state"]
    assert start["from"] == "scene" and "closed-form trim estimate" in start["what"]
    assert np.ptp(roll_deg(home / "est")) > 5.0  # the issue's -2.9 to +6.1 deg: why a trim is the default


def test_trims_of_two_aircraft_are_kept_apart_and_read_back(home, capsys):
    for craft in ("bo105", "lynx"):
        code, out, err = run(["trim", "hover", "--aircraft", craft, "--write", "--quiet", "--json"], capsys)
        assert code == 0, err
        assert json.loads(out)["written"] == str(store.default_file())
    tables = {k: v for k, v in store.read(store.default_file()).items()}
    assert sorted(v["aircraft"] for v in tables.values()) == ["MBB Bo105", "Westland Lynx"]  # the Lynx's replaced nothing
    for craft in ("bo105", "lynx"):
        code, _, err = run(["simulate", "hover", "--aircraft", craft, "--revs", "0.5", "--quiet", "--out", craft],
                           capsys)
        assert code == 0 and "starting from the periodic trim of hover at 0 m/s" in err and "trimming" not in err
        start = json.loads((home / craft / "run.json").read_text())["initial_state"]
        assert tables[start["key"]]["aircraft_sha256"] == aircraft.load(craft).digest
        assert start["controls"] == tables[start["key"]]["controls"]


def test_a_changed_aircraft_file_is_not_given_its_earlier_trim(home, capsys):
    craft = home / "bo105.toml"
    shutil.copy(aircraft.packaged()["bo105"], craft)
    assert run(["trim", "hover", "--aircraft", str(craft), "--write", "--quiet"], capsys)[0] == 0
    craft.write_text(craft.read_text().replace("[aircraft]", "[aircraft]\n# a comment changes the file's digest", 1))
    scene = scenes.get("hover", aircraft.load(craft))
    ident = scene_identity(scene, {}, 0.0, 0.0, "rk4", 100)
    assert store.find([store.default_file()], ident) is None
    assert store.earlier_versions([store.default_file()], ident, str(craft.resolve())) == [store.default_file()]


def test_an_entry_of_the_same_identity_is_replaced_and_other_tables_kept(tmp_path):
    path = tmp_path / "trims.toml"
    path.write_text('["hover"]\n"speed" = 0.0\n"collective" = 0.25\n')  # the earlier format: kept, never matched
    scene = scenes.get("hover")
    ident = scene_identity(scene, {}, 0.0, 0.0, "rk4", 100)
    entry = {"scene": "hover", "aircraft": "MBB Bo105", **ident, "controls": {"collective": 0.1}, "state": {}}
    first = store.write(path, entry)
    second = store.write(path, {**entry, "controls": {"collective": 0.2}})
    other = store.write(path, {**entry, **scene_identity(scene, {}, 5.0, 0.0, "rk4", 100)})
    tables = store.read(path)
    assert first == second != other and sorted(tables) == sorted(["hover", first, other])
    assert tables[first]["controls"] == {"collective": 0.2} and tables["hover"]["collective"] == 0.25
    assert store.find([path], ident)[1] == first
    assert store.find([path], scene_identity(scene, {"omega": 40.0}, 0.0, 0.0, "rk4", 100)) is None


def test_start_trim_is_refused_where_there_is_no_trim(home, capsys):
    code, _, err = run(["simulate", "structural", "--start", "trim"], capsys)
    assert code == 2 and "--start trim: scene 'structural' has no periodic trim" in err


def test_runs_that_start_from_the_estimate_say_so(home):
    from mbs.trims.start import estimate_warning

    craft = aircraft.load(shutil.copy(aircraft.packaged()["bo105"], home / "bo105.toml"))
    text = estimate_warning(scenes.get("forward-flight", craft), "every point of the sweep")
    assert text.startswith("every point of the sweep starts scene 'forward-flight' of the MBB Bo105 from its own "
                           "initial state, the closed-form trim estimate")
    assert estimate_warning(scenes.get("forward-flight"), "x") is None  # the Bo105's stored trim: its controls
    assert estimate_warning(scenes.get("ground-run", craft), "x") is None  # clamped: no flight to trim


def test_heli_scenes_says_where_the_flying_scenes_start(capsys):
    assert cli.main(["scenes"]) == 0
    out = capsys.readouterr().out
    assert "heli simulate starts it from its periodic trim (stored per aircraft file, or trimmed and stored on first " \
           "use)" in out and "trimmed controls and attitude" not in out
    assert "hover controls (a stored hover trim's, else the closed-form estimate's)" in out
