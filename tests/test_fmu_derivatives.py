"""Exact derivatives of the native FMU (FMI 2.0 and 3.0, model exchange and co-simulation):
directional derivatives against central differences of the same FMU, adjoint derivatives
against the transposed forward ones, the declared dependencies against the Jacobian's pattern,
``fmu.linearize`` against the core's (``mbs.linearize``), and CasADi's FMU import as a host
that uses them. The FMUs are C only: fmpy loads them in this process."""
from __future__ import annotations

import ctypes
import json
import subprocess
import sys
import zipfile
from xml.etree import ElementTree

import numpy as np
import pytest
from fmpy import extract, instantiate_fmu, read_model_description

from fmu.native import build as native_build

FAMILY = ("forward-flight", "hover", "ground-run")
SCENE = "forward-flight"
POINTS, DIRECTIONS = 5, 4  # 20 random (point, direction) pairs per FMU and interface


@pytest.fixture(scope="module")
def fmus() -> dict:
    return {v: native_build.ensure_native_fmu(FAMILY, fmi=v)[0] for v in (2, 3)}


class Host:
    """One initialised instance (FMI 2.0 or 3.0, ME or CS) of the forward-flight scene, with the
    knowns (continuous states (ME), then inputs) and unknowns (derivatives (ME), then outputs) as
    flat vectors: ``set(z)``, ``values()``, ``forward(v)``, ``adjoint(w)``."""

    def __init__(self, fmu, kind: str):
        self.md = read_model_description(str(fmu))
        self.v3, self.me = self.md.fmiVersion.startswith("3"), kind == "ModelExchange"
        self.inst = instantiate_fmu(extract(str(fmu)), self.md, fmi_type=kind)
        vr = {v.name: v.valueReference for v in self.md.modelVariables}
        if self.v3:
            self.inst.enterInitializationMode(startTime=0.0)
        else:
            self.inst.setupExperiment(startTime=0.0)
            self.inst.enterInitializationMode()
        self.inst.setString([vr["scene"]], [SCENE])
        self.inst.exitInitializationMode()
        if self.me:
            (self.inst.updateDiscreteStates if self.v3 else self.inst.newDiscreteStates)()
            self.inst.enterContinuousTimeMode()
        else:
            for k in range(5):  # a few steps: the communication point is not the start
                self._step(k)
        ders = [d.variable for d in self.md.derivatives] if self.me else []
        self.inputs = [v for v in self.md.modelVariables if v.causality == "input"]
        self.outputs = [v for v in self.md.modelVariables if v.causality == "output"]
        self.unknowns = [*ders, *self.outputs]
        self.n_unknown = sum(self._size(v) for v in self.unknowns)
        self.nx = sum(self._size(v) for v in ders)
        self.known_vrs = [*(d.derivative.valueReference for d in ders), *(v.valueReference for v in self.inputs)]
        self.known_sizes = [*(self._size(d) for d in ders), *(1 for _ in self.inputs)]
        self.calls = 0

    @staticmethod
    def _size(v) -> int:
        return int(np.prod([int(d.start) for d in v.dimensions])) if getattr(v, "dimensions", None) else 1

    def _step(self, k: int) -> None:
        dt = float(self.md.defaultExperiment.stepSize)
        self.inst.doStep(k * dt, dt)

    def point(self) -> np.ndarray:
        u = np.array(self._get_reals([v.valueReference for v in self.inputs], len(self.inputs)))
        if not self.me:
            return u
        buf = (ctypes.c_double * self.nx)()
        self.inst.getContinuousStates(buf, self.nx)
        return np.concatenate([np.array(buf[:]), u])

    def _get_reals(self, vrs, n):
        return self.inst.getFloat64(vrs, n) if self.v3 else self.inst.getReal(vrs)

    def set(self, z: np.ndarray) -> None:
        if self.me:
            self.inst.setContinuousStates((ctypes.c_double * self.nx)(*z[:self.nx]), self.nx)
        u = [float(a) for a in z[self.nx:]]
        vrs = [v.valueReference for v in self.inputs]
        self.inst.setFloat64(vrs, u) if self.v3 else self.inst.setReal(vrs, u)

    def values(self) -> np.ndarray:
        out = []
        if self.me:
            buf = (ctypes.c_double * self.nx)()
            (self.inst.getContinuousStateDerivatives if self.v3 else self.inst.getDerivatives)(buf, self.nx)
            out.append(np.array(buf[:]))
        vrs = [v.valueReference for v in self.outputs]
        out.append(np.array(self._get_reals(vrs, sum(self._size(v) for v in self.outputs))))
        return np.concatenate(out)

    def forward(self, v: np.ndarray) -> np.ndarray:
        self.calls += 1
        u = [w.valueReference for w in self.unknowns]
        if self.v3:
            return np.array(self.inst.getDirectionalDerivative(u, self.known_vrs, list(v), self.n_unknown))
        return np.array(self.inst.getDirectionalDerivative(u, self.known_vrs, list(v)))

    def adjoint(self, w: np.ndarray) -> np.ndarray:
        u = [x.valueReference for x in self.unknowns]
        return np.array(self.inst.getAdjointDerivative(u, self.known_vrs, list(w), sum(self.known_sizes)))

    def close(self) -> None:
        self.inst.terminate()
        self.inst.freeInstance()


