"""heli fly without a browser: the page's contents, the WebAssembly model's exports, the starts of
heli simulate (``--start``). The flight itself, in Chromium: tests/test_fly_browser.py."""
from __future__ import annotations

import json
import re

import numpy as np
import pytest

from mbs import cli, scenes, starts


def wasm_exports(module: bytes) -> list[str]:
    """The names a WebAssembly module exports (its export section, read by hand)."""
    def leb(i: int) -> tuple[int, int]:
        value = shift = 0
        while True:
            byte = module[i]
            i += 1
            value |= (byte & 0x7F) << shift
            shift += 7
            if byte < 0x80:
                return value, i
    i, names = 8, []
    while i < len(module):
        section, i = module[i], i + 1
        size, i = leb(i)
        if section == 7:
            count, j = leb(i)
            for _ in range(count):
                n, j = leb(j)
                names.append(module[j:j + n].decode())
                j += n + 1
                _, j = leb(j)
        i += size
    return names


@pytest.fixture(scope="module")
def stand(tmp_path_factory):
    """``heli fly ground-run --json``: the page of the rotor on a stand, and the command's JSON."""
    import contextlib
    import io

    out = tmp_path_factory.mktemp("fly") / "stand.html"
    stdout = io.StringIO()
    with contextlib.redirect_stdout(stdout):
        assert cli.main(["fly", "ground-run", "--html", str(out), "--json"]) == 0
    return out, json.loads(stdout.getvalue())


def test_heli_fly_writes_a_self_contained_page(stand):
    out, res = stand
    text = out.read_text()
    assert res["html"] == str(out) and res["bytes"] == out.stat().st_size < 5_000_000
    assert res["scene"] == "ground-run" and not res["free_fuselage"] and not res["controller"]
    assert "a rotor on a stand" in res["note"] and len(res["starts"]) == 1
    urls = set(re.findall(r"(?:https?|wss?|ftp)://[^\s\"'<>)]*", text))
    assert urls <= {"http://www.w3.org/1999/xhtml", "http://www.w3.org/2000/svg", "ws://${location.host}`"}, urls
    assert "<script src" not in text and 'id="model-wasm"' in text


def test_the_webassembly_model_is_the_core_without_the_fmi_wrappers():
    """The module exports the page's entry points (heli_wasm.c) and nothing of the FMI wrappers: the
    page drives the model core directly; its only imports are WASI's."""
    from fmu.native import wasm
    from viewer.fly import family

    built = wasm.ensure_model(family("forward-flight"))
    names = wasm_exports(built.wasm.read_bytes())
    assert {"hw_open", "hw_step", "hw_run", "hw_load", "hw_poses", "hw_get", "hw_message", "memory"} <= set(names)
    assert not [n for n in names if n.startswith(("fmi2", "fmi3"))]
    assert built.spec["poses"] == {"forward_flight": 120, "ground_run": 120}  # 10 bodies, origin and rotation each


@pytest.mark.parametrize("text, expected", [("scene", ("scene", None)), ("periodic", ("periodic", None)),
                                            ("periodic:20", ("periodic", 20.0)), ("periodic:-5.5", ("periodic", -5.5))])
def test_start_names(text, expected):
    assert starts.parse(text) == expected


def test_heli_simulate_from_a_periodic_trim_at_a_speed_repeats_each_shooting_interval(tmp_path):
    """``--start periodic:20``: the trim at 20 m/s (controls, attitude, every rotor state), so with its
    controls held the rotor repeats itself from the first revolution: after the trim's shooting
    interval (two revolutions) every hinge angle is back to 1e-8 rad; run.json records the start."""
    out = tmp_path / "run"
    assert cli.main(["simulate", "forward-flight", "--start", "periodic:20", "--revs", "2", "--out", str(out),
                     "--quiet"]) == 0
    run = json.loads((out / "run.json").read_text())
    assert run["set"]["start"] == "periodic:20"
    header = (out / "results.csv").read_text().split("\n", 1)[0].split(",")
    rows = np.loadtxt(out / "results.csv", delimiter=",", skiprows=1)
    hinges = [header.index(f"blade{k}.{h}") for k in range(1, 5) for h in ("flap", "lag")]
    assert np.abs(rows[-1, hinges] - rows[0, hinges]).max() < 1e-8
    trim = starts.periodic(scenes.get("forward-flight"), 20.0)
    assert rows[0, header.index("fuselage.u")] == pytest.approx(trim.x0[scenes.get("forward-flight").system(
        "compiled").info.state_names.index("fuselage.u")], abs=1e-12)
    assert run["parameters"]["collective"] == trim.controls["collective"]
