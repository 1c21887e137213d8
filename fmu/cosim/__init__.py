"""The closed-loop co-simulation: the helicopter FMU (native, scene hover from its periodic trim)
and the hover-hold controller FMU (:mod:`fmu.controller`) in one SSP file, run by two masters:

- :func:`run_libcosim`: OSP libcosim (``libcosimpy``) loads the ``.ssp`` itself (connections,
  start values) and runs its fixed-step algorithm;
- :func:`run_fmpy`: our master loop over fmpy's ``FMU2Slave``, with the system read from the
  same ``.ssp`` by fmpy's SSP reader. It does what libcosim does: time in whole nanoseconds
  (``t_k = k·h_ns / 1e9``, each step ``t_{k+1} − t_k``), connections transferred once during
  initialisation, then every step: both FMUs step, then every output goes to its input.

The disturbance: ``initial_forward_speed`` = 1 m/s at the hover trim (the aircraft moving 1 m/s
relative to still air, as after a 1 m/s gust step). ``gain_scale = 0`` runs the same system
open loop.

The SSD gives every start value a run needs as SSP 1.0 parameter bindings (inline parameter
sets): the helicopter's scene, start and disturbance, and its four pitch inputs at the hover trim
(SSP 1.0 binds start values of inputs too; its connectors carry no start value), so a master
that applies the bindings starts at the trim before any value is transferred.
:mod:`fmu.cosim.fmpy_ssp` runs fmpy's own SSP runner on it, which cannot run it (see there why).

This package: the masters and ``heli cosim`` here; :mod:`fmu.cosim.ssp` writes the SSP file (SSD
and FMUs); :mod:`fmu.cosim.fmpy_ssp` is the fmpy SSP runner's fresh-process attempt.
"""
from __future__ import annotations

import tempfile
import time
import zipfile
from pathlib import Path

import numpy as np

from fmu import controller
from mbs import atomic

HELI, CTRL = "helicopter", "controller"
RECORDED = list(controller.INPUTS)
VIEWER_REVS = 20  # revolutions shown by the viewer page: the first 2.8 s, the response to the disturbance


def system(heli_fmu: Path, ctrl_fmu: Path, closed: bool = True, speed: float = 1.0) -> dict:
    """Components and connections of the hover-hold system (see :func:`fmu.cosim.ssp.write_ssp`)."""
    trim = controller.read_design(ctrl_fmu)["trim_controls"]
    heli = {"path": heli_fmu, "fmu": heli_fmu.name, "inputs": list(controller.OUTPUTS), "outputs": RECORDED,
            "parameters": {"scene": controller.SCENE, "initial_state": "periodic", "initial_forward_speed": speed,
                           **{c: float(trim[c]) for c in controller.OUTPUTS}}}
    ctrl = {"path": ctrl_fmu, "fmu": ctrl_fmu.name, "inputs": RECORDED, "outputs": list(controller.OUTPUTS),
            "parameters": {"gain_scale": 1.0 if closed else 0.0}}
    wires = [(HELI, n, CTRL, n) for n in RECORDED] + [(CTRL, n, HELI, n) for n in controller.OUTPUTS]
    return {"components": {HELI: heli, CTRL: ctrl}, "connections": wires}


def write(dest: Path, heli_fmu: Path, ctrl_fmu: Path, stop: float, closed: bool = True, speed: float = 1.0) -> Path:
    from fmu.cosim import ssp

    s = system(heli_fmu, ctrl_fmu, closed, speed)
    return ssp.write_ssp(dest, "hover-hold" if closed else "hover-open-loop", s["components"], s["connections"], stop)


# -- libcosim --------------------------------------------------------------------------------------

