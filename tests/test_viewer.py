"""Viewer without a browser: scene from the model, keyframes, exported HTML, CLI, live server."""
from __future__ import annotations

import json
import os
import re
import subprocess
import sys
import time

import numpy as np
import pytest

from mbs import atomic, scenes
from mbs.simulate import simulate, write
from viewer import animation as anim
from viewer import build_scene, export_html, from_results, motion, pack
from viewer import kinematics as kin
from viewer.export import commands_in, data_in
from viewer.scene import WORLD


@pytest.fixture(scope="module")
def flight():
    """One main-rotor revolution of the Bo105 in forward flight (VM), every step recorded."""
    return simulate("forward-flight", 1.0, backend="vm")


@pytest.fixture(scope="module")
def flight_page(flight, tmp_path_factory):
    return export_html(flight, tmp_path_factory.mktemp("view") / "viewer.html")


def test_scene_has_one_node_per_body_nested_as_the_tree(flight):
    scene = build_scene(flight.system.info)
    assert scene.paths["fuselage"] == WORLD + "/fuselage"
    assert scene.paths["blade3"] == WORLD + "/fuselage/main_hub/blade3"
    assert scene.paths["tail_blade2"] == WORLD + "/fuselage/tail_hub/seesaw/tail_blade2"
    assert len(scene.paths) == len(flight.system.info.bodies) == 10
    driven = build_scene(scenes.get("demo-driven").system("vm").info)
    assert sorted(driven.paths) == ["blade1", "blade2", "blade3", "fuselage", "hub"]


def test_geometry_is_sized_from_the_model(flight):
    from mbs.aircraft import load as load_aircraft

    mr = load_aircraft().data["main_rotor"]
    scene = build_scene(flight.system.info)
    (blade,) = scene.parts["blade1"]
    assert blade.kind == "box"
    np.testing.assert_allclose(blade.dims, [mr["radius"] - mr["flap_hinge_offset"], mr["chord"], mr["blade_thickness"]])
    # the tip (traced) lies at the rotor radius from the shaft axis
    np.testing.assert_allclose(scene.tip_point("blade1")[0] + mr["flap_hinge_offset"], mr["radius"])
    (hub,) = scene.parts["main_hub"]
    assert hub.kind == "cylinder" and hub.dims[0] == mr["hub_radius"]
    np.testing.assert_allclose(hub.transform[:3, :3] @ [0, 1, 0], [0, 0, 1], atol=1e-15)  # three.js y -> shaft
    fuselage = scene.parts["fuselage"]
    boom = [p for p in fuselage if p.kind == "cylinder"]
    assert len(fuselage) == 4 and len(boom) == 1
    np.testing.assert_allclose(boom[0].transform[:3, :3] @ [0, 1, 0], [1, 0, 0], atol=1e-15)  # boom along x


def test_viewer_transforms_equal_core_body_poses(flight):
    mo = motion(flight)
    composed = kin.compose(mo.local, mo.parents)
    for k in range(0, len(mo.t), 7):
        x = mo.recording.state_at(mo.t[k])
        origins, rotations = flight.system.poses(x, mo.t[k], flight.params)
        np.testing.assert_allclose(composed[k], kin.homogeneous(origins, rotations), atol=1e-12)


@pytest.mark.parametrize("name", sorted(scenes.all_scenes()))
def test_every_scene_can_be_shown(name, tmp_path):
    """Each scene's own bodies only; node transforms reproduce the core's poses; keys < 60 deg."""
    sim = simulate(name, 0.25, backend="vm")
    exp = export_html(sim, tmp_path / "v.html", revs=None)
    assert list(exp.scene.paths) == sim.system.info.body_names
    assert exp.max_key_angle_deg < 60
    composed = kin.compose(exp.motion.local, exp.motion.parents)
    x, t = sim.traj.x[-1], sim.traj.t[-1]
    np.testing.assert_allclose(composed[-1], kin.homogeneous(*sim.system.poses(x, t, sim.params)), atol=1e-12)
    shapes = [c["path"] for c in commands_in(exp.path) if c["type"] == "set_object" and "/shape/" in c["path"]]
    assert len(shapes) == sum(len(p) for p in exp.scene.parts.values()) > 0


