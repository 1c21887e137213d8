"""The exported page and the live server in a real browser: headless Debian Chromium via
Playwright (see browser_fixtures: skipped without Chromium, failing in CI)."""
from __future__ import annotations

import os
import re

import numpy as np
import pytest

from browser_fixtures import count_color, open_viewer, pixels
from mbs import scenes
from mbs.simulate import simulate
from viewer import animation as anim
from viewer import export_html, pack
from viewer import kinematics as kin
from viewer.export import data_in

SCENE = "forward-flight" if "forward-flight" in scenes.all_scenes() else "demo-driven"


@pytest.fixture(scope="module")
def sim():
    return simulate(SCENE, 1.0, backend="vm")


@pytest.fixture(scope="module")
def pages(sim, tmp_path_factory):
    """The default page and a flat-colour page (unlit, no background, grid or axes)."""
    folder = tmp_path_factory.mktemp("pages")
    return {"default": export_html(sim, folder / "viewer.html"),
            "flat": export_html(sim, folder / "flat.html", flat=True)}


def _transforms(page, paths):
    """Node transforms (n, 4, 4) of ``paths`` in the page (three.js stores them column-major)."""
    got = page.evaluate("paths => paths.map(p => mcLocal(p))", paths)
    return np.array(got).reshape(len(paths), 4, 4).transpose(0, 2, 1)


def _node_paths(exp):
    return [exp.scene.paths[b] for b in exp.scene.body_names] + ["/meshcat/model/world"]


def _core_transforms(exp, t: float, follow: bool = True) -> np.ndarray:
    """The core's body poses at ``t`` (s) as the page's node transforms: bodies relative to
    their parents, then the world node (minus the fuselage origin now, or at the start)."""
    rec, mo = exp.motion.recording, exp.motion
    origins, rotations = rec.system.poses(rec.state_at(t), t, rec.params_at(t))
    world = np.eye(4)
    world[:3, 3] = -(origins[0] if follow else mo.origins[0, 0])
    return np.concatenate([kin.relative(kin.homogeneous(origins, rotations), mo.parents), world[None]])


def test_page_renders_with_webgl_and_no_errors(page, pages):
    exp = pages["default"]
    requests = []
    page.on("request", lambda r: requests.append(r.url))
    page.context.set_offline(True)
    open_viewer(page, exp.path.as_uri())
    renderer = page.evaluate("""() => { const gl = viewer.renderer.getContext();
        const ext = gl.getExtension('WEBGL_debug_renderer_info');
        return ext ? gl.getParameter(ext.UNMASKED_RENDERER_WEBGL) : gl.getParameter(gl.RENDERER); }""")
    assert renderer
    for control in ("#play", "#time", "#readout", "#speed", "#follow", "#plot"):
        assert page.locator(control).is_visible(), control
    page.evaluate("mcSeek(0.03)")
    rgb = pixels(page)
    assert len(np.unique(rgb.reshape(-1, 3), axis=0)) > 100  # a rendered scene, not a blank canvas
    assert page.errors == []
    assert requests == [exp.path.as_uri()]  # offline: nothing but the file itself is fetched