def run_libcosim(ssp_file: Path, stop: float, step: float, record: bool = True) -> dict:
    """The ``.ssp`` in libcosim with a fixed step ``step`` (s, a whole number of ns) until
    ``stop``: the recorded helicopter outputs and controls after every step (``record``), the
    wall time of the run and libcosim's messages."""
    from libcosimpy.CosimExecution import CosimExecution
    from libcosimpy.CosimLogging import CosimLogLevel, log_output_level
    from libcosimpy.CosimObserver import CosimObserver

    log_output_level(CosimLogLevel.WARNING)  # what libcosim warns about (an ignored variable, ...) is shown
    step_ns, n = round(step * 1e9), round(stop / step)
    ex = CosimExecution.from_ssp_file(str(ssp_file), step_size=step_ns)
    slaves = {info.name.decode(): info.index for info in ex.slave_infos()}
    vr = {s: {v.name.decode(): v.reference for v in ex.slave_variables(i)} for s, i in slaves.items()}
    observer = CosimObserver.create_last_value()
    ex.add_observer(observer)
    rows = []
    start = time.perf_counter()
    if not record:
        ok = ex.simulate_until(target_time=n * step_ns)
        return {"wall_s": time.perf_counter() - start, "ok": bool(ok), "steps": n}
    for k in range(n):
        if not ex.step():
            raise RuntimeError(f"libcosim step {k} failed")
        heli = observer.last_real_values(slaves[HELI], [vr[HELI][m] for m in RECORDED])
        ctrl = observer.last_real_values(slaves[CTRL], [vr[CTRL][m] for m in controller.OUTPUTS])
        rows.append([(k + 1) * step_ns / 1e9, *heli, *ctrl])
    return {**_table(rows), "wall_s": time.perf_counter() - start}


def _table(rows: list) -> dict:
    a = np.array(rows)
    return {"time": a[:, 0], **{n: a[:, j + 1] for j, n in enumerate(RECORDED + list(controller.OUTPUTS))}}


# -- fmpy --------------------------------------------------------------------------------------------

class _Slave:
    """One component of the SSP under fmpy: its FMU2Slave, value references, the parameters."""

    def __init__(self, component, unzipped: Path, instance: str):
        from fmpy import extract, read_model_description
        from fmpy.fmi2 import FMU2Slave

        path = str(unzipped / component.source)
        md = read_model_description(path)
        self.vr = {v.name: v.valueReference for v in md.modelVariables}
        self.fmu = FMU2Slave(guid=md.guid, unzipDirectory=extract(path), modelIdentifier=md.coSimulation.modelIdentifier,
                             instanceName=instance)
        params = [p for b in component.parameterBindings for ps in b.parameterValues or [] for p in ps.parameters]
        self.parameters = {p.name: p.value for p in params}
        self.kinds = {p.name: p.type for p in params}

    def start(self) -> None:
        self.fmu.instantiate()
        self.fmu.setupExperiment(startTime=0.0)
        self.fmu.enterInitializationMode()
        for name, value in self.parameters.items():
            if self.kinds[name] == "String":
                self.fmu.setString([self.vr[name]], [value])
            else:
                self.fmu.setReal([self.vr[name]], [float(value)])


def _read(ssp_file: Path, unzipped: Path) -> tuple[dict, list]:
    """Components (as :class:`_Slave`) and connections of the ``.ssp`` (fmpy's SSP reader)."""
    from fmpy.ssp.ssd import read_ssd

    ssd = read_ssd(str(ssp_file))
    with zipfile.ZipFile(ssp_file) as z:
        z.extractall(unzipped)
    slaves = {c.name: _Slave(c, unzipped, c.name) for c in ssd.system.elements}
    wires = [(c.startElement, c.startConnector, c.endElement, c.endConnector) for c in ssd.system.connections]
    return slaves, wires


def run_fmpy(ssp_file: Path, stop: float, step: float, workdir: Path, states: list[str] | None = None) -> dict:
    """The ``.ssp`` in our master loop over fmpy (libcosim's sequence, see the module docstring):
    recorded outputs after every step, wall time, and the time spent in the helicopter's
    ``fmi2DoStep`` (s); with ``states`` (names of the helicopter's variables), also those after
    every step, as ``states`` (n + 1, len(states)) from the start, for the viewer."""
    slaves, wires = _read(ssp_file, workdir)
    step_ns, n = round(step * 1e9), round(stop / step)
    for s in slaves.values():
        s.start()
    transfer = _transfer(slaves, wires)
    transfer()  # initial values, in initialisation mode (as libcosim does)
    for s in slaves.values():
        s.fmu.exitInitializationMode()
    heli, ctrl = slaves[HELI], slaves[CTRL]
    out_h, out_c = [heli.vr[m] for m in RECORDED], [ctrl.vr[m] for m in controller.OUTPUTS]
    rows, in_heli, kept = [], 0.0, []
    state_vrs = [heli.vr[m] for m in states or []]
    if states:
        kept.append(heli.fmu.getReal(state_vrs))
    start = time.perf_counter()
    for k in range(n):
        t0, t1 = k * step_ns / 1e9, (k + 1) * step_ns / 1e9
        tick = time.perf_counter()
        heli.fmu.doStep(currentCommunicationPoint=t0, communicationStepSize=t1 - t0)
        in_heli += time.perf_counter() - tick
        ctrl.fmu.doStep(currentCommunicationPoint=t0, communicationStepSize=t1 - t0)
        transfer()
        rows.append([t1, *heli.fmu.getReal(out_h), *ctrl.fmu.getReal(out_c)])
        if states:
            kept.append(heli.fmu.getReal(state_vrs))
    wall = time.perf_counter() - start
    for s in slaves.values():
        s.fmu.terminate()
        s.fmu.freeInstance()
    extra = {"states": np.array(kept), "state_names": list(states)} if states else {}
    return {**_table(rows), "wall_s": wall, "helicopter_dostep_s": in_heli, **extra}