def _page_local(page_path, scene):
    """Key times (k,) s, node transforms (k, nb, 4, 4) stored in the page (float32) and the
    followed origin (k, 3) m."""
    kf = pack.keyframes_of(data_in(page_path))
    tracks = [[np.broadcast_to(a, (len(kf.t), a.shape[1])) for a in kf.nodes[scene.paths[b]]] for b in scene.body_names]
    return kf, np.stack([kin.homogeneous(pos, kin.rotations_xyzw(q)) for pos, q in tracks], axis=1)


def test_page_keys_reproduce_core_poses(flight, flight_page):
    """Keys decoded from the HTML (float32), composed down the tree, give the core's poses."""
    mo, scene = flight_page.motion, flight_page.scene
    kf, local = _page_local(flight_page.path, scene)
    np.testing.assert_array_equal(kf.t, mo.t)
    world = kin.compose(local, mo.parents)
    for k in range(len(mo.t)):
        origins, rotations = flight.system.poses(mo.recording.state_at(mo.t[k]), mo.t[k], flight.params)
        np.testing.assert_allclose(world[k, :, :3, :3], rotations, atol=2e-6)
        np.testing.assert_allclose(world[k, :, :3, 3], origins, atol=1e-5 * max(1.0, np.abs(origins).max()))
        np.testing.assert_allclose(kf.follow[k], origins[0], atol=1e-12)  # float64: the camera follows the fuselage


def test_between_keys_the_page_departs_from_the_core_by_the_interpolation_error(flight, flight_page):
    """The player's mapping (animation.local_at / world_at: linear positions, slerp) at
    midpoints between keys departs from the core's poses of the state at that time by no more
    than the interpolation error of a smooth path, h^2 |R''| / 8, estimated from the keys'
    second differences (measured 0.94 of it: the cyclic pitch, a function of azimuth, curves
    between keys; 1.6e-5 at 100 keys per revolution). Nearest-key or first-order schemes fail."""
    mo, scene = flight_page.motion, flight_page.scene
    kf = pack.keyframes_of(data_in(flight_page.path))
    R = mo.local[:, :, :3, :3]
    curve = np.abs(R[:-2] - 2 * R[1:-1] + R[2:]).max(axis=(-1, -2)) / 8  # (k - 2, nb)
    curve = np.maximum(np.vstack([curve[:1], curve]), np.vstack([curve, curve[-1:]]))  # per interval
    rec = mo.recording
    for j, t in enumerate(0.5 * (mo.t[:-1] + mo.t[1:])):
        origins, rotations = flight.system.poses(rec.state_at(t), t, flight.params)
        core = kin.relative(kin.homogeneous(origins, rotations), mo.parents)
        got = anim.local_at(kf, t)
        err = np.array([np.abs(got[scene.paths[b]] - core[i]).max() for i, b in enumerate(scene.body_names)])
        assert np.all(err <= 1.5 * curve[j] + 2e-6), (t, err, curve[j])
        np.testing.assert_allclose(anim.world_at(kf, t)[:3, 3], -origins[0], atol=1e-12)
        np.testing.assert_allclose(anim.world_at(kf, t, follow=False)[:3, 3], -mo.origins[0, 0], atol=1e-12)


