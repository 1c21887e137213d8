"""Both FMUs of the modal elastic rotor (``elastic-rotor-modal``) under fmpy against the core."""
import json
import zipfile
from pathlib import Path

import numpy as np
import pytest

from fmu import build, hosts
from fmu.native import build as native_build
from test_fmu_native import fmpy_run, max_rel

SCENE = "elastic-rotor-modal"
REVS = 2


@pytest.fixture(scope="module")
def fmus() -> tuple[Path, Path]:
    return build.ensure_fmu([SCENE])[0], native_build.ensure_native_fmu([SCENE])[0]


def test_both_fmus_of_the_modal_rotor_equal_the_core(fmus, tmp_path):
    """Two revolutions at the FMU's default step with the trim inputs held: every output (the
    modal coordinates and rates as hinge states, thrust, blade root loads, shaft torque,
    energy) of the pythonfmu FMU equals the core's run to 1e-9, the native FMU's the pythonfmu
    FMU's to 1e-9."""
    python_fmu, native_fmu = fmus
    with zipfile.ZipFile(python_fmu) as z:
        spec = json.loads(z.read("resources/heli_models/spec.json"))
    scene = spec["scenes"][SCENE]
    dt, steps = scene["revolution"] / scene["steps_per_rev"], REVS * scene["steps_per_rev"]
    names = [v["name"] for v in spec["variables"] if v["causality"] == "output"]
    assert "blade1.flap2" in names and "blade1.torsion" in names and "blade1.root.moment_y" in names
    python = fmpy_run(python_fmu, SCENE, spec, dt, steps, names, tmp_path)
    native = fmpy_run(native_fmu, SCENE, spec, dt, steps, names, tmp_path)
    inputs = {n: scene["defaults"][n] for n in ("collective", "lateral_cyclic", "longitudinal_cyclic")}
    table = np.array([(0.0, *inputs.values())], dtype=[("time", float)] + [(n, float) for n in inputs])
    core = hosts.run_core(SCENE, hosts.grid(steps * dt, dt), table, names=names)
    for n in names:
        np.testing.assert_allclose(python[n], core[n], rtol=1e-9, atol=1e-9, err_msg=n)
        np.testing.assert_allclose(native[n], python[n], rtol=1e-9, atol=1e-9, err_msg=n)
    print(f"pythonfmu vs core {max_rel(python, core, names):.1e}, "
          f"native vs pythonfmu {max_rel(native, python, names):.1e}")
