"""``heli bench loads``: what the loads outputs cost, and a loads sweep's wall time.

The loads outputs are evaluated when a result is recorded (``System.outputs``), never inside
an integrator step: the step of the model with them is the step of the model without them
(the same generated right-hand side), which the benchmark checks by timing both.
"""
from __future__ import annotations

import re
import time

import numpy as np

from mbs.bench.timing import machine, median_time

LOADS = re.compile(r"\.(hub|root|station\d+)\.|\.shaft_(torque|power)$|^engine\.")
"""The outputs :func:`mbs.loads.rotorcraft.add_load_outputs` declares."""


def _systems(scene_name: str):
    """The scene's compiled system with its loads outputs and without them."""
    from mbs import scenes
    from mbs.backends import build

    sc = scenes.get(scene_name)
    bare = sc.model()
    for name in [n for n in bare.outputs if LOADS.search(n)]:
        del bare.outputs[name]
    bare.name += "-without-loads"
    return sc, sc.system("compiled"), build(bare, "compiled")


def _step_in_run(system, x, p, h: float, steps: int = 200) -> float:
    return median_time(lambda: system.run(x, 0.0, h, steps, every=steps, p=p)) / steps


def outputs_cost(scene_name: str = "forward-flight") -> dict:
    """Per step (µs): the loads outputs against the RK4 step, with and without the loads."""
    sc, system, bare = _systems(scene_name)
    x, p, t = system.x0(), system.params(), np.zeros(1)
    h = sc.revolution(system, p) / sc.steps_per_rev
    raw = {k: system.function(k) for k in ("outputs", "rhs", "step_rk4")}
    res = {"scene": scene_name, "outputs": len(system.info.outputs), "load_outputs":
           sum(1 for n in system.info.output_names if LOADS.search(n)),
           "outputs_us": 1e6 * median_time(lambda: raw["outputs"](x, t, p)),
           "outputs_without_loads_us": 1e6 * median_time(lambda: bare.function("outputs")(x, t, p)),
           "recorded_row_us": 1e6 * median_time(lambda: system.outputs(x, 0.0, p)),
           "rhs_us": 1e6 * median_time(lambda: raw["rhs"](x, t, p)),
           "rk4_step_us": 1e6 * median_time(lambda: raw["step_rk4"](x, t, h, p)),
           "rk4_step_in_run_us": 1e6 * _step_in_run(system, x, p, h),
           "rk4_step_in_run_without_loads_us": 1e6 * _step_in_run(bare, x, p, h)}
    res["outputs_share_of_rk4_step"] = res["outputs_us"] / res["rk4_step_us"]
    res["step_ratio_with_to_without_loads"] = res["rk4_step_in_run_us"] / res["rk4_step_in_run_without_loads_us"]
    return res


def sweep_time(scene_name: str, speeds) -> dict:
    """Wall time of ``heli loads SCENE --sweep`` (trim and loads at every speed)."""
    from mbs.loads.sweep import speed_sweep

    start = time.perf_counter()
    res = speed_sweep(scene_name, speeds)
    return {"scene": scene_name, "speeds": list(map(float, speeds)), "trimmed": len(res.points),
            "failed": [v for v, _ in res.failed], "setup_s": res.setup_s, "wall_s": time.perf_counter() - start,
            "per_speed_s": [p.wall_s for p in res.points]}


def run(scene_name: str = "forward-flight", sweep: str = "0:72:13") -> dict:
    from mbs.arguments import parse_speeds

    return {"benchmark": "loads", "machine": machine(), "cost": outputs_cost(scene_name),
            "sweep": sweep_time(scene_name, parse_speeds(sweep))}


def lines(res: dict) -> list[str]:
    c, s = res["cost"], res["sweep"]
    return [f"{c['scene']}: {c['outputs']} outputs, {c['load_outputs']} of them loads (compiled C, float64; medians)",
            f"  outputs, one call: {c['outputs_us']:.2f} µs with the loads, {c['outputs_without_loads_us']:.2f} µs "
            f"without; {c['outputs_share_of_rk4_step']:.2f} of an RK4 step ({c['rk4_step_us']:.2f} µs; rhs "
            f"{c['rhs_us']:.2f} µs); a recorded row from Python {c['recorded_row_us']:.2f} µs",
            f"  RK4 step inside a 200-step run: {c['rk4_step_in_run_us']:.2f} µs with the loads outputs, "
            f"{c['rk4_step_in_run_without_loads_us']:.2f} µs without "
            f"(ratio {c['step_ratio_with_to_without_loads']:.3f})",
            f"  loads sweep over {len(s['speeds'])} speeds: {s['wall_s']:.1f} s ({s['setup_s']:.1f} s set-up, median "
            f"{np.median(s['per_speed_s']) if s['per_speed_s'] else float('nan'):.2f} s per speed); "
            f"no trim at {s['failed'] or 'none'}"]