def test_keys_stay_under_90_degrees_even_from_coarse_rows(flight, tmp_path):
    """Rows 20 steps apart turn the tail rotor by ~1.05 revolutions: keys are added back, so
    slerp's short way between keys is the true way."""
    exp = export_html(flight, tmp_path / "coarse.html", every=20)
    mo, scene = exp.motion, exp.scene
    kf = pack.keyframes_of(data_in(exp.path))
    for path, (_, q) in kf.nodes.items():
        if len(q) == 1:
            continue  # a node that never turns
        angle = np.degrees(2 * np.arccos(np.clip(np.abs(np.sum(q[1:] * q[:-1], axis=1)), 0, 1)))
        assert angle.max() < 60.5, path
    # the short way between keys is the true way: the tail hub turns by the driven azimuth
    names = flight.system.info.output_names
    tail = np.array([flight.system.outputs(mo.recording.state_at(t), t, flight.params)[names.index("tail_rotor.azimuth")]
                     for t in mo.t])
    turned = kin.key_angles(mo.local)[:, scene.body_names.index("tail_hub")]
    np.testing.assert_allclose(turned, np.diff(tail), atol=1e-9)
    assert np.diff(tail).sum() > 5 * 2 * np.pi  # ~5.2 tail revolutions in one main-rotor revolution
    assert len(mo.t) > 5 * 101 / 20


def test_exported_page_is_one_offline_file(flight_page):
    text = flight_page.path.read_text()
    assert "<script src" not in text.lower() and "<link" not in text.lower()
    urls = set(re.findall(r"(?:https?|wss?|ftp)://[^\s\"'<>)]*", text))
    # namespace names (never fetched) and the template of viewer.connect(), never called here
    assert urls <= {"http://www.w3.org/1999/xhtml", "http://www.w3.org/2000/svg", "ws://${location.host}`"}, urls
    assert "viewer.connect(" not in text and "fetch(" not in text.split("var viewer = new MeshCat.Viewer", 1)[1]
    assert "window.__viewerReady = true" in text
    assert flight_page.size < 1.3e6


def test_results_folder_gives_the_same_keys_as_the_simulation(flight, tmp_path):
    write(flight, tmp_path)
    a, b = motion(flight), motion(from_results(tmp_path))
    np.testing.assert_array_equal(a.t, b.t)
    np.testing.assert_allclose(a.local, b.local, atol=1e-12)


def test_inputs_recorded_per_row_drive_the_pitch(tmp_path):
    """A collective column in results.csv (e.g. an FMU input schedule) is used row by row."""
    sim, _ = _with_collective_step(tmp_path)
    rec = from_results(tmp_path)
    i = rec.info.param_names.index("collective")
    assert rec.params_at(rec.t[10])[i] == 0.1 and rec.params_at(rec.t[80])[i] == 0.3
    mo = motion(rec, revs=None)
    b = rec.info.body_names.index("blade1")
    for k, pitch in ((10, 0.1), (80, 0.3)):
        p = sim.system.params(collective=pitch)
        _, rotations = sim.system.poses(rec.x[k], rec.t[k], p)
        np.testing.assert_allclose(mo.rotations[k, b], rotations[b], atol=1e-12)


def _with_collective_step(tmp_path, revs: float = 1.0):
    """A demo-driven results folder with a per-row collective column stepping 0.1 -> 0.3 rad
    at row 50 (as an FMU input schedule records it)."""
    sim = simulate("demo-driven", revs, backend="vm")
    write(sim, tmp_path)
    csv = tmp_path / "results.csv"
    lines = csv.read_text().splitlines()
    step = [0.1 if i < 50 else 0.3 for i in range(len(lines) - 1)]
    csv.write_text("\n".join([lines[0] + ",collective"] + [f"{l},{c}" for l, c in zip(lines[1:], step)]) + "\n")
    run = json.loads((tmp_path / "run.json").read_text())  # the table's new digest: run.json is its record
    (tmp_path / "run.json").write_text(json.dumps({**run, "results_sha256": atomic.sha256(csv)}))
    return sim, np.array(step)


