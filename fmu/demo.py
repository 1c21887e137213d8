"""``heli demo``: the main job.

Builds the Bo105 FMU (or takes it from the cache), runs the ``forward-flight`` scene through
fmpy for a few revolutions with a pitch-input schedule (a collective step and a longitudinal
cyclic doublet) and writes, into one folder:

- ``results.csv``: time (s), every state by name, the model outputs, the fuselage Euler
  angles, the total energy and the pitch inputs, all as recorded from the FMU;
- ``run.json``: scene, FMU, communication step, schedule, timings, final parameters (so
  that the folder can be reopened, e.g. by the viewer);
- ``hinge_angles.png``: the pitch inputs and the hinge angles over revolutions;
- ``viewer.html``: the animated last revolution (when the ``viewer`` package is present).
"""
from __future__ import annotations

import json
import time
from pathlib import Path

import numpy as np

from fmu import build, hosts

SCENE = "forward-flight"


def fmu_facts(path: Path) -> dict:
    """Inputs (name -> start value), recorded variables and the default experiment."""
    from fmpy import read_model_description

    md = read_model_description(str(path))
    inputs = {v.name: float(v.start) for v in md.modelVariables if v.causality == "input"}
    recorded = [v.name for v in md.modelVariables if v.causality in ("output", "local")]
    return {"inputs": inputs, "recorded": recorded, "step": float(md.defaultExperiment.stepSize)}


def run(out: Path, revs: float = 10.0, log=print) -> dict:
    """Build (cached), run through fmpy and write the files; returns a summary."""
    start = time.perf_counter()
    path, build_s = build.ensure_fmu(build.DEFAULT_SCENES, log=log)
    facts = fmu_facts(path)
    dt, steps_per_rev = facts["step"], 100
    table = hosts.pitch_schedule(facts["inputs"], dt, steps_per_rev)
    stop = round(revs * steps_per_rev) * dt
    names = facts["recorded"] + list(facts["inputs"])
    t0 = time.perf_counter()
    res = hosts.run_fmpy(path, stop, dt, table, {"scene": SCENE}, names)
    run_s = time.perf_counter() - t0
    out.mkdir(parents=True, exist_ok=True)
    summary = {"scene": SCENE, "fmu": str(path), "revs": revs, "communication_step_s": dt,
               "simulated_s": stop, "build_s": build_s, "fmpy_wall_s": run_s,
               "realtime_factor": stop / run_s, "importer": "fmpy.simulate_fmu",
               "schedule": hosts.table_rows(table),
               "parameters": {**_fmu_parameters(path), **{n: float(res[n][-1]) for n in facts["inputs"]}}}
    files = {"results": _write_csv(res, out / "results.csv"),
             "hinge_angles": hinge_plot(res, path, facts, dt * steps_per_rev, out / "hinge_angles.png")}
    summary["files"] = {k: str(v) for k, v in files.items()}
    (out / "run.json").write_text(json.dumps(summary, indent=1))
    summary["files"]["run"] = str(out / "run.json")
    viewer = _viewer(out)
    if viewer:
        summary["files"]["viewer"] = str(viewer)
    summary["total_s"] = time.perf_counter() - start
    (out / "run.json").write_text(json.dumps(summary, indent=1))
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


def hinge_plot(res: np.ndarray, fmu: Path, facts: dict, revolution: float, path: Path) -> Path:
    """Pitch inputs, then one panel per group of hinge angles (the scene's plot panels), deg."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    panels = {"pitch inputs (rad)": list(facts["inputs"]), **_scene_panels(fmu)}
    fig, axes = plt.subplots(len(panels), 1, figsize=(8, 2.2 * len(panels) + 0.6), sharex=True, squeeze=False)
    revs = res["time"] / revolution
    for ax, (label, names) in zip(axes[:, 0], panels.items()):
        for name in names:
            ax.plot(revs, np.degrees(res[name]), lw=1.0, label=name)
        ax.set_ylabel(label.replace("(rad)", "(deg)"), fontsize=8)
        ax.grid(alpha=0.3)
        ax.legend(fontsize=7, ncol=min(len(names), 4), loc="upper right")
    axes[-1, 0].set_xlabel("main-rotor revolutions")
    fig.suptitle(f"{SCENE} through the FMU (fmpy): collective step and cyclic doublet", fontsize=10)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path


def _scene_panels(fmu: Path) -> dict:
    import zipfile

    with zipfile.ZipFile(fmu) as z:
        spec = json.loads(z.read("resources/heli_models/spec.json"))
    return spec["scenes"][SCENE]["plots"]


def _viewer(out: Path) -> Path | None:
    """``viewer.export_html(out, out / "viewer.html")`` if the viewer package exists."""
    try:
        from viewer import export_html
    except ImportError:
        print("note: the viewer package is not available; viewer.html not written")
        return None
    return export_html(out, out / "viewer.html", revs=None).path  # the whole run (thinned to fit 5 MB)
