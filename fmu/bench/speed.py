"""``heli bench fmu``: the FMU's speed under fmpy against the core run directly.

The same ``forward-flight`` run (the demo's pitch schedule, communication step 1/100
revolution, one RK4 sub-step per communication step) is timed three ways, each in a fresh
interpreter so that nothing is shared:

- ``fmpy.simulate_fmu`` end to end (extract, instantiate, loop, record all outputs): the
  second call in the process (``fmpy``) and the first one, imports included (``fmpy_cold``);
- fmpy's low-level loop: the FMU already instantiated, ``setReal`` + ``doStep`` + ``getReal``
  of every output per step (what a co-simulation master pays per step);
- the core directly: one ``system.run`` of all the steps (compiled evaluator);
- the native FMU (C only) through ``fmpy.simulate_fmu`` (``fmpy_native``) and through the C
  host of :mod:`fmu.native.run` (``c_host``: ``setReal`` of the inputs, ``doStep``, ``getReal``
  of every output per step, the trim inputs held; ``c_host_states``: the same reading only
  the hinge angles and rates, which the FMU takes from its state without evaluating the model
  outputs).

Real-time factor = simulated time / wall time. Overhead ratio = core RTF / FMU RTF.
"""
from __future__ import annotations

import json
import os
import subprocess
import sys
import tempfile
from pathlib import Path

from fmu import build

CHILD = r"""
import json, sys, time
a = json.loads(sys.argv[1])
from fmu import hosts


def timed(fn):
    w, c = time.perf_counter(), time.process_time()
    fn()
    return {"wall_s": time.perf_counter() - w, "cpu_s": time.process_time() - c}


table = hosts.pitch_schedule(a["inputs"], a["dt"], 100)
stop = a["steps"] * a["dt"]
out = {}
if a["what"] == "fmpy":
    run = lambda: hosts.run_fmpy(a["fmu"], stop, a["dt"], table, {"scene": a["scene"]})
    out["cold"] = timed(run)
    out["warm"] = timed(run)
elif a["what"] == "loop":
    inst = hosts.Instance(a["fmu"])
    inst.initialise(strings={"scene": a["scene"]})
    names, times = hosts.output_names(a["fmu"]), hosts.grid(stop, a["dt"])
    out["warm"] = timed(lambda: hosts.run_instance(inst, times, table, names))
else:
    from mbs import scenes
    system = scenes.get(a["scene"]).system("compiled")
    p = system.params(a["inputs"])
    system.run(system.x0(), 0.0, a["dt"], 10, p=p)
    out["warm"] = timed(lambda: system.run(system.x0(), 0.0, a["dt"], a["steps"], every=1, p=p))
print(json.dumps(out))
"""


def _child(args: dict, cwd: str) -> dict:
    proc = subprocess.run([sys.executable, "-c", CHILD, json.dumps(args)], cwd=cwd, capture_output=True, text=True)
    if proc.returncode:
        raise RuntimeError(f"benchmark run failed:\n{proc.stderr[-3000:]}")
    return json.loads(proc.stdout.strip().splitlines()[-1])


def run(revs: float = 20.0, repeats: int = 3, scene: str = "forward-flight") -> dict:
    """Median times of ``repeats`` fresh-process runs of each kind; returns the figures.

    Real-time factors use wall time (the definition); the CPU-time factors beside them are
    what the same runs cost this process alone, robust to other load on the machine.
    """
    from fmu.demo import fmu_facts

    path, _ = build.ensure_fmu(build.DEFAULT_SCENES)
    facts = fmu_facts(path)
    steps = int(round(revs * 100))
    args = {"fmu": str(path), "dt": facts["step"], "steps": steps, "inputs": facts["inputs"], "scene": scene}
    runs = {}
    with tempfile.TemporaryDirectory(prefix="heli-bench-fmu-") as cwd:
        for what in ("core", "loop", "fmpy"):
            runs[what] = [_child({**args, "what": what}, cwd) for _ in range(repeats)]
        runs.update(_native_runs(args, repeats, cwd))
    sim = steps * facts["step"]
    kinds = {"core": ("core", "warm"), "fmpy_loop": ("loop", "warm"), "fmpy": ("fmpy", "warm"),
             "fmpy_cold": ("fmpy", "cold"), "fmpy_native": ("fmpy_native", "warm"), "c_host": ("c_host", "warm"),
             "c_host_states": ("c_host_states", "warm")}
    res = {"scene": scene, "fmu": str(path), "revs": revs, "communication_step_s": facts["step"], "steps": steps,
           "simulated_s": sim, "repeats": repeats, "load_average": os.getloadavg(), "target_fmpy_rtf": 10.0}
    for kind, (what, when) in kinds.items():
        for clock in ("wall_s", "cpu_s"):
            t = sorted(r[when][clock] for r in runs[what])[repeats // 2]
            suffix = "" if clock == "wall_s" else "_cpu"
            res[f"realtime_factor_{kind}{suffix}"] = sim / t
            res.setdefault("us_per_step" + suffix, {})[kind] = t / steps * 1e6
    res["overhead_ratio"] = res["realtime_factor_core"] / res["realtime_factor_fmpy"]
    res["overhead_ratio_cpu"] = res["realtime_factor_core_cpu"] / res["realtime_factor_fmpy_cpu"]
    res["meets_target"] = res["realtime_factor_fmpy"] >= 10.0
    res.update(_native_targets(res))
    return res


def _native_runs(args: dict, repeats: int, cwd: str) -> dict:
    """The native FMU: fmpy (fresh interpreters) and the C host (fresh processes)."""
    from fmu.native import run as native_run
    from fmu.native.build import ensure_native_fmu

    path, _ = ensure_native_fmu(build.DEFAULT_SCENES)
    fmpy_runs = [_child({**args, "what": "fmpy", "fmu": str(path)}, cwd) for _ in range(repeats)]
    host, folder = native_run.compile_host(Path(cwd) / "heli_fmi_host"), native_run.extract(path, Path(cwd) / "native")
    facts = native_run.facts(path)
    so = native_run.library(folder, facts["identifier"])
    inputs = {n: args["inputs"][n] for n in facts["inputs"]}
    hinges = [n for n in facts["outputs"] if n.split(".")[-1].split("_")[0] in ("flap", "lag", "teeter")]
    runs = {"fmpy_native": fmpy_runs}
    for kind, names in (("c_host", facts["outputs"]), ("c_host_states", hinges)):
        runs[kind] = [{"warm": native_run.time_host(host, so, facts, args["scene"], args["dt"], args["steps"], inputs,
                                                    names)} for _ in range(repeats)]
    return runs


def _native_targets(res: dict) -> dict:
    """C host time per step against the core's (target <= 1.2) and fmpy's real-time factor
    with the native FMU (target >= 30)."""
    us, usc = res["us_per_step"], res["us_per_step_cpu"]
    return {"c_host_over_core": us["c_host"] / us["core"], "c_host_over_core_cpu": usc["c_host"] / usc["core"],
            "c_host_states_over_core": us["c_host_states"] / us["core"],
            "meets_native_targets": us["c_host"] / us["core"] <= 1.2 and res["realtime_factor_fmpy_native"] >= 30.0}