def test_plot_holds_the_runs_inputs_and_hinge_angles(tmp_path):
    """The page's plot covers the whole run: per-row collective (deg), the cyclics in their own
    panel, and every blade's flap and lag (deg) at every recorded row."""
    sim, step = _with_collective_step(tmp_path)
    exp = export_html(tmp_path, tmp_path / "v.html")
    plot = data_in(exp.path)["plot"]
    np.testing.assert_array_equal(pack.decode(plot["t"]), sim.traj.t)
    series = {p["title"]: {s["name"]: pack.decode(s["values"]) for s in p["series"]} for p in plot["panels"]}
    assert list(series) == ["collective pitch (deg)", "cyclic pitch (deg)", "flap (deg)", "lag (deg)"]
    np.testing.assert_allclose(series["collective pitch (deg)"]["collective"], np.degrees(step), rtol=1e-6)
    assert list(series["cyclic pitch (deg)"]) == ["lateral_cyclic", "longitudinal_cyclic"]
    names = sim.system.info.state_names
    for b in range(1, 4):
        for hinge in ("flap", "lag"):
            got = series[f"{hinge} (deg)"][f"blade{b}.{hinge}"]
            np.testing.assert_allclose(got, np.degrees(sim.traj.x[:, names.index(f"blade{b}.{hinge}")]), atol=1e-5)
    assert exp.plot_rows == len(sim.traj.t) and exp.sim_time == (sim.traj.t[0], sim.traj.t[-1])


def test_azimuth_of_the_readout_is_the_main_rotors(flight, flight_page):
    """Keyed main-rotor azimuth (unwrapped, rad) equals the model's output omega t."""
    doc = data_in(flight_page.path)
    omega = flight.params[flight.system.info.param_names.index("omega")]
    np.testing.assert_allclose(pack.decode(doc["azimuth"]), omega * flight_page.motion.t, atol=1e-12)
    assert doc["revolution"] == pytest.approx(2 * np.pi / omega, rel=1e-12)


def test_long_runs_are_thinned_to_the_size_limit(tmp_path):
    """The whole run is shown; under a tighter limit every n-th row is kept (and the page fits)."""
    sim = simulate("demo-driven", 4.0, backend="vm")
    full = export_html(sim, tmp_path / "full.html")
    assert full.every == 1 and full.keys == len(sim.traj.t) == 401
    limit = full.size - 60_000
    thin = export_html(sim, tmp_path / "thin.html", max_bytes=limit)
    assert thin.every >= 2 and thin.size <= limit and thin.keys < full.keys / 1.5
    assert thin.sim_time == full.sim_time == (0.0, sim.traj.t[-1])
    assert np.all(np.isin(sim.traj.t[::thin.every], thin.motion.t))
    with pytest.raises(ValueError, match="max_bytes = 500000 leaves no room"):
        export_html(sim, tmp_path / "none.html", max_bytes=5e5)


def test_last_revolutions_and_slow_motion(tmp_path):
    sim = simulate("demo-driven", 2.0, backend="vm")
    exp = export_html(sim, tmp_path / "v.html", revs=1.0, slow=4.0, trace=False)
    period = sim.scene.revolution(sim.system, sim.params)
    np.testing.assert_allclose(exp.sim_time, [period, 2 * period], rtol=1e-12)
    np.testing.assert_allclose(exp.duration, 4.0 * period, rtol=1e-12)
    assert not [c for c in commands_in(exp.path) if "tip_path" in c["path"]]


@pytest.mark.parametrize("options, message", [
    ({"slow": 0.0}, "slow"), ({"revs": -1.0}, "revs"), ({"every": 0}, "every"),
    ({"trace": ["rotor"]}, "unknown body 'rotor'"), ({"follow": "cabin"}, "unknown body 'cabin'"),
    ({"start": 99.0}, "--start 99 s is outside the run"),
])
def test_bad_options_are_named(flight, tmp_path, options, message):
    with pytest.raises(ValueError, match=re.escape(message)):
        export_html(flight, tmp_path / "v.html", **options)


def test_bad_shapes_and_missing_run_json_are_named(flight, tmp_path):
    info = flight.system.info
    bad = type(info)(**{**info.__dict__, "bodies": [{**info.bodies[0], "shape": {"kind": "sphere"}}, *info.bodies[1:]]})
    with pytest.raises(ValueError, match="body 'fuselage': unknown shape kind 'sphere'"):
        build_scene(bad)
    bad.bodies[0]["shape"] = {"kind": "box", "size": [1, 0, 1], "color": "#c8ccd2"}
    with pytest.raises(ValueError, match="box size must be positive"):
        build_scene(bad)
    write(flight, tmp_path)
    (tmp_path / "run.json").unlink()
    with pytest.raises(ValueError, match="no run.json"):
        from_results(tmp_path)


