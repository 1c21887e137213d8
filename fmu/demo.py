"""``heli demo``: the main job.

Builds the FMU of the Bo105 or another aircraft (or takes it from the cache), starts the
``forward-flight`` scene from
its periodic trim (``initial_state = "periodic"``: controls, attitude and rotor states of
:mod:`fmu.periodic`, so that no start-up transient hides the response), runs it through fmpy
for a few revolutions with a pitch-input schedule on the trim's inputs (a collective step and
a longitudinal cyclic doublet) and writes, into one folder:

- ``results.csv``: time (s), every state by name, the model outputs, the fuselage Euler
  angles, the total energy and the pitch inputs, all as recorded from the FMU;
- ``run.json``: scene, start, trim (with its provenance), FMU, communication step, schedule,
  timings, final parameters (so that the folder can be reopened, e.g. by the viewer);
- ``hinge_angles.png``: the pitch inputs and the hinge angles against time (s and revolutions);
- the ``.fmu`` that ran (a copy of the cached one), for other importers;
- ``viewer.html``: the browser animation (when the ``viewer`` package is present);
- ``fly.html``: the scene to fly in the browser (``heli fly``: the model as WebAssembly, starting
  from the periodic trims at :data:`FLY_SPEEDS` and the scene's own; without the hover-hold
  controller, whose design would double the demo's first run: ``heli fly`` adds it).
"""
from __future__ import annotations

import json
import shutil
import time
import zipfile
from pathlib import Path

import numpy as np

from fmu import build, hosts

SCENE = "forward-flight"
START = "periodic"
FLY_SPEEDS = (0.0, 20.0, 40.0)  # m/s: the trims fly.html starts from, besides the scene's own


def fmu_facts(path: Path) -> dict:
    """Inputs (name -> start value), recorded variables and the default experiment."""
    from fmpy import read_model_description

    md = read_model_description(str(path))
    inputs = {v.name: float(v.start) for v in md.modelVariables if v.causality == "input"}
    recorded = [v.name for v in md.modelVariables if v.causality in ("output", "local")]
    return {"inputs": inputs, "recorded": recorded, "step": float(md.defaultExperiment.stepSize)}


def run(out: Path, revs: float = 10.0, log=print, aircraft=None) -> dict:
    """Build (cached), run through fmpy and write the files; returns a summary. ``aircraft``:
    an :class:`mbs.aircraft.Aircraft`, a packaged name or a file (default the Bo105)."""
    from mbs import scenes
    from mbs.simulate import run_record

    start = time.perf_counter()
    craft = build.load_aircraft(aircraft)
    path, build_s = build.ensure_fmu(build.DEFAULT_SCENES, log=log, aircraft=craft)
    facts, spec = fmu_facts(path), fmu_spec(path)
    trim = spec["scenes"][SCENE]["periodic"]
    dt, steps_per_rev = facts["step"], 100
    table = hosts.pitch_schedule({n: trim["defaults"][n] for n in facts["inputs"]}, dt, steps_per_rev)
    stop = round(revs * steps_per_rev) * dt
    names = facts["recorded"] + list(facts["inputs"])
    t0 = time.perf_counter()
    res = hosts.run_fmpy(path, stop, dt, table, {"scene": SCENE, "initial_state": START}, names)
    run_s = time.perf_counter() - t0
    from mbs import atomic
    from mbs.results import RESULTS_DIGEST

    files = {"results": out / "results.csv", "hinge_angles": out / "hinge_angles.png", "fmu": out / path.name}
    summary = {**run_record(scenes.get(SCENE, aircraft=craft)), "initial_state": START, "trim": trim["trim"],
               "fmu": str(files["fmu"]),
               "fmu_cached": str(path), "revs": revs, "communication_step_s": dt,
               "simulated_s": stop, "build_s": build_s, "fmpy_wall_s": run_s,
               "realtime_factor": stop / run_s, "importer": "fmpy.simulate_fmu",
               "schedule": hosts.table_rows(table), "inputs_seen": _inputs_seen(table, stop),
               "parameters": {**_fmu_parameters(path), **{n: float(res[n][-1]) for n in facts["inputs"]}}}
    summary["files"] = {**{k: str(v) for k, v in files.items()}, "run": str(out / "run.json")}
    with atomic.Files() as written:  # renamed together: the folder never mixes two runs
        _write_csv(res, written.temporary(files["results"]))
        summary[RESULTS_DIGEST] = atomic.sha256(written.pending[0][0])
        hinge_plot(res, table, dt * steps_per_rev, spec, written.temporary(files["hinge_angles"]),
                   f"{SCENE} of the {craft.name} at {trim['trim']['speed']:g} m/s")
        shutil.copyfile(path, written.temporary(files["fmu"]))
        written.temporary(out / "run.json").write_text(json.dumps(summary, indent=1))
    viewer = _viewer(out)
    if viewer:
        summary["files"]["viewer"] = str(viewer)
    fly = _fly(out, craft, log)
    if fly:
        summary["files"]["fly"] = str(fly)
    summary["total_s"] = time.perf_counter() - start
    atomic.write_text(out / "run.json", json.dumps(summary, indent=1))
    return summary