KINDS = [(2, "ModelExchange"), (2, "CoSimulation"), (3, "ModelExchange"), (3, "CoSimulation")]


@pytest.fixture(params=KINDS, ids=lambda k: f"fmi{k[0]}-{k[1]}")
def host(request, fmus):
    h = Host(fmus[request.param[0]], request.param[1])
    yield h
    h.close()


def random_points(h: Host, rng) -> list[np.ndarray]:
    z0 = h.point()
    return [z0 + 0.02 * rng.standard_normal(z0.size) for _ in range(POINTS)]


def test_directional_derivatives_equal_central_differences(host):
    """20 random (point, direction) pairs: J v from one fmiXGetDirectionalDerivative equals the
    central difference of the FMU's own values to 1e-7 of |J v|."""
    rng = np.random.default_rng(7)
    worst = 0.0
    for z in random_points(host, rng):
        for _ in range(DIRECTIONS):
            v = rng.standard_normal(z.size)
            host.set(z)
            exact = host.forward(v)
            h = 1e-5
            host.set(z + h * v)
            plus = host.values()
            host.set(z - h * v)
            minus = host.values()
            fd = (plus - minus) / (2 * h)
            err = np.linalg.norm(exact - fd) / np.linalg.norm(exact)
            worst = max(worst, err)
            assert err < 1e-7, err
    print(f"fmi{3 if host.v3 else 2} {'ME' if host.me else 'CS'}: largest |Jv - central difference| / |Jv| = {worst:.1e}")


def _jacobian(host: Host) -> np.ndarray:
    n = sum(host.known_sizes)
    return np.array([host.forward(np.eye(n)[j]) for j in range(n)]).T


@pytest.mark.parametrize("kind", ["ModelExchange", "CoSimulation"])
def test_adjoint_derivatives_equal_the_transposed_forward_ones(kind, fmus):
    """FMI 3.0: the Jacobian read row by row with fmi3GetAdjointDerivative (reverse mode) equals
    the one read column by column with fmi3GetDirectionalDerivative to 1e-12."""
    h = Host(fmus[3], kind)
    try:
        rng = np.random.default_rng(3)
        for z in random_points(h, rng)[:2]:
            h.set(z)
            jac = _jacobian(h)
            rows = np.array([h.adjoint(np.eye(h.n_unknown)[i]) for i in range(h.n_unknown)])
            assert np.max(np.abs(rows - jac)) <= 1e-12 * np.max(np.abs(jac))
            w = rng.standard_normal(h.n_unknown)
            np.testing.assert_allclose(h.adjoint(w), jac.T @ w, rtol=1e-12, atol=1e-12 * np.abs(jac.T @ w).max())
    finally:
        h.close()


