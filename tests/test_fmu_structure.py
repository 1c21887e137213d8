"""``ModelStructure`` of both FMUs: the outputs' direct dependencies on the inputs and the
initial unknowns' dependencies are those of the generated functions' sparsity (recomputed
here from the CasADi functions shipped in the pythonfmu FMU, by a symbolic Jacobian rather
than the build's sparsity propagation), and those an FMI host measures: moving an input
without a step changes exactly the outputs declared to depend on it."""
from __future__ import annotations

import json
import re
import subprocess
import sys
import zipfile
from pathlib import Path
from xml.etree import ElementTree

import numpy as np
import pytest

from fmu import build

FAMILY = build.DEFAULT_SCENES


def _native() -> Path:
    from fmu.native import build as native_build

    return native_build.ensure_native_fmu(FAMILY)[0]


FMUS = {"python": lambda: build.ensure_fmu(FAMILY)[0], "native": _native}


@pytest.fixture(scope="module", params=sorted(FMUS))
def fmu_path(request) -> Path:
    return FMUS[request.param]()


def declared(fmu: Path) -> tuple[list[str], dict, dict]:
    """(variable names by index - 1, outputs {name: {dependency: kind}}, initial unknowns likewise)."""
    root = ElementTree.fromstring(zipfile.ZipFile(fmu).read("modelDescription.xml"))
    svs = list(root.find("ModelVariables"))
    names = [sv.get("name") for sv in svs]
    outputs = {sv.get("name") for sv in svs if sv.get("causality") == "output"}
    # the native FMU's model exchange also declares dependencies on the continuous states
    # (tests/test_fmu_me.py checks those): here, the outputs on inputs and parameters
    states = {names[int(sv[0].get("derivative")) - 1] for sv in svs if sv[0].get("derivative")}

    def read(tag: str) -> dict:
        out = {}
        for u in root.find("ModelStructure").find(tag):
            deps, kinds = u.get("dependencies").split(), u.get("dependenciesKind").split()
            assert len(deps) == len(kinds), u.attrib
            if names[int(u.get("index")) - 1] in outputs:
                out[names[int(u.get("index")) - 1]] = {names[int(d) - 1]: k for d, k in zip(deps, kinds)
                                                       if names[int(d) - 1] not in states}
        return out

    return names, read("Outputs"), read("InitialUnknowns")


def shipped_sparsity() -> dict:
    """Per output, the inputs whose symbolic partial derivative in ``fmu_outputs`` is not
    structurally zero in some model of the family (functions from the pythonfmu FMU)."""
    import casadi as ca

    z = zipfile.ZipFile(build.ensure_fmu(FAMILY)[0])
    spec = json.loads(z.read("resources/heli_models/spec.json"))
    computed = [v["name"] for v in spec["variables"] if v["causality"] in ("output", "local")]
    inputs = {v["name"] for v in spec["variables"] if v["causality"] == "input"}
    out = {n: set() for n in computed}
    for group in {s["group"] for s in spec["scenes"].values()}:
        f = _load(z, group)
        params = next(s["parameter_order"] for s in spec["scenes"].values() if s["group"] == group)
        x, t, p = f.mx_in()
        jac = ca.jacobian(f(x, t, p), p).sparsity()
        rows, cols = jac.get_triplet()
        for r, c in zip(rows, cols):
            if params[c] in inputs:
                out[computed[r]].add(params[c])
    return out


def _load(z: zipfile.ZipFile, group: str):
    import tempfile

    import casadi as ca

    with tempfile.NamedTemporaryFile(suffix=".casadi") as tmp:
        tmp.write(z.read(f"resources/heli_models/{group}/vm/fmu_outputs.casadi"))
        tmp.flush()
        return ca.Function.load(tmp.name)


def test_outputs_depend_on_exactly_the_inputs_of_the_sparsity(fmu_path):
    names, outputs, _ = declared(fmu_path)
    sparsity = shipped_sparsity()
    assert set(outputs) == {n for n in names if n in sparsity and n in outputs}
    assert {n: set(d) for n, d in outputs.items()} == {n: sparsity[n] for n in outputs}
    states = [n for n in outputs if re.fullmatch(r"(blade\d+|seesaw)\.(flap|lag|teeter)(_rate)?", n)
              or n.startswith("fuselage.") and not n.endswith("download")]
    assert len(states) > 20 and all(not outputs[n] for n in states)
    assert outputs["blade1.root.moment_x"], "blade loads feel the pitch inputs at once (accelerations)"
    assert any(outputs.values()), "some outputs (rotor loads, power) have direct feedthrough"
    assert set(outputs["main_rotor.thrust"]) >= {"collective"}


def test_initial_unknowns_are_every_output_with_its_start_parameters(fmu_path):
    names, outputs, initial = declared(fmu_path)
    assert list(initial) == list(outputs)  # every output, in index order
    for n, deps in initial.items():
        assert set(outputs[n]) <= set(deps), n
        assert [names.index(d) for d in deps] == sorted(names.index(d) for d in deps), n
    assert {"scene", "initial_state"} <= set(initial["fuselage.q"]) and "collective" not in initial["fuselage.q"]
    assert "initial_forward_speed" in initial["fuselage.u"] and "initial_forward_speed" not in initial["blade1.flap"]


def test_an_input_moved_without_a_step_changes_exactly_its_declared_outputs(fmu_path, tmp_path):
    _, outputs, _ = declared(fmu_path)
    args = tmp_path / "args.json"
    args.write_text(json.dumps({"fmu": str(fmu_path), "delta": 0.01}))
    proc = subprocess.run([sys.executable, "-m", "fmu_hosts.probe_fmi", "feedthrough", str(args)], cwd=tmp_path,
                          capture_output=True, text=True, timeout=300)
    assert proc.returncode == 0, proc.stderr[-2000:]
    moved = json.loads(proc.stdout.strip().splitlines()[-1])
    for name, changed in moved.items():
        assert set(changed) == {o for o, d in outputs.items() if name in d}, name
    assert np.any([len(c) for c in moved.values()])
