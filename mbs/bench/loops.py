"""The cost of the swashplate's local loops: ``heli bench loops [--json]`` (or ``python -m mbs.bench.loops``).

RK4 step and right-hand side of forward flight (the Bo105, every aerodynamics switch on) without
the mechanism and with it: pitch links closed in closed form (the Bo105's horn on the housing,
and a horn on the blade whose loop also reads flap and lag), by Newton steps, and elastic links
(the pitch four more states). Medians of CPU time (``time.thread_time``) in µs, each variant timed
in turn within one run, and the ratio to forward flight; the Newton residual after each step from
its predictor over ten revolutions of the Newton variant's run.
"""
from __future__ import annotations

import argparse
import json
import tempfile
import time
from dataclasses import replace
from pathlib import Path

import casadi as ca
import numpy as np

STEPS_PER_REV = 100


def _blade_horn(folder: Path):
    """The Bo105 with its horn on the blade (δ3 = 15°, link lean 3°), written in ``folder``."""
    from mbs import aircraft
    from mbs.aircraft.reader import tomllib

    raw = tomllib.loads(aircraft.packaged()["bo105"].read_text())
    sp = raw["swashplate"]
    sp.pop("ball_radius")
    sp["horn"]["value"] = "blade"
    sp["delta3"] = {"value": 15.0, "unit": "deg", "source": "EST"}
    sp["link_lean"] = {"value": 3.0, "unit": "deg", "source": "EST"}
    lines = []
    for section, items in raw.items():
        lines.append(f"[{section}]")
        lines += [f"{k} = {{ {', '.join(f'{f} = {json.dumps(v)}' for f, v in e.items())} }}" for k, e in items.items()]
    path = folder / "bo105_blade_horn.toml"
    path.write_text("\n".join(lines) + "\n")
    return aircraft.load(path)


def variants(folder: Path) -> dict:
    """Name -> (config, aircraft) of the timed models."""
    from mbs import aircraft
    from mbs.models.helicopter.scenes import SCENE_CONFIGS

    forward, bo105, horn = SCENE_CONFIGS["forward-flight"][0], aircraft.load(), _blade_horn(folder)
    return {"forward-flight": (forward, bo105),
            "swashplate, closed form (horn on the housing)": (replace(forward, swashplate="pitch"), bo105),
            "swashplate, closed form (horn on the blade)": (replace(forward, swashplate="pitch"), horn),
            "swashplate, Newton (horn on the blade)": (replace(forward, swashplate="pitch", loop_solver="newton"), horn),
            "swashplate, elastic links (horn on the blade)": (replace(forward, swashplate="pitch", pitch_link="elastic"),
                                                              horn)}


def _timers(system) -> tuple:
    from mbs.bench.timing import median_time

    x, p = system.x0(), system.params()
    h = 2 * np.pi / system.info.parameters[0]["default"] / STEPS_PER_REV
    rhs = system.bind("rhs")
    rhs.inputs[0][:], rhs.inputs[2][:] = x, p

    def steps():
        system.run(x, 0.0, h, 200, every=200, p=p)
    return (lambda: median_time(steps, clock=time.thread_time) / 200 * 1e6,
            lambda: median_time(rhs, clock=time.thread_time) * 1e6)


def newton_residuals(config, craft, iterations: int = 6) -> list[float]:
    """Largest link-length residual (m) after 1..``iterations`` Newton steps from the predictor,
    over every blade and every step of ten revolutions of the Newton variant's run."""
    import mbs
    from mbs.joints import Params
    from mbs.loops import Newton
    from mbs.models.helicopter import build

    model = build(config, craft)
    system = mbs.build(model, "compiled")
    p = system.params()
    traj = system.run(system.x0(), 0.0, 2 * np.pi / model.parameters["omega"].default / STEPS_PER_REV,
                      10 * STEPS_PER_REV, p=p)
    q, t, ps = ca.SX.sym("q", 2), ca.SX.sym("t"), ca.SX.sym("p", len(model.parameters))
    par, worst = Params(list(model.parameters), ps), np.zeros(iterations)
    for blade in (b for b in model.bodies if b.startswith("blade")):
        joint = model.bodies[blade].joint
        loop = joint.loop
        out = []
        for k in range(1, iterations + 1):
            _, g = Newton(loop.loop, loop.guess, iterations=k).iterate(joint, q, t, par)
            out.append(g)
        f = ca.Function("residuals", [q, t, ps], [ca.vertcat(*out)])
        names = system.info.state_names
        cols = [names.index(f"{blade}.flap"), names.index(f"{blade}.lag")]
        for x, tk in zip(traj.x, traj.t):
            worst = np.maximum(worst, np.abs(np.array(f(x[cols], tk, p)).ravel()))
    return worst.tolist()


def run(repeats: int = 3) -> dict:
    import mbs
    from mbs.bench.timing import machine
    from mbs.models.helicopter import build

    with tempfile.TemporaryDirectory() as folder:
        todo = variants(Path(folder))
        systems = {name: mbs.build(build(cfg, craft), "compiled") for name, (cfg, craft) in todo.items()}
        samples = {name: [] for name in systems}
        for _ in range(repeats):  # interleaved, so that load changes touch every variant alike
            for name, system in systems.items():
                step, rhs = _timers(system)
                samples[name].append((step(), rhs()))
        rows = {name: {"rk4_step_us": float(np.median([s[0] for s in v])), "rhs_us": float(np.median([s[1] for s in v])),
                       "dof": systems[name].info.nv} for name, v in samples.items()}
        base = rows["forward-flight"]["rk4_step_us"]
        for row in rows.values():
            row["ratio"] = row["rk4_step_us"] / base
        cfg, craft = todo["swashplate, Newton (horn on the blade)"]
        residuals = newton_residuals(cfg, craft)
    from mbs.models.helicopter.swashplate import NEWTON_ITERATIONS

    return {"machine": machine(), "rows": rows, "newton_residual_m_after_steps": residuals,
            "newton_steps_per_solve": NEWTON_ITERATIONS, "solves_per_rk4_step": 4 * 4}


def _lines(res: dict) -> list[str]:
    out = [f"{'model':48s} {'RK4 step µs':>12s} {'rhs µs':>8s} {'ratio':>6s}"]
    for name, row in res["rows"].items():
        out.append(f"{name:48s} {row['rk4_step_us']:12.1f} {row['rhs_us']:8.2f} {row['ratio']:6.2f}")
    out.append("Newton: largest link-length residual (m) after 1..6 steps from the predictor over 10 revolutions: "
               + ", ".join(f"{r:.1e}" for r in res["newton_residual_m_after_steps"]))
    return out


def cmd_bench_loops(args) -> int:
    from mbs.cli import emit

    res = run()
    emit(res, args.json, _lines(res))
    return 0


def register(sub, bench) -> None:
    from mbs.cli import add_json

    p = bench.add_parser("loops", help="forward flight's RK4 step with the swashplate's local loops (closed form, "
                                       "Newton, elastic links) against without, and Newton's residual per step")
    add_json(p)
    p.set_defaults(fn=cmd_bench_loops)


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(prog="python -m mbs.bench.loops", description=__doc__.splitlines()[0])
    parser.add_argument("--json", action="store_true", help="print one JSON object")
    args = parser.parse_args(argv)
    res = run()
    print(json.dumps(res) if args.json else "\n".join(_lines(res)))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
