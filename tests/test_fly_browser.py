"""The flight page (heli fly) in a real browser: headless Debian Chromium via Playwright (see
browser_fixtures: skipped without Chromium, failing in CI). The WebAssembly model, the trims and
the pages are built once per module."""
from __future__ import annotations

import base64
import io
import json
import math
from pathlib import Path

import numpy as np
import pytest

from browser_fixtures import browser, count_color, page, pixels  # noqa: F401  (fixtures)
from fmu import hosts
from mbs import scenes, starts
from mbs.inputs import read_table, run_held
from viewer.fly import write_page

SCENE = "forward-flight"
REVS = 7  # the demo's collective step (rev 2) and longitudinal-cyclic doublet (revs 4 to 6), then one more


@pytest.fixture(scope="module")
def pages(tmp_path_factory):
    """The Bo105 forward-flight page with its own trim (10 m/s) and the hover trim (0 m/s), flat
    colours, and the same with the default look."""
    folder = tmp_path_factory.mktemp("fly")
    return {"flat": write_page(SCENE, folder / "flat.html", speeds=[0.0], flat=True),
            "default": write_page(SCENE, folder / "fly.html", speeds=[])}


def open_page(page, built, ready="window.__fly && window.__fly.state.ready && window.__fly.state.frame"):
    page.goto(built.path.as_uri())
    page.wait_for_function(ready, timeout=30000)
    return page


def config(built) -> dict:
    text = built.path.read_text()
    start = text.index('<script id="fly-data" type="application/json">') + len('<script id="fly-data" type="application/json">')
    return json.loads(text[start:text.index("</script>", start)].replace("<\\/", "</"))["config"]


def fly_until(page, t: float, scale="max") -> dict:
    """Fly to simulated time ``t`` (s) at the time scale ``scale`` and pause there; the last frame."""
    page.evaluate(f"window.__fly.scale({json.dumps(scale)})")
    page.evaluate(f"window.__fly.until({t!r})")
    page.wait_for_function("t => { const f = window.__fly.state.frame; return f && (f.stopped || !f.running && f.t >= t - 1e-9); }",
                           arg=t, timeout=120000)
    return page.evaluate("window.__fly.state.frame")


def demo_table(cfg: dict, path: Path) -> Path:
    """The FMU demo's input table on the page's start 0: its trim, then a collective step of 0.02 rad
    at revolution 2 and a longitudinal-cyclic doublet of 0.01 rad at revolutions 4 to 6."""
    trim = dict(zip([q["name"] for q in cfg["inputs"]], cfg["starts"][0]["controls"]))
    table = hosts.pitch_schedule(trim, cfg["h"], cfg["steps_per_rev"])
    names = table.dtype.names
    lines = [",".join(names)] + [",".join(repr(float(row[n])) for n in names) for row in table]
    path.write_text("\n".join(lines) + "\n")
    return path


def core_run(cfg: dict, table_path: Path, steps: int) -> np.ndarray:
    """The core's run of the same inputs from the same start: hinge angles (steps + 1, nh)."""
    sc = scenes.get(SCENE)
    system = sc.system("compiled")
    start = starts.periodic(sc, None, system=system)
    p = system.params(start.controls)
    traj, _ = run_held(system, start.x0, cfg["h"], steps, p, read_table(table_path))
    return traj.x[:, cfg["hinge"]]


def test_page_loads_from_file_offline_with_webgl(page, pages):
    built = pages["default"]
    requests = []
    page.on("request", lambda r: requests.append(r.url))
    page.context.set_offline(True)
    open_page(page, built)
    assert page.evaluate("!!viewer.renderer.getContext()")
    for control in ("#run", "#reset", "#start", "#scale", "#sas", "#record", "#trim", "#charts", "#tpp", "#stick"):
        assert page.locator(control).is_visible(), control
    # the model, the worker and the viewer are all in the file (the worker starts from a Blob of its text)
    assert requests[0] == built.path.as_uri() and all(r.startswith("blob:") for r in requests[1:]), requests
    assert page.errors == []
    assert built.size < 5_000_000


def test_scripted_flight_equals_the_core_and_its_record_replays_in_heli_simulate(page, pages, tmp_path):
    """The demo's collective step and cyclic doublet flown through the page's own input path (its
    'fly a table' file input) at the largest time scale: the hinge angles after every step equal the
    core's run of the same inputs from the same start to 1e-9 rad; the page's record (the inputs
    CSV it downloads) replayed by heli simulate --start periodic gives them to 1e-9 rad too."""
    built = pages["flat"]
    cfg = config(built)
    steps = REVS * cfg["steps_per_rev"]
    table = demo_table(cfg, tmp_path / "demo.csv")
    open_page(page, built)
    page.set_input_files("#table-file", str(table))
    page.wait_for_function("window.__fly.state.frame.table === 'demo.csv'")
    frame = fly_until(page, steps * cfg["h"])
    assert frame["k"] == steps and not frame["stopped"]
    history = page.evaluate("window.__fly.history()")
    got = np.array(history["values"])
    assert got.shape == (steps + 1, len(cfg["hinge"])) and history["names"] == cfg["hinge_names"]
    core = core_run(cfg, table, steps)
    err = np.abs(got - core).max()
    assert err < 1e-9, err
    assert np.ptp(core[:, 0]) > 0.01  # the inputs move the blades
    with page.expect_download() as download:
        page.click("#record")
    csv = tmp_path / "flown.csv"
    download.value.save_as(csv)
    from mbs.cli import main

    out = tmp_path / "replay"
    assert main(["simulate", SCENE, "--start", "periodic", "--revs", str(REVS), "--inputs", str(csv), "--out", str(out),
                 "--quiet"]) == 0
    cols = np.genfromtxt(out / "results.csv", delimiter=",", names=True)
    replay = np.column_stack([cols[n.replace(".", "")] if n.replace(".", "") in cols.dtype.names else cols[n]
                              for n in cfg["hinge_names"]])
    err = np.abs(replay - got).max()
    assert err < 1e-9, err
    assert page.errors == []