def test_cli_view_writes_html(flight, tmp_path, capsys):
    from mbs.cli import main

    write(flight, tmp_path)
    assert main(["view", str(tmp_path), "--html", str(tmp_path / "out.html"), "--json"]) == 0
    res = json.loads(capsys.readouterr().out.strip().splitlines()[-1])
    assert res["keys"] == 101 and res["max_key_angle_deg"] < 60 and (tmp_path / "out.html").stat().st_size == res["bytes"]
    assert main(["view", str(tmp_path / "missing")]) == 2


def test_cli_serve_streams_then_stops(flight, tmp_path):
    write(flight, tmp_path)
    proc = subprocess.run([sys.executable, "-m", "mbs", "view", str(tmp_path), "--serve", "--duration", "0.5",
                           "--slow", "2", "--json"], capture_output=True, text=True, timeout=60)
    assert proc.returncode == 0, proc.stderr
    res = json.loads(proc.stdout.strip().splitlines()[-1])
    assert res["url"].startswith("http://127.0.0.1:")
    assert _gone(res["pid"])


def test_live_viewer_gives_up_on_a_silent_server(flight):
    from viewer.live import LiveViewer, ServerError

    start = time.monotonic()
    with pytest.raises(ServerError, match="did not answer within 0.3 s"):
        LiveViewer(flight.system, zmq_url="tcp://127.0.0.1:9", timeout=0.3)  # nothing listens there
    assert time.monotonic() - start < 5


def _listening(port: int) -> set[str]:
    """Local addresses (hex, as in /proc/net/tcp*) listening on ``port``."""
    out = set()
    for name in ("/proc/net/tcp", "/proc/net/tcp6"):
        with open(name) as f:
            lines = f.read().splitlines()[1:]
        for line in lines:
            local, state = line.split()[1], line.split()[3]
            if state == "0A" and int(local.rsplit(":", 1)[1], 16) == port:
                out.add(local.rsplit(":", 1)[0])
    return out


def _gone(pid: int) -> bool:
    try:
        with open(f"/proc/{pid}/stat") as f:
            return f.read().split(") ", 1)[1][0] == "Z"  # exited, not yet reaped by its parent
    except FileNotFoundError:
        return True


@pytest.mark.skipif(not os.path.exists("/proc/net/tcp"), reason="needs Linux /proc")
def test_live_server_is_loopback_only_and_stops(flight):
    from viewer.live import LiveViewer

    live = LiveViewer(flight.system)
    pid, web_port = live.pid, int(live.url.split(":")[2].split("/")[0])
    zmq_port = int(live.zmq_url.rsplit(":", 1)[1])
    assert live.url.startswith("http://127.0.0.1:")
    assert _listening(web_port) == {"0100007F"} and _listening(zmq_port) == {"0100007F"}
    live.show(flight.traj.x[5], flight.traj.t[5], flight.params)
    live.close()
    live.close()
    with pytest.raises(ProcessLookupError):
        os.killpg(pid, 0)
    assert not _listening(web_port)


def test_live_server_exits_when_its_parent_is_killed(tmp_path):
    script = ("import time; from mbs import scenes; from viewer.live import LiveViewer\n"
              "v = LiveViewer(scenes.get('demo-driven').system('vm'))\nprint(v.pid, flush=True)\ntime.sleep(60)\n")
    parent = subprocess.Popen([sys.executable, "-c", script], stdout=subprocess.PIPE, text=True)
    try:
        server = int(parent.stdout.readline())
    finally:
        parent.kill()
        parent.wait(10)
        parent.stdout.close()
    deadline = time.monotonic() + 5
    while not _gone(server) and time.monotonic() < deadline:
        time.sleep(0.05)
    gone = _gone(server)
    if not gone:
        os.killpg(server, 9)
    assert gone
