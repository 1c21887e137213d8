"""The exported page and the live server in a real browser: headless Debian Chromium via
Playwright (see browser_fixtures: skipped without Chromium, failing in CI)."""
from __future__ import annotations

import os

import numpy as np
import pytest

from browser_fixtures import browser, count_color, open_viewer, page, pixels  # noqa: F401  (fixtures)
from mbs import scenes
from mbs.simulate import simulate
from viewer import export_html

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


def _clip_time(exp, k: int) -> float:
    """Clip time of key ``k`` as three.js stores it (float32), so a seek lands on the key."""
    return float(np.float32((exp.motion.t[k] - exp.motion.t[0]) * exp.slow))


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
    assert page.evaluate("viewer.animator.actions.length") > 0
    assert page.evaluate("viewer.animator.duration") == pytest.approx(exp.duration, rel=1e-6)
    page.evaluate("mcSeek(0.3)")
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
        page.evaluate(f"mcSeek({_clip_time(exp, k)})")
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
                        [[_clip_time(exp, k) for k in keys], paths])
    got = np.array(got).reshape(len(keys), len(paths), 4, 4).transpose(0, 1, 3, 2)  # column-major
    err = np.abs(got - exp.motion.local[keys]).max()
    assert err < 1e-5, err
    assert page.errors == []


def test_picture_changes_between_two_times(page, pages):
    exp = pages["flat"]
    open_viewer(page, exp.path.as_uri())
    eighth = len(exp.motion.t) // 8  # 45 deg of main-rotor azimuth
    page.evaluate(f"mcSeek({_clip_time(exp, 0)})")
    a = pixels(page).astype(int)
    page.evaluate(f"mcSeek({_clip_time(exp, eighth)})")
    b = pixels(page).astype(int)
    changed = int((np.abs(a - b).max(axis=-1) > 30).sum())
    assert changed > 500, changed


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