def _fmu_parameters(path: Path) -> dict:
    from fmpy import read_model_description

    md = read_model_description(str(path))
    return {v.name: float(v.start) for v in md.modelVariables
            if v.causality == "parameter" and v.type == "Real" and v.name not in ("max_step", "initial_forward_speed")}


def _write_csv(res: np.ndarray, path: Path) -> Path:
    names = list(res.dtype.names)
    np.savetxt(path, np.column_stack([res[n] for n in names]), delimiter=",", header=",".join(names),
               comments="", fmt="%.17g")
    return path


def hinge_plot(res: np.ndarray, table: np.ndarray, revolution: float, spec: dict, path: Path,
               what: str = SCENE) -> Path:
    """The pitch inputs (collectives, cyclics) and the scene's hinge-angle panels against time
    (s and revolutions), in degrees; dotted lines at the input switches of ``table`` within the
    run; the title names ``what`` (scene, aircraft, speed) and the inputs that happen in the run."""
    from mbs import plots

    inputs = list(table.dtype.names[1:])
    panels = {"collective pitch (rad)": [n for n in inputs if "cyclic" not in n],
              "cyclic pitch (rad)": [n for n in inputs if "cyclic" in n], **spec["scenes"][SCENE]["plots"]}
    end = res["time"][-1]
    events = sorted({float(t) for t in table["time"][1:] if t < end})
    return plots.time_panels(res["time"], revolution, res, panels, path,
                             f"{what} through the FMU (fmpy) from its periodic trim: {_inputs_seen(table, end)}",
                             events)


def _inputs_seen(table: np.ndarray, end: float) -> str:
    """The pitch inputs of ``table`` that change before ``end`` (s), as a title says them."""
    said = []
    for n in table.dtype.names[1:]:
        times = table["time"][1:][np.diff(table[n]) != 0]
        if times.size and times[0] < end:
            what = "collective step" if n == "collective" else f"{n.replace('_', '-')} doublet"
            said.append(what + (" (its start: the run ends before the rest)" if times[-1] >= end else ""))
    return " and ".join(said) or "trim inputs held (the run ends before the first input)"


def fmu_spec(fmu: Path) -> dict:
    """The build's ``spec.json`` inside the pythonfmu FMU ``fmu`` (variables, scenes, starts)."""
    with zipfile.ZipFile(fmu) as z:
        return json.loads(z.read("resources/heli_models/spec.json"))


def _viewer(out: Path) -> Path | None:
    """``viewer.export_html(out, out / "viewer.html")`` if the viewer package exists."""
    try:
        from viewer import export_html
    except ImportError:
        print("note: the viewer package is not available; viewer.html not written")
        return None
    return export_html(out, out / "viewer.html", revs=None).path  # the whole run (thinned to fit 5 MB)


def _fly(out: Path, aircraft, log) -> Path | None:
    """``fly.html`` of the demo's scene (:func:`viewer.fly.write_page`) if the viewer package exists."""
    try:
        from viewer.fly import write_page
    except ImportError:
        print("note: the viewer package is not available; fly.html not written")
        return None
    return write_page(SCENE, out / "fly.html", aircraft, FLY_SPEEDS, log=log, controller=False).path
