"""The closed loop: the helicopter FMU (native, hover from its periodic trim, 1 m/s initial
disturbance) and the hover-hold controller FMU in one SSP file, run by libcosim (which reads
the .ssp) and by our fmpy master loop: the two masters agree to 1e-9 (they give the same bits),
libcosim reports no algebraic loop, the closed loop holds the hover for 60 s while the open loop
diverges; the controller FMU passes fmpy's validation and fmutool's checks, and its design is
the LQR of our own linearisation (stable, gains of the documented weights)."""
from __future__ import annotations

import json
import shutil
import subprocess
import sys
import zipfile
from pathlib import Path

import numpy as np
import pytest

from fmu import controller


@pytest.fixture(scope="module")
def cosim(tmp_path_factory) -> dict:
    out = tmp_path_factory.mktemp("cosim")
    proc = subprocess.run([sys.executable, "-m", "mbs", "cosim", "--out", str(out), "--json"], capture_output=True,
                          text=True, timeout=1200, cwd=out)
    assert proc.returncode == 0, proc.stderr[-3000:]
    return {**json.loads(proc.stdout.strip().splitlines()[-1]), "_log": proc.stdout + proc.stderr}


def test_libcosim_and_the_fmpy_master_agree(cosim):
    print(f"libcosim vs the fmpy master: largest difference {cosim['libcosim_vs_fmpy_max_abs']:.1e}")
    assert cosim["libcosim_vs_fmpy_max_abs"] <= 1e-9
    assert cosim["steps"] == round(60.0 / cosim["step_s"])


def test_fmpy_ssp_runner_cannot_run_the_ssp_as_the_readme_says(cosim):
    """fmpy's own SSP runner (``fmpy.ssp.simulation.simulate_ssp``) starts every connector at 0.0
    and ignores the SSD's parameter bindings (which give the helicopter's inputs their trim values,
    as SSP 1.0 allows): the helicopter FMU refuses ``collective = 0.0`` with fmi2Error and fmpy
    raises. Our master over fmpy (bindings applied, connections transferred in initialisation)
    equals libcosim instead (the test above)."""
    from fmpy.ssp.ssd import read_ssd

    res = cosim["fmpy_ssp_runner"]
    assert res["completed"] is False and "fmi2SetReal failed with status 3" in res["error"], res
    assert any("input 'collective' = 0.0 rad is outside its range" in m for m in res["refused"]), res
    heli = next(c for c in read_ssd(cosim["files"]["ssp"]).system.elements if c.name == "helicopter")
    bound = {p.name: p.value for b in heli.parameterBindings for s in b.parameterValues for p in s.parameters}
    trim = controller.read_design(Path(cosim["controller_fmu"]))["trim_controls"]
    assert {c: float(bound[c]) for c in controller.OUTPUTS} == trim
    assert bound["scene"] == "hover" and bound["initial_state"] == "periodic"


def test_no_algebraic_loop_and_libcosim_warns_of_nothing(cosim):
    """The declared dependencies leave no cycle of connections and direct feedthrough (a tool
    assuming every output depends on every input would find dozens); libcosim, whose
    warnings are shown, warns of nothing (it would, e.g., of a variable it ignores)."""
    assert cosim["algebraic_loops"] == [] and cosim["algebraic_loops_without_dependencies"] > 0
    assert "[warning]" not in cosim["_log"] and "[error]" not in cosim["_log"], cosim["_log"][-3000:]


def test_closed_loop_holds_the_hover_for_a_minute_and_the_open_loop_diverges(cosim):
    c, o = cosim["closed"], cosim["open"]
    assert c["max_drift_m"] < 5.0 and c["drift_beyond_5m_s"] is None
    # the aircraft's first response to the gust peaks at 1.87 deg (0.5 s)
    assert c["max_attitude_deg"] < 2.0 and c["attitude_beyond_2deg_s"] is None, c
    assert o["drift_beyond_5m_s"] is not None and o["drift_beyond_5m_s"] < 10.0, o
    assert o["attitude_beyond_20deg_s"] is not None and o["attitude_beyond_20deg_s"] < 20.0, o
    for name in ("ssp", "ssp_open", "figure", "csv", "viewer"):
        assert Path(cosim["files"][name]).stat().st_size > 0
    page = Path(cosim["files"]["viewer"]).read_text()
    assert "closed loop (HoverHold FMU)" in page and "longitudinal_cyclic" in page


def test_ssp_holds_the_system_structure_and_both_fmus(cosim):
    from fmpy.ssp.ssd import read_ssd

    ssd = read_ssd(cosim["files"]["ssp"])
    assert {c.name for c in ssd.system.elements} == {"helicopter", "controller"}
    assert len(ssd.system.connections) == len(controller.INPUTS) + len(controller.OUTPUTS)
    names = zipfile.ZipFile(cosim["files"]["ssp"]).namelist()
    assert "SystemStructure.ssd" in names and sum(n.endswith(".fmu") for n in names) == 2


def test_controller_fmu_passes_fmpy_validate_and_fmutool_check(tmp_path):
    fmu, _ = controller.ensure_controller_fmu()
    from fmpy.validation import validate_fmu

    assert validate_fmu(str(fmu)) == []
    tool = shutil.which("fmutool") or str(Path(sys.executable).parent / "fmutool")
    proc = subprocess.run([tool, "-input", str(fmu), "-check"], capture_output=True, text=True, cwd=tmp_path)
    assert proc.returncode == 0, proc.stdout + proc.stderr
    assert "No semantic error" in proc.stdout + proc.stderr


def test_controller_is_the_lqr_of_our_linearisation():
    """The gains solve the Riccati equation of the shipped A, B with Bryson's weights, and
    every closed-loop eigenvalue of the linear model is in the left half-plane (the open loop
    has the unstable phugoid)."""
    dsg = controller.read_design(controller.ensure_controller_fmu()[0])
    a, b, k = np.array(dsg["A"]), np.array(dsg["B"]), np.array(dsg["K_states"])
    np.testing.assert_allclose(controller.lqr(a, b), k, rtol=1e-9, atol=1e-12)
    assert max(re for re, _ in dsg["closed_loop"]) < -0.1
    assert max(re for re, _ in dsg["open_loop"]) > 0.0
    assert np.linalg.eigvals(a - b @ k).real.max() < 0