def test_a_derivative_call_without_knowns_or_unknowns_is_empty_not_refused(fmus):
    """FMI 3.0 model exchange: an adjoint call with no knowns, and one with no unknowns, answer
    fmi3OK with nothing to fill (the adjoint's NULL check had seeds and sensitivities crossed
    for these two cases and refused them); a forward call likewise."""
    h = Host(fmus[3], "ModelExchange")
    try:
        u = [x.valueReference for x in h.unknowns]
        assert list(h.inst.getAdjointDerivative(u, [], [1.0] * h.n_unknown, 0)) == []
        assert list(h.inst.getAdjointDerivative([], h.known_vrs, [], sum(h.known_sizes))) == [0.0] * sum(h.known_sizes)
        assert list(h.inst.getDirectionalDerivative(u, [], [], h.n_unknown)) == [0.0] * h.n_unknown
    finally:
        h.close()


def _declared_pattern(fmu, host: Host) -> np.ndarray:
    """The FMI 2.0 model description's dependencies as a boolean (unknowns, knowns) matrix."""
    root = ElementTree.fromstring(zipfile.ZipFile(fmu).read("modelDescription.xml"))
    index_of = {str(k + 1): v.valueReference for k, v in enumerate(host.md.modelVariables)}
    rows = {u.valueReference: i for i, u in enumerate(host.unknowns)}
    cols = {vr: j for j, vr in enumerate(host.known_vrs)}
    out = np.zeros((host.n_unknown, len(host.known_vrs)), dtype=bool)
    for tag in ("Outputs", "Derivatives"):
        for u in root.find(f"ModelStructure/{tag}"):
            for d in u.get("dependencies").split():
                out[rows[index_of[u.get("index")]], cols[index_of[d]]] = True
    return out


def test_declared_dependencies_are_exactly_the_jacobians_pattern(fmus):
    """FMI 2.0 model exchange: the union over 5 random points of the non-zero entries of the
    exact Jacobian (states and inputs to derivatives and outputs) is the declared
    ModelStructure (Derivatives and Outputs)."""
    h = Host(fmus[2], "ModelExchange")
    try:
        seen = np.zeros((h.n_unknown, len(h.known_vrs)), dtype=bool)
        for z in random_points(h, np.random.default_rng(11)):
            h.set(z)
            seen |= _jacobian(h) != 0
        declared = _declared_pattern(fmus[2], h)
        assert np.array_equal(seen, declared), (np.argwhere(seen & ~declared)[:5], np.argwhere(declared & ~seen)[:5])
        print(f"{declared.sum()} declared dependencies of {declared.size} ({declared.sum() / declared.size:.0%})")
    finally:
        h.close()


def test_linearize_equals_the_cores_jacobians(fmus):
    """fmu.linearize (A, B, C, D from the FMU's directional derivatives) of both FMUs equals the
    core's: A = mbs.linearize.rhs_jacobian, B, C, D the CasADi Jacobians of rhs and fmu_outputs,
    to 1e-10 of each matrix's largest entry."""
    import casadi as ca

    from fmu.linearize import linearize
    from mbs.linearize import rhs_jacobian

    spec, groups = native_build.native_spec(FAMILY)
    vm, functions = groups[spec["scenes"][SCENE]["group"]]
    x0, p = np.array(vm.info.x0), vm.params()
    inputs = [k for k, q in enumerate(vm.info.parameters) if q["control"]]
    outputs = [v["name"] for v in spec["variables"] if v["causality"] in ("output", "local")]
    pm = ca.MX.sym("p", p.size)
    xm = ca.MX.sym("x", x0.size)
    core = {"A": np.array(rhs_jacobian(vm.functions["rhs"])(x0, 0.0, p)),
            "B": np.array(ca.Function("b", [pm], [ca.jacobian(vm.functions["rhs"](x0, 0.0, pm), pm)])(p))[:, inputs],
            "C": np.array(ca.Function("c", [xm], [ca.jacobian(functions["fmu_outputs"](xm, 0.0, p), xm)])(x0)),
            "D": np.array(ca.Function("d", [pm], [ca.jacobian(functions["fmu_outputs"](x0, 0.0, pm), pm)])(p))[:, inputs]}
    for version in (2, 3):
        lin = linearize(fmus[version], {"scene": SCENE})
        xi = [vm.info.state_names.index(_scalar(n)) for n in lin.states]
        yi = [outputs.index(_scalar(n)) for n in lin.outputs]
        assert lin.inputs == [vm.info.parameters[k]["name"] for k in inputs]
        expect = {"A": core["A"][np.ix_(xi, xi)], "B": core["B"][xi], "C": core["C"][np.ix_(yi, xi)],
                  "D": core["D"][yi]}
        for name, m in expect.items():
            got = getattr(lin, name)
            assert got.shape == m.shape, name
            assert np.max(np.abs(got - m)) <= 1e-10 * np.max(np.abs(m)), (version, name)
        assert lin.calls == len(lin.states) + len(lin.inputs)


