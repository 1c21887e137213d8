"""``heli bench fmu``: the FMU's speed under fmpy against the core run directly.

The same ``forward-flight`` run (the demo's pitch schedule, communication step 1/100
revolution, one RK4 sub-step per communication step) is timed three ways, each in a fresh
interpreter so that nothing is shared:

- ``fmpy.simulate_fmu`` end to end (extract, instantiate, loop, record all outputs);
- fmpy's loop alone: the FMU already instantiated, ``setReal`` + ``doStep`` + ``getReal`` of
  every output per step (what a co-simulation master pays per step);
- the core directly: one ``system.run`` of all the steps (compiled evaluator).

Real-time factor = simulated time / wall time. Overhead ratio = core RTF / FMU RTF.
"""
from __future__ import annotations

import json
import subprocess
import sys
import tempfile
from pathlib import Path

from fmu import build

CHILD = r"""
import json, sys, time
import numpy as np
a = json.loads(sys.argv[1])
from fmu import hosts
facts = {"inputs": a["inputs"]}
table = hosts.pitch_schedule(a["inputs"], a["dt"], 100)
stop = a["steps"] * a["dt"]
out = {}
if a["what"] == "fmpy":
    t = time.perf_counter()
    hosts.run_fmpy(a["fmu"], stop, a["dt"], table, {"scene": a["scene"]})
    out["wall_s"] = time.perf_counter() - t
elif a["what"] == "loop":
    inst = hosts.Instance(a["fmu"])
    inst.initialise(strings={"scene": a["scene"]})
    names = hosts.output_names(a["fmu"])
    times = hosts.grid(stop, a["dt"])
    t = time.perf_counter()
    hosts.run_instance(inst, times, table, names)
    out["wall_s"] = time.perf_counter() - t
else:
    from mbs import scenes
    sc = scenes.get(a["scene"])
    system = sc.system("compiled")
    p = system.params(a["inputs"])
    system.run(system.x0(), 0.0, a["dt"], 10, p=p)
    t = time.perf_counter()
    system.run(system.x0(), 0.0, a["dt"], a["steps"], every=1, p=p)
    out["wall_s"] = time.perf_counter() - t
print(json.dumps(out))
"""


def _child(args: dict, cwd: str) -> dict:
    proc = subprocess.run([sys.executable, "-c", CHILD, json.dumps(args)], cwd=cwd, capture_output=True, text=True)
    if proc.returncode:
        raise RuntimeError(f"benchmark run failed:\n{proc.stderr[-3000:]}")
    return json.loads(proc.stdout.strip().splitlines()[-1])


def run(revs: float = 20.0, repeats: int = 3, scene: str = "forward-flight") -> dict:
    """Median wall times of ``repeats`` fresh-process runs of each kind; returns the figures."""
    from fmu.demo import fmu_facts

    path, build_s = build.ensure_fmu(build.DEFAULT_SCENES)
    facts = fmu_facts(path)
    steps = int(round(revs * 100))
    args = {"fmu": str(path), "dt": facts["step"], "steps": steps, "inputs": facts["inputs"], "scene": scene}
    walls = {}
    with tempfile.TemporaryDirectory(prefix="heli-bench-fmu-") as cwd:
        for what in ("core", "loop", "fmpy"):
            walls[what] = sorted(_child({**args, "what": what}, cwd)["wall_s"] for _ in range(repeats))
    sim = steps * facts["step"]
    med = {k: v[len(v) // 2] for k, v in walls.items()}
    rtf = {k: sim / w for k, w in med.items()}
    return {"scene": scene, "fmu": str(path), "revs": revs, "communication_step_s": facts["step"],
            "steps": steps, "simulated_s": sim, "repeats": repeats, "wall_s": walls,
            "realtime_factor_fmpy": rtf["fmpy"], "realtime_factor_fmpy_loop": rtf["loop"],
            "realtime_factor_core": rtf["core"], "overhead_ratio": rtf["core"] / rtf["fmpy"],
            "overhead_ratio_loop": rtf["core"] / rtf["loop"],
            "us_per_step": {k: w / steps * 1e6 for k, w in med.items()}, "target_fmpy_rtf": 10.0,
            "meets_target": rtf["fmpy"] >= 10.0}