def test_every_main_rotor_blade_is_visible(page, pages):
    exp = pages["flat"]
    open_viewer(page, exp.path.as_uri())
    blades = [b for b in exp.scene.body_names if b.startswith("blade")]
    assert len(blades) == (4 if SCENE == "forward-flight" else 3)
    for k in (0, len(exp.motion.t) // 8):
        page.evaluate(f"mcSeek({float(exp.motion.t[k])!r})")
        rgb = pixels(page)
        counts = {b: count_color(rgb, exp.scene.colors[b]) for b in blades}
        assert min(counts.values()) > 150, counts
    assert page.errors == []


def test_browser_node_transforms_equal_python_at_keys(page, pages):
    exp = pages["flat"]
    open_viewer(page, exp.path.as_uri())
    paths = [exp.scene.paths[b] for b in exp.scene.body_names]
    keys = list(range(len(exp.motion.t)))
    got = page.evaluate("""([times, paths]) => times.map(t => { mcSeek(t); return paths.map(p => mcLocal(p)); })""",
                        [[float(exp.motion.t[k]) for k in keys], paths])
    got = np.array(got).reshape(len(keys), len(paths), 4, 4).transpose(0, 1, 3, 2)  # column-major
    err = np.abs(got - exp.motion.local[keys]).max()
    assert err < 1e-5, err
    assert page.errors == []


def test_picture_changes_between_two_times(page, pages):
    exp = pages["flat"]
    open_viewer(page, exp.path.as_uri())
    eighth = len(exp.motion.t) // 8  # 45 deg of main-rotor azimuth
    page.evaluate(f"mcSeek({float(exp.motion.t[0])!r})")
    a = pixels(page).astype(int)
    page.evaluate(f"mcSeek({float(exp.motion.t[eighth])!r})")
    b = pixels(page).astype(int)
    changed = int((np.abs(a - b).max(axis=-1) > 30).sum())
    assert changed > 500, changed


def test_pause_stops_the_motion(page, pages):
    """The page plays on load (transforms change); the pause button (and the space bar) stop
    it: the time and every node transform stay constant."""
    exp = pages["default"]
    open_viewer(page, exp.path.as_uri())
    paths = _node_paths(exp)
    assert page.evaluate("__player.state().playing") and "pause" in page.text_content("#play")
    before = _transforms(page, paths)
    page.wait_for_function("t => __player.state().time > t + 0.002", arg=page.evaluate("__player.state().time"))
    assert np.abs(_transforms(page, paths) - before).max() > 1e-3  # playing: the rotor turns
    page.click("#play")
    assert "play" in page.text_content("#play") and not page.evaluate("__player.state().playing")
    paused, t_paused = _transforms(page, paths), page.evaluate("__player.state().time")
    page.wait_for_timeout(400)
    np.testing.assert_array_equal(_transforms(page, paths), paused)
    assert page.evaluate("__player.state().time") == t_paused
    page.keyboard.press(" ")  # space bar: play again
    page.wait_for_function("t => __player.state().time > t", arg=t_paused)
    page.keyboard.press(" ")
    assert not page.evaluate("__player.state().playing")
    assert page.errors == []


def _readout(page) -> tuple[float, float, float]:
    text = page.text_content("#readout")
    m = re.fullmatch(r"t = (\S+) s\s+rev (\S+)\s+azimuth (\S+)\u00b0", text.strip())
    assert m, text
    return tuple(float(v) for v in m.groups())


def test_slider_sets_the_time_pose_readout_and_plot_cursor(page, pages):
    """The slider goes to the key nearest the time it is set to: the player's time is that
    key's, the node transforms equal the core's body poses at that time to 1e-5 (float32
    keys: measured 1.7e-7), the readout shows the time, revolution and azimuth, and the plot
    cursor stands at that time. Arrow keys step one key back or on."""
    exp = pages["default"]
    open_viewer(page, exp.path.as_uri())
    page.click("#play")  # pause
    mo, paths = exp.motion, _node_paths(exp)
    revolution = mo.recording.revolution
    omega = 2 * np.pi / revolution
    svg = page.evaluate("(() => { const d = document.getElementById('plot').dataset; "
                        "return [+d.t0, +d.t1, +d.x0, +d.x1]; })()")
    k, last = len(mo.t) // 3, len(mo.t) - 1
    for target, key in ((mo.t[0], 0), (mo.t[k], k), (0.7 * mo.t[k] + 0.3 * mo.t[k + 1], k),
                        (0.3 * mo.t[k] + 0.7 * mo.t[k + 1], k + 1), (0.77 * mo.t[-1], round(0.77 * last)),
                        (mo.t[-1], last)):
        page.locator("#time").fill(repr(float(target)))
        t = page.evaluate("__player.state().time")
        assert t == mo.t[key]
        err = np.abs(_transforms(page, paths) - _core_transforms(exp, t)).max()
        assert err < 1e-5, (t, err)
        shown_t, shown_rev, shown_az = _readout(page)
        assert shown_t == round(t, 4) and shown_rev == round(t / revolution, 3)
        az = np.degrees(omega * t) % 360
        assert min(abs(shown_az - az), 360 - abs(shown_az - az)) < 0.051
        x = float(page.get_attribute("#plot-cursor", "x1"))
        assert svg[0] + (x - svg[2]) / (svg[3] - svg[2]) * (svg[1] - svg[0]) == pytest.approx(t, abs=1e-9)
    page.evaluate(f"__player.seek({float(0.5 * (mo.t[k] + mo.t[k + 1]))!r})")
    page.locator("#plot").focus()
    for key, expected in (("ArrowLeft", k), ("ArrowLeft", k - 1), ("ArrowRight", k), ("ArrowRight", k + 1)):
        page.keyboard.press(key)
        assert page.evaluate("__player.state().time") == mo.t[expected]
    assert page.errors == []


def test_between_keys_the_page_moves_as_python_says(page, pages):
    """Playing passes through times between keys: there the node transforms are the mapping
    of viewer.animation (local_at, world_at) to 1e-12 (measured 1.5e-15)."""
    exp = pages["default"]
    open_viewer(page, exp.path.as_uri())
    mo, paths = exp.motion, _node_paths(exp)
    kf = pack.keyframes_of(data_in(exp.path))
    for k in range(0, len(mo.t) - 1, 7):
        t = float(0.37 * mo.t[k] + 0.63 * mo.t[k + 1])
        page.evaluate(f"mcSeek({t!r})")
        mine = anim.local_at(kf, t)
        expected = np.array([mine[p] for p in paths[:-1]] + [anim.world_at(kf, t)])
        err = np.abs(_transforms(page, paths) - expected).max()
        assert err < 1e-12, (t, err)
    assert page.errors == []


def test_camera_follows_the_fuselage_or_stays(page, pages):
    """Follow (default): the world node is moved by minus the fuselage origin now; unticked,
    by minus its origin at the start, so the aircraft flies off through the view."""
    exp = pages["default"]
    open_viewer(page, exp.path.as_uri())
    page.click("#play")
    t = float(exp.motion.t[-1])
    page.locator("#time").fill(repr(t))
    world = "/meshcat/model/world"
    np.testing.assert_allclose(_transforms(page, [world])[0], _core_transforms(exp, t)[-1], atol=1e-9)
    page.uncheck("#follow")
    fixed = _transforms(page, [world])[0]
    np.testing.assert_allclose(fixed, _core_transforms(exp, t, follow=False)[-1], atol=1e-9)
    assert np.linalg.norm(fixed[:3, 3] - _core_transforms(exp, t)[-1][:3, 3]) > 1.0  # 10 m/s for 0.14 s
    page.check("#follow")
    np.testing.assert_allclose(_transforms(page, [world])[0], _core_transforms(exp, t)[-1], atol=1e-9)


def test_speed_control_sets_the_rate_of_play(page, pages):
    """Simulated seconds per wall second follow the speed control (x0.01 and x0.1 of real time)."""
    exp = pages["default"]
    open_viewer(page, exp.path.as_uri())
    rates = {}
    for speed in ("0.01", "0.1"):
        page.select_option("#speed", speed)
        page.evaluate(f"__player.pause(); __player.seek({float(exp.motion.t[0])!r}); __player.play()")
        rates[speed] = page.evaluate("""() => new Promise(done => {
            const t0 = __player.state().time, w0 = performance.now();
            setTimeout(() => done((__player.state().time - t0) / ((performance.now() - w0) / 1000)), 600); })""")
    for speed, rate in rates.items():
        assert 0.5 * float(speed) < rate < 1.2 * float(speed), rates


def test_plot_shows_every_panel_of_the_run(page, pages, sim):
    """One polyline per series, spanning the whole run, with the run's values."""
    exp = pages["default"]
    open_viewer(page, exp.path.as_uri())
    doc = data_in(exp.path)["plot"]
    names = [s["name"] for p in doc["panels"] for s in p["series"]]
    drawn = page.evaluate("Array.from(document.querySelectorAll('#plot polyline')).map(e => "
                          "[e.dataset.name, e.getAttribute('points').split(' ').length])")
    assert [d[0] for d in drawn] == names and all(n == len(sim.traj.t) for _, n in drawn)
    titles = page.evaluate("Array.from(document.querySelectorAll('#plot text')).map(e => e.textContent)")
    for title in ("collective pitch (deg)", "cyclic pitch (deg)", "time (s)", "main-rotor revolutions"):
        assert title in titles
    assert page.errors == []


def test_live_update_reaches_the_page_and_the_server_stops(page, sim):
    """Poses streamed while a simulation runs show up in the page; the server is gone after close."""
    from viewer.live import LiveViewer

    live = LiveViewer(sim.system)
    try:
        hub = live.scene.paths[sim.system.info.body_names[1]]
        open_viewer(page, live.url, ready="viewer.scene_tree.children.meshcat !== undefined")
        page.wait_for_function(f"mcNode('{hub}/shape/0/<object>') !== null")
        t, x = live.simulate(SCENE, revs=0.3, slow=1.0)  # the hub turns by about a third of a revolution
        np.testing.assert_allclose(x, sim.traj.x[30], atol=1e-8)  # streaming does not change the run
        origins, rotations = sim.system.poses(x, t, sim.params)
        expected = live._transforms(origins, rotations)[0][1]
        page.wait_for_function("""([p, m]) => { const g = mcLocal(p);
            return g !== null && g.every((v, i) => Math.abs(v - m[i]) < 1e-6); }""",
                               arg=[hub, expected.T.ravel().tolist()], timeout=10000)
        assert page.errors == []
    finally:
        pid = live.pid
        live.close()
    with pytest.raises(ProcessLookupError):
        os.killpg(pid, 0)


def test_hub_load_arrows_stand_where_their_tracks_say_and_are_drawn(page, pages):
    """The hub force and moment arrows (viewer/loads.py): at keys the arrow nodes' transforms
    (position, turn and scale) are their tracks', and the red force arrow is on the picture."""
    from viewer.loads import KINDS

    exp = pages["flat"]
    arrows = data_in(exp.path)["arrows"]
    if not arrows:
        pytest.skip(f"{SCENE} has no hub loads")
    open_viewer(page, exp.path.as_uri())
    tracks = {a["path"]: {k: pack.decode(a[k]) for k in ("position", "quaternion", "scale")} for a in arrows}
    keys = [0, len(exp.motion.t) // 3, len(exp.motion.t) - 1]
    got = page.evaluate("""([times, paths]) => times.map(t => { mcSeek(t); return paths.map(p => mcLocal(p)); })""",
                        [[float(exp.motion.t[k]) for k in keys], list(tracks)])
    got = np.array(got).reshape(len(keys), len(tracks), 4, 4).transpose(0, 1, 3, 2)  # column-major
    for j, (path, tr) in enumerate(tracks.items()):
        for n, k in enumerate(keys):
            position, quaternion, scale = (v[min(k, len(v) - 1)] for v in tr.values())  # constant: one row
            want = kin.homogeneous(position, kin.rotations_xyzw(quaternion)) @ np.diag([*scale, 1.0])
            np.testing.assert_allclose(got[n, j], want, atol=1e-5, err_msg=path)
    page.evaluate(f"mcSeek({float(exp.motion.t[-1])})")
    assert count_color(pixels(page), int(KINDS["force"][0][1:], 16), tol=30) > 30
    assert page.errors == []