def viewer_page(res: dict, path: Path, scene: str = controller.SCENE, aircraft=None) -> Path | None:
    """``viewer.html``: the first VIEWER_REVS revolutions of the closed loop in the browser viewer (the helicopter's states from
    the fmpy run, the pitch inputs row by row); None without the viewer package."""
    try:
        from viewer import export_html
        from viewer.motion import Recording
    except ImportError:
        return None
    from mbs import scenes

    sc = scenes.get(scene, aircraft)
    system = sc.system("vm")
    cols = dict(zip(res["state_names"], res["states"].T))
    x = np.column_stack([cols[n] for n in system.info.state_names])
    t = np.r_[0.0, res["time"]]
    controls = {c: np.r_[res[c][0], res[c]] for c in controller.OUTPUTS}  # held over the step that follows
    p = system.params()
    rows = np.array([system.params(p, **{c: float(v[i]) for c, v in controls.items()}) for i in range(len(t))])
    rec = Recording(system, t, x, p, f"{scene}, closed loop (HoverHold FMU)", sc.revolution(system, p), rows)
    return export_html(rec, path, revs=VIEWER_REVS, start=0.0, slow=5.0).path


def _state_names(heli_fmu: Path) -> list[str]:
    """The helicopter FMU's outputs and locals (every state among them)."""
    from fmpy import read_model_description

    return [v.name for v in read_model_description(str(heli_fmu)).modelVariables if v.causality in ("output", "local")]


def _transfer(slaves: dict, wires: list):
    """A function that copies every connected output to its input (one getReal, one setReal
    per component)."""
    plan = {}
    for a, out, b, inp in wires:
        plan.setdefault((a, b), []).append((slaves[a].vr[out], slaves[b].vr[inp]))

    def transfer() -> None:
        for (a, b), pairs in plan.items():
            values = slaves[a].fmu.getReal([p[0] for p in pairs])
            slaves[b].fmu.setReal([p[1] for p in pairs], values)

    return transfer


# -- algebraic loops ----------------------------------------------------------------------------------

def algebraic_loops(ssp_file: Path, declared: bool = True) -> list[list[str]]:
    """The algebraic loops of the ``.ssp`` system as a master finds them: cycles of connections
    and direct feedthrough (an output to the inputs its ``ModelStructure`` says it depends on;
    with ``declared = False``, or where an FMU declares nothing, to every input, as a tool must
    then assume). Each loop as its ``component.variable`` names."""
    from fmpy import read_model_description
    from fmpy.ssp.ssd import read_ssd

    ssd = read_ssd(str(ssp_file))
    edges: dict[str, set[str]] = {}
    with zipfile.ZipFile(ssp_file) as z:
        for c in ssd.system.elements:
            md = read_model_description(z.open(c.source))
            inputs = [v.name for v in md.modelVariables if v.causality == "input"]
            for u in md.outputs:
                # direct feedthrough is on inputs only (model exchange also lists the continuous states)
                deps = inputs if not declared or u.dependencies is None else \
                    [d.name for d in u.dependencies if d.name in inputs]
                for d in deps:
                    edges.setdefault(f"{c.name}.{d}", set()).add(f"{c.name}.{u.variable.name}")
    for con in ssd.system.connections:
        edges.setdefault(f"{con.startElement}.{con.startConnector}", set()).add(f"{con.endElement}.{con.endConnector}")
    return _cycles(edges)


