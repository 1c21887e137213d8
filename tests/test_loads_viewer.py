"""The viewer's hub-load arrows and loads panel: the page's arrow tracks and plot panels
reproduce the core's hub loads (in a browser: ``tests/test_viewer_browser.py``, which holds
every browser test, since they share one Playwright session)."""
from __future__ import annotations

import numpy as np
import pytest

from mbs.simulate import simulate
from viewer import export_html, pack
from viewer import kinematics as kin
from viewer.export import commands_in, data_in
from viewer.loads import HEAD, KINDS, output_names


@pytest.fixture(scope="module")
def flight():
    return simulate("forward-flight", 1.0, backend="vm")


@pytest.fixture(scope="module")
def flight_page(flight, tmp_path_factory):
    return export_html(flight, tmp_path_factory.mktemp("loads-view") / "viewer.html", flat=True)


def arrow_tracks(path) -> dict[str, dict[str, np.ndarray]]:
    return {a["path"]: {k: pack.decode(a[k]) for k in ("position", "quaternion", "scale")}
            for a in data_in(path)["arrows"]}


def core_loads(sim, times, kind: str) -> np.ndarray:
    info, idx = sim.system.info, [sim.system.info.output_names.index(n) for n in output_names(kind)]
    return np.array([sim.system.outputs(sim.traj.x[list(sim.traj.t).index(t)], t, sim.params)[idx] for t in times])


def test_arrows_point_along_the_hub_loads_and_are_as_long_as_they_are_large(flight, flight_page):
    tracks, info = arrow_tracks(flight_page.path), flight.system.info
    base = flight_page.scene.paths["fuselage"] + "/hub_loads"
    hub_at = info.bodies[info.body_names.index("main_hub")]["at"]
    times = flight_page.motion.t
    for kind in KINDS:
        group, shaft, head = (tracks[f"{base}/{kind}{s}"] for s in ("", "/shaft", "/head"))
        direction = kin.rotations_xyzw(group["quaternion"])[:, :, 1]  # the arrow's y axis, body axes
        length = shaft["scale"][:, 1]
        loads = core_loads(flight, times, kind)
        scale = np.linalg.norm(loads, axis=1).max() / 1.5
        np.testing.assert_allclose(direction * length[:, None] * scale, loads, rtol=0, atol=2e-6 * scale * 1.5)
        np.testing.assert_allclose(group["position"][0], hub_at, atol=1e-6)
        np.testing.assert_allclose(shaft["position"][:, 1], length / 2, rtol=1e-6)
        np.testing.assert_allclose(head["position"][:, 1], length + HEAD / 2, rtol=1e-6)
    assert "main-rotor hub loads on the airframe: force 1 m = " in flight_page.path.read_text()
    shapes = [c["path"] for c in commands_in(flight_page.path) if "hub_loads" in c["path"]]
    assert len(shapes) == 4  # a shaft and a head per arrow


def test_the_plot_has_the_hub_force_and_moment_in_kn(flight, flight_page):
    panels = {p["title"]: p for p in data_in(flight_page.path)["plot"]["panels"]}
    t = pack.decode(data_in(flight_page.path)["plot"]["t"])
    for kind, title in (("force", "main-rotor hub force on the airframe, body axes (kN)"),
                        ("moment", "main-rotor hub moment on the airframe, body axes (kN m)")):
        series = panels[title]["series"]
        assert [s["name"] for s in series] == output_names(kind)
        values = np.column_stack([pack.decode(s["values"]) for s in series])
        np.testing.assert_allclose(values, core_loads(flight, t, kind) * 1e-3, rtol=1e-6, atol=1e-6)
    assert "rotor and engine power (kW)" in panels
    assert [s["name"] for s in panels["rotor and engine power (kW)"]["series"]][-1] == "engine.power"


def test_models_without_hub_loads_and_pages_asked_without_get_no_arrows(flight, tmp_path):
    demo = simulate("demo-driven", 0.5, backend="vm")
    assert data_in(export_html(demo, tmp_path / "demo.html").path)["arrows"] == []
    assert data_in(export_html(flight, tmp_path / "plain.html", loads=False).path)["arrows"] == []