def _scalar(name: str) -> str:
    """The FMI 2.0 name of an FMI 3.0 array element: ``blade.flap[2]`` -> ``blade2.flap``."""
    if not name.endswith("]"):
        return name
    base, k = name[:-1].split("[")
    part, rest = base.split(".", 1)
    return f"{part}{k}.{rest}"


CASADI_HOST = r'''
import json, sys, tempfile, zipfile
import casadi as ca, numpy as np
fmu, point = sys.argv[1], json.loads(sys.argv[2])
folder = tempfile.mkdtemp()
zipfile.ZipFile(fmu).extractall(folder)
dae = ca.DaeBuilder("heli", folder, {"debug": True})
x, u = [point[n] for n in dae.x()], [point[n] for n in dae.u()]
f = dae.create("f", ["x", "u"], ["ode", "y"], {"uses_directional_derivatives": True})
out = f(x, u)
jac = f.jacobian()(x, u, out[0], out[1])
sys.stdout.flush()
print("JSON " + json.dumps({"states": dae.x(), "outputs": dae.y(), "inputs": dae.u(),
                            "jac": [np.array(j).tolist() for j in jac]}), flush=True)
'''


def test_casadi_fmu_import_uses_the_derivatives_and_its_jacobian_equals_ours(fmus, tmp_path):
    """CasADi's FMU import (DaeBuilder) loads the FMI 2.0 ME FMU as a function (x, u) -> (x', y):
    its Jacobian comes from the FMU's fmi2GetDirectionalDerivative (the FMU logs each call: at
    most one per state and input, asking only for the declared dependencies) and equals
    fmu.linearize's."""
    from fmu.linearize import linearize

    lin = linearize(fmus[2], {"scene": SCENE})
    point = {**dict(zip(lin.states, lin.x.tolist())), **dict(zip(lin.inputs, lin.u.tolist()))}
    proc = subprocess.run([sys.executable, "-c", CASADI_HOST, str(fmus[2]), json.dumps(point)], capture_output=True, text=True, cwd=tmp_path,
                          timeout=600)
    assert proc.returncode == 0, proc.stderr[-3000:]
    res = json.loads(proc.stdout.split("JSON ", 1)[1])
    calls = [line for line in proc.stdout.splitlines() if "fmi2GetDirectionalDerivative: call" in line]
    # one call per group of structurally independent columns (CasADi colours the declared pattern)
    assert 0 < len(calls) <= len(lin.states) + len(lin.inputs), calls[-3:]
    assert f"{len(calls)} directional and 0 adjoint derivative calls answered" in proc.stdout
    assert sorted(res["states"]) == sorted(lin.states) and res["inputs"] == lin.inputs
    xi, yi = [lin.states.index(n) for n in res["states"]], [lin.outputs.index(n) for n in res["outputs"]]
    ours = (lin.A[np.ix_(xi, xi)], lin.B[xi], lin.C[np.ix_(yi, xi)], lin.D[yi])  # in CasADi's order
    for got, want in zip(res["jac"], ours):
        np.testing.assert_allclose(np.array(got).reshape(want.shape), want, rtol=1e-12, atol=1e-12 * np.abs(want).max())
    print(f"CasADi's FMU import: {len(calls)} fmi2GetDirectionalDerivative calls for its Jacobian")