def _cycles(edges: dict[str, set[str]]) -> list[list[str]]:
    """One cycle through each strongly connected part of the directed graph ``edges`` that has one."""
    loops, done = [], set()
    for root in sorted(edges):
        stack, path, on_path = [(root, iter(sorted(edges.get(root, ()))))], [root], {root}
        while stack:
            node, children = stack[-1]
            child = next(children, None)
            if child is None:
                stack.pop(), on_path.discard(path.pop()), done.add(node)
            elif child in on_path:
                loop = path[path.index(child):]
                if not any(set(loop) == set(seen) for seen in loops):
                    loops.append(loop)
            elif child not in done:
                stack.append((child, iter(sorted(edges.get(child, ())))))
                path.append(child), on_path.add(child)
    return loops


# -- figures of merit --------------------------------------------------------------------------------

def excursions(res: dict, trim: dict) -> dict:
    """Largest attitude deviation from the trim (deg, roll and pitch) and horizontal/vertical
    distance from the start (m) over the run, and the first times (s) beyond 2°, 5 m and 20°."""
    att = np.degrees(np.hypot(res["fuselage.roll"] - trim["fuselage.roll"], res["fuselage.pitch"] - trim["fuselage.pitch"]))
    drift = np.sqrt(sum((res[f"fuselage.{c}"] - trim[f"fuselage.{c}"]) ** 2 for c in "xyz"))

    def first(mask) -> float | None:
        idx = np.flatnonzero(mask)
        return float(res["time"][idx[0]]) if idx.size else None

    return {"max_attitude_deg": float(att.max()), "max_drift_m": float(drift.max()),
            "attitude_beyond_2deg_s": first(att > 2.0), "drift_beyond_5m_s": first(drift > 5.0),
            "attitude_beyond_20deg_s": first(att > 20.0), "final_drift_m": float(drift[-1]),
            "attitude_within_2deg_after_s": float(res["time"][np.flatnonzero(att > 2.0)[-1]]) if (att > 2.0).any()
            else 0.0}


def max_difference(a: dict, b: dict) -> float:
    """Largest absolute difference between two runs over every recorded variable."""
    names = RECORDED + list(controller.OUTPUTS)
    return max(float(np.max(np.abs(np.asarray(a[m]) - np.asarray(b[m])))) for m in names)


