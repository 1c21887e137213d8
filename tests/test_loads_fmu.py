"""Both FMUs output the hub loads, the blade root loads, the shaft and engine power, equal to
the core's (1e-9), through a collective step and a cyclic doublet. Every FMU runs under fmpy
in a fresh interpreter (``python -m fmu_hosts.modes``); the FMUs are built once and cached."""
from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from fmu import build, hosts
from mbs.loads.outputs import COMPONENTS

NAMES = [*(f"{r}.hub.{c}" for r in ("main_rotor", "tail_rotor") for c in COMPONENTS),
         *(f"blade1.root.{c}" for c in (*COMPONENTS, "pitch_torque")),
         "main_rotor.shaft_torque", "main_rotor.shaft_power", "tail_rotor.shaft_power", "engine.power"]
STEPS = 350  # past the collective step (2 revolutions) into the doublet (4 revolutions)


@pytest.fixture(scope="module")
def native_fmu() -> Path:
    from fmu.native import build as native_build

    return native_build.ensure_native_fmu(build.DEFAULT_SCENES)[0]


def fmpy(fmu: Path, args: dict, tmp_path: Path) -> dict:
    path = tmp_path / f"fmpy-{fmu.stem}.json"
    path.write_text(json.dumps({"fmu": str(fmu), **args}))
    proc = subprocess.run([sys.executable, "-m", "fmu_hosts.modes", "fmpy", str(path)], cwd=tmp_path, capture_output=True,
                          text=True, timeout=600, env=dict(os.environ))
    assert proc.returncode == 0, proc.stderr[-3000:]
    return json.loads(proc.stdout.strip().splitlines()[-1])


def test_both_fmus_output_the_loads_equal_to_the_core(python_fmu, python_spec, native_fmu, tmp_path):
    spec = python_spec
    outputs = {v["name"]: v for v in spec["variables"] if v["causality"] == "output"}
    assert set(NAMES) <= set(outputs) and outputs["main_rotor.hub.force_z"]["unit"] == "N"
    assert outputs["engine.power"]["unit"] == "W"
    assert "transmission efficiency" in outputs["engine.power"]["description"]
    dt = spec["default_experiment"]["step"]
    inputs = {v["name"]: spec["scenes"]["forward-flight"]["defaults"][v["name"]]
              for v in spec["variables"] if v["causality"] == "input"}
    table = hosts.pitch_schedule(inputs, dt, 100)
    ref = hosts.run_core("forward-flight", hosts.grid(STEPS * dt, dt), table, names=NAMES)
    args = {"stop": STEPS * dt, "dt": dt, "table": hosts.table_rows(table), "names": NAMES}
    for fmu in (python_fmu, native_fmu):
        run = fmpy(fmu, args, tmp_path)
        assert len(run["time"]) == STEPS
        worst = 0.0
        for n in NAMES:
            scale = max(np.abs(ref[n]).max(), 1.0)
            np.testing.assert_allclose(run[n], ref[n], rtol=1e-9, atol=1e-9 * scale, err_msg=f"{fmu.name}: {n}")
            worst = max(worst, float(np.abs(np.subtract(run[n], ref[n])).max() / scale))
        print(f"{fmu.name}: loads against the core, largest difference {worst:.1e} of each output's range")
    force = np.asarray(ref["main_rotor.hub.force_z"])
    assert force[250] < force[150] - 500  # the collective step pulls the airframe up harder
