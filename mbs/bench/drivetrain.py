"""The cost of the rotor speed as a state, the engines and the air: ``heli bench drivetrain [--json]``.

RK4 step and right-hand side of forward flight (the Bo105, every aerodynamics switch on) at constant
rotor speed, and with the rotor speed a state (rigid drive train), with the engines and governor,
with Dryden turbulence (moderate), and with everything on (ISA, wind, turbulence, gust, ground
effect): medians of CPU time (``time.thread_time``) in µs, each variant timed in turn within one
run, the ratio to the constant-speed step, and the real-time factor at 100 steps per revolution.
"""
from __future__ import annotations

import time
from dataclasses import replace

import numpy as np

STEPS_PER_REV = 100
CONSTANT = "forward-flight (constant rotor speed)"


def variants() -> dict:
    """Name -> config of the timed models."""
    from mbs.models.helicopter.scenes import SCENE_CONFIGS

    forward = SCENE_CONFIGS["forward-flight"][0]
    free = replace(forward, drive_train="rigid")
    engines = replace(free, engines=True)
    turbulent = replace(engines, turbulence="dryden")
    return {CONSTANT: forward, "rotor speed a state (rigid drive train)": free,
            "+ engines and governor": engines, "+ Dryden turbulence (the benchmark's)": turbulent,
            "everything (+ ISA, wind, gust, ground effect)": replace(turbulent, atmosphere="isa", wind=(-3.0, 0.0, 0.0),
                                                                     gust=True, ground_effect=True, height=50.0)}


def _timers(system, h: float) -> tuple:
    from mbs.bench.timing import median_time

    x, p = system.x0(), system.params()
    rhs = system.bind("rhs")
    rhs.inputs[0][:], rhs.inputs[2][:] = x, p

    def steps():
        system.run(x, 0.0, h, 200, every=200, p=p)
    return (lambda: median_time(steps, clock=time.thread_time) / 200 * 1e6,
            lambda: median_time(rhs, clock=time.thread_time) * 1e6)


def run(repeats: int = 3) -> dict:
    import mbs
    from mbs import aircraft
    from mbs.bench.timing import machine
    from mbs.models.helicopter import build

    craft = aircraft.load()
    h = 2 * np.pi / craft.omega / STEPS_PER_REV
    systems = {name: mbs.build(build(cfg, craft), "compiled") for name, cfg in variants().items()}
    samples = {name: [] for name in systems}
    for _ in range(repeats):  # interleaved, so that load changes touch every variant alike
        for name, system in systems.items():
            step, rhs = _timers(system, h)
            samples[name].append((step(), rhs()))
    rows = {name: {"rk4_step_us": float(np.median([s[0] for s in v])), "rhs_us": float(np.median([s[1] for s in v])),
                   "states": systems[name].info.nx} for name, v in samples.items()}
    base = rows[CONSTANT]["rk4_step_us"]
    for row in rows.values():
        row["ratio"] = row["rk4_step_us"] / base
        row["realtime_factor"] = h * 1e6 / row["rk4_step_us"]
    return {"machine": machine(), "step_s": h, "rows": rows, "goal_ratio": 1.2,
            "ratio": rows["+ Dryden turbulence (the benchmark's)"]["ratio"]}


def _lines(res: dict) -> list[str]:
    out = [f"{'model':46s} {'RK4 step µs':>12s} {'rhs µs':>8s} {'ratio':>6s} {'real time':>9s}"]
    for name, row in res["rows"].items():
        out.append(f"{name:46s} {row['rk4_step_us']:12.1f} {row['rhs_us']:8.2f} {row['ratio']:6.2f} "
                   f"{row['realtime_factor']:8.1f}x")
    out.append(f"free rotor speed, engines and turbulence against constant speed: {res['ratio']:.2f}x "
               f"(goal {res['goal_ratio']}x)")
    return out


def cmd_bench_drivetrain(args) -> int:
    from mbs.cli import emit

    res = run()
    emit(res, args.json, _lines(res))
    return 0


def register(sub, bench) -> None:
    from mbs.cli import add_json

    p = bench.add_parser("drivetrain", help="forward flight's RK4 step with the rotor speed a state, the engines and "
                                            "turbulence against constant rotor speed; the real-time factor with "
                                            "everything on")
    add_json(p)
    p.set_defaults(fn=cmd_bench_drivetrain)