def plot(closed: dict, open_: dict, trim: dict, path: Path, aircraft: str = "Bo105") -> Path:
    """Attitude, position and controls of the closed and open loop against time; the attitude
    and position axes fit the run, up to ±25 deg and ±60 m (beyond, the open loop's divergence
    would flatten the closed loop)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, axes = plt.subplots(3, 1, figsize=(9, 9), sharex=True)
    for res, style, label in ((closed, "-", "closed loop"), (open_, "--", "open loop")):
        t = res["time"]
        for c in ("roll", "pitch"):
            axes[0].plot(t, np.degrees(res[f"fuselage.{c}"] - trim[f"fuselage.{c}"]), style, label=f"{c}, {label}")
        for c, name in zip("xyz", ("north", "east", "down")):
            axes[1].plot(t, res[f"fuselage.{c}"] - trim[f"fuselage.{c}"], style, label=f"{name}, {label}")
        if res is closed:
            for c in controller.OUTPUTS:
                axes[2].plot(t, np.degrees(res[c]), label=c)
    axes[0].set_ylabel("attitude − trim (deg)")
    axes[1].set_ylabel("position − start (m)")
    axes[2].set_ylabel("pitch inputs, closed loop (deg)")
    axes[2].set_xlabel("time (s)")
    for ax in axes:
        ax.grid(True, alpha=0.3)
        ax.legend(fontsize=7, ncol=3)
    for ax, most in ((axes[0], 25.0), (axes[1], 60.0)):
        low, high = ax.get_ylim()
        ax.set_ylim(max(low, -most), min(high, most))
    fig.suptitle(f"{aircraft} hover after a 1 m/s disturbance: helicopter FMU + hover-hold controller FMU (libcosim)")
    fig.tight_layout()
    atomic.savefig(fig, path, dpi=110)
    plt.close(fig)
    return path


def run(out: Path, stop: float = 60.0, log=None, aircraft=None) -> dict:
    """``heli cosim``: build both FMUs, write the closed- and open-loop ``.ssp``, run the closed
    loop in libcosim and in the fmpy loop, the open loop in libcosim; compare, plot, write CSV."""
    from fmu import build as pybuild
    from fmu.cosim import fmpy_ssp
    from fmu.native.build import ensure_native_fmu

    out.mkdir(parents=True, exist_ok=True)
    craft = pybuild.load_aircraft(aircraft)
    heli, _ = ensure_native_fmu(pybuild.DEFAULT_SCENES, log=log, aircraft=craft)
    ctrl, _ = controller.ensure_controller_fmu(log=log, aircraft=craft)
    dsg = controller.read_design(ctrl)
    step = controller.default_step(aircraft=craft)
    closed_ssp = write(out / "hover_hold.ssp", heli, ctrl, stop, closed=True)
    open_ssp = write(out / "hover_open_loop.ssp", heli, ctrl, stop, closed=False)
    loops = algebraic_loops(closed_ssp)
    closed = run_libcosim(closed_ssp, stop, step)
    with tempfile.TemporaryDirectory(prefix="heli-cosim-fmpy-") as tmp:
        via_fmpy = run_fmpy(closed_ssp, stop, step, Path(tmp), _state_names(heli))
    open_ = run_libcosim(open_ssp, stop, step)
    fmpy_runner = fmpy_ssp.run(closed_ssp, stop, step)
    trim = dsg["trim_inputs"]
    figure = plot(closed, open_, trim, out / "hover_hold.png", craft.name)
    page = viewer_page(via_fmpy, out / "viewer.html", aircraft=craft)
    csv = out / "hover_hold.csv"
    names = ["time", *RECORDED, *controller.OUTPUTS]
    atomic.write(csv, lambda tmp: np.savetxt(tmp, np.column_stack([closed[m] for m in names]), delimiter=",",
                                             header=",".join(names), comments="", fmt="%.12g"))
    return {"stop_s": stop, "step_s": step, "steps": len(closed["time"]), "closed": excursions(closed, trim),
            "open": excursions(open_, trim), "libcosim_vs_fmpy_max_abs": max_difference(closed, via_fmpy),
            "algebraic_loops": loops, "algebraic_loops_without_dependencies": len(algebraic_loops(closed_ssp, False)),
            "libcosim_wall_s": closed["wall_s"], "fmpy_wall_s": via_fmpy["wall_s"], "fmpy_ssp_runner": fmpy_runner,
            "closed_loop_eigenvalues": dsg["closed_loop"], "open_loop_eigenvalues": dsg["open_loop"],
            "files": {"ssp": str(closed_ssp), "ssp_open": str(open_ssp), "figure": str(figure), "csv": str(csv),
                      **({"viewer": str(page)} if page else {})},
            "helicopter_fmu": str(heli), "controller_fmu": str(ctrl)}


def bench(stop: float = 60.0, repeats: int = 3) -> dict:
    """Wall time of the closed loop for ``stop`` s: libcosim's own loop (``simulate_until``, no
    recording) and the fmpy loop (recording), medians of ``repeats``; the share of the fmpy
    loop spent in the helicopter's ``fmi2DoStep``."""
    import tempfile

    from fmu import build as pybuild
    from fmu.native.build import ensure_native_fmu

    heli, _ = ensure_native_fmu(pybuild.DEFAULT_SCENES)
    ctrl, _ = controller.ensure_controller_fmu()
    step = controller.default_step()
    with tempfile.TemporaryDirectory(prefix="heli-cosim-bench-") as tmp:
        ssp_file = write(Path(tmp) / "hover_hold.ssp", heli, ctrl, stop)
        lib = [run_libcosim(ssp_file, stop, step, record=False)["wall_s"] for _ in range(repeats)]
        runs = [run_fmpy(ssp_file, stop, step, Path(tmp) / f"fmpy{k}") for k in range(repeats)]
    fm = sorted(runs, key=lambda r: r["wall_s"])[len(runs) // 2]
    lib_s = float(np.median(lib))
    return {"stop_s": stop, "step_s": step, "repeats": repeats, "libcosim_wall_s": lib_s,
            "libcosim_realtime_factor": stop / lib_s, "fmpy_wall_s": fm["wall_s"],
            "fmpy_realtime_factor": stop / fm["wall_s"], "helicopter_dostep_s": fm["helicopter_dostep_s"],
            "helicopter_share_fmpy": fm["helicopter_dostep_s"] / fm["wall_s"],
            "helicopter_share_libcosim": min(1.0, fm["helicopter_dostep_s"] / lib_s)}