def test_heli_fmu_linearize_command(fmus, tmp_path):
    """``heli fmu linearize``: the matrices of fmu.linearize as JSON and in a .mat file; a bad
    start value or an unknown name is a one-line error naming it."""
    from scipy.io import loadmat

    from fmu.linearize import linearize

    heli = [sys.executable, "-m", "mbs"]
    out = tmp_path / "lin.mat"
    proc = subprocess.run([*heli, "fmu", "linearize", str(fmus[3]), "--set", "scene=hover", "--out", str(out), "--json"],
                          capture_output=True, text=True, timeout=600)
    assert proc.returncode == 0, proc.stderr[-2000:]
    res, lin = json.loads(proc.stdout), linearize(fmus[3], {"scene": "hover"})
    assert res["states"] == lin.states and np.array_equal(np.array(res["A"]), lin.A)
    assert np.array_equal(loadmat(out)["D"], lin.D)
    for setting, words in (("scene=nope", "'scene' = 'nope' is not one of"), ("bogus=1", "'bogus' is not a parameter")):
        bad = subprocess.run([*heli, "fmu", "linearize", str(fmus[2]), "--set", setting], capture_output=True,
                             text=True, timeout=600)
        assert bad.returncode != 0 and words in bad.stderr.strip().splitlines()[-1], bad.stderr[-500:]


def _structure(fmu, v3: bool) -> tuple[dict, dict]:
    """(unknown -> set of known names) of Outputs and state derivatives, and name -> FMI 3.0 array
    name (FMI 2.0: identity) from a model description."""
    root = ElementTree.fromstring(zipfile.ZipFile(fmu).read("modelDescription.xml"))
    svs = list(root.find("ModelVariables"))
    names = [sv.get("name") for sv in svs]
    if v3:
        by_vr = {sv.get("valueReference"): sv.get("name") for sv in svs}
        tags, key, ref = ("Output", "ContinuousStateDerivative"), "valueReference", by_vr.__getitem__
    else:
        tags, key, ref = ("Outputs/Unknown", "Derivatives/Unknown"), "index", lambda i: names[int(i) - 1]
    return {ref(u.get(key)): {ref(d) for d in u.get("dependencies").split()}
            for tag in tags for u in root.find("ModelStructure").findall(tag)}


def test_fmi3_dependencies_are_the_fmi2_ones_over_arrays(fmus):
    """Every FMI 3.0 output and state derivative depends on exactly the (array) variables that hold
    the FMI 2.0 dependencies of its elements."""
    from fmu.native.fmi3 import ELEMENT

    def array(name: str) -> str:
        m = ELEMENT.match(name)
        return f"{'der(' if m[1] else ''}{m[2]}.{m[4]}{')' if m[1] else ''}" if m else name

    two, three = _structure(fmus[2], False), _structure(fmus[3], True)
    root = ElementTree.fromstring(zipfile.ZipFile(fmus[3]).read("modelDescription.xml"))
    names3 = {v.get("name") for v in root.find("ModelVariables")}
    to3 = lambda n: array(n) if array(n) in names3 else n  # noqa: E731
    merged: dict = {}
    for name, deps in two.items():
        merged.setdefault(to3(name), set()).update(map(to3, deps))
    assert set(merged) == set(three)
    assert all(merged[n] == three[n] for n in three), [n for n in three if merged[n] != three[n]][:3]


def test_heli_bench_fmu_me_reports_exact_and_differenced_jacobians(fmus):
    """``heli bench fmu-me --json`` (a short run): the exact Jacobian repeats to the bit, central
    differences are closer to it than forward ones, and both runs reach the end."""
    proc = subprocess.run([sys.executable, "-m", "mbs", "bench", "fmu-me", "--revs", "0.2", "--repeats", "1", "--json"],
                          capture_output=True, text=True, timeout=900)
    assert proc.returncode == 0, proc.stderr[-2000:]
    res = json.loads(proc.stdout)
    j, s = res["jacobian"], res["simulation"]
    assert j["shape"] == [131, 39] and j["repeat_error"] == 0.0  # 131: the model's outputs with its 2 stall shares
    assert 0 < j["central_error"] < j["forward_error"] < 1e-6
    assert s["cvode_steps"] > 0 and s["cs_steps"] == 20 and s["largest_flap_difference_rad"] < 1e-6
