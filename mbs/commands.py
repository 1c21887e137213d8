"""Core subcommands of ``heli``: scenes, simulate, trim, figures (``heli demo`` is in :mod:`fmu.commands`)."""
from __future__ import annotations

from pathlib import Path

from mbs.cli import add_json, emit

FIXED_METHODS = ("euler", "rk4", "rk8")  # mbs.integrators.FIXED_STEP, named here to keep casadi out of start-up


def cmd_scenes(args) -> int:
    from mbs import scenes
    from mbs.dynamics import Layout

    rows, lines = [], []
    for sc in scenes.all_scenes().values():
        model = sc.model()
        lay = Layout.of(model)
        row = {"scene": sc.name, "description": sc.description, "bodies": [b.name for b in lay.bodies],
               "dof": lay.nv, "position_coordinates": lay.nq, "conservative": sc.conservative,
               "forces": [f.name for f in model.forces],
               "parameters": {p.name: p.default for p in model.parameters.values()}}
        rows.append(row)
        lines += [f"{sc.name}: {sc.description}",
                  f"  {len(lay.bodies)} bodies: {', '.join(row['bodies'])}",
                  f"  {lay.nv} degrees of freedom: {', '.join(lay.v_names)}",
                  f"  force elements: {', '.join(row['forces']) or 'none'} (+ gravity)",
                  f"  {'conservative' if sc.conservative else 'not conservative'}", ""]
    emit({"scenes": rows}, args.json, lines)
    return 0


def cmd_simulate(args) -> int:
    from mbs._progress import Progress
    from mbs.simulate import simulate, write

    sim = simulate(args.scene, args.revs, args.steps_per_rev, args.dtype, args.backend,
                   every=args.every, progress=Progress(f"simulate {args.scene}", not args.quiet), method=args.method)
    paths = write(sim, Path(args.out))
    res = sim.summary()
    res["files"] = {k: str(v) for k, v in paths.items()}
    lines = [f"{sim.scene.name}: {sim.revs:g} revolutions, {res['steps']} {sim.method} steps ({sim.system.dtype}, "
             f"{sim.system.backend}) in {sim.traj.wall_s:.3f} s, {res['realtime_factor']:.1f}x real time",
             f"result: {sim.traj.message}"]
    if "max_rel_energy_error" in res:
        lines.append(f"max relative energy error: {res['max_rel_energy_error']:.3e}")
    lines += [f"wrote {p}" for p in paths.values()]
    emit(res, args.json, lines)
    return 0 if sim.traj.ok else 1


def cmd_trim(args) -> int:
    from mbs._progress import Progress
    from mbs.trim import trim

    res = trim(args.scene, speed=args.speed, climb_rate=args.climb_rate, method=args.method,
               steps_per_rev=args.steps_per_rev, backend=args.backend, tol=args.tol,
               max_iterations=args.iterations, progress=Progress(f"trim {args.scene}", not args.quiet))
    out, lines = res.summary(), _trim_lines(res)
    if args.write and res.converged:
        from mbs.trim import write_trim

        out["written"] = str(write_trim(res, Path(args.write)))
        lines.append(f"wrote {out['written']}")
    emit(out, args.json, lines)
    return 0 if res.converged else 1


def _trim_lines(res) -> list[str]:
    """The human-readable report of :func:`mbs.trim.trim`."""
    import numpy as np

    per = res.period
    flip = f", teeter reversed; period {per.full_revs} revolutions" if per.flip else ""
    lines = [f"{res.scene} at {res.speed:g} m/s, climb {res.climb_rate:g} m/s: periodic shooting over {per.revs} "
             f"main-rotor revolution(s){flip}; {res.method}, {res.steps_per_rev} steps/rev",
             *[f"  iteration {k + 1}: max |scaled residual| {it.residual:.3e}, step {it.step:g}"
               for k, it in enumerate(res.history)],
             f"  final:       max |scaled residual| {np.abs(res.residual).max():.3e}",
             *[f"  {k:20s} {v:+.6f} rad ({np.degrees(v):+.4f} deg)" for k, v in
               [*res.controls.items(), ("roll", res.roll), ("pitch", res.pitch)]]]
    if res.thrust is not None:
        lines.append(f"  main-rotor thrust (mean) {res.thrust:.1f} N")
    verdict = "converged" if res.converged else "NOT CONVERGED"
    return lines + [f"  {res.summary()['note']}",
                    f"{verdict}: {res.reason}; {res.iterations} Newton iterations, {res.n_jacobian} Jacobians, "
                    f"{res.n_residual} residual runs, {res.wall_s:.2f} s (+ {res.setup_s:.2f} s set-up)"]


def cmd_floquet(args) -> int:
    from mbs.analysis.floquet import floquet

    res = floquet(args.scene, speed=args.speed, method=args.method, steps_per_rev=args.steps_per_rev,
                  backend=args.backend)
    lines = [f"{res.scene} at {res.speed:g} m/s: Floquet analysis over {res.period_revs} main-rotor revolutions "
             f"(monodromy over {res.interval_revs}; periodic solution in {res.trim.iterations} Newton iterations; "
             f"analysis {res.wall_s:.2f} s)",
             f"  {'mode':24s} {'Re λ 1/s':>10s} {'Im λ rad/s':>11s} {'Hz':>8s} {'/rev':>7s} {'ζ':>7s} {'|μ|':>9s}",
             *[f"  {m.name:24s} {m.exponent.real:+10.4f} {m.exponent.imag:11.4f} {m.frequency_hz:8.4f} "
               f"{m.per_rev:7.4f} {m.damping_ratio:+7.3f} {abs(m.multiplier):9.3e}" for m in res.modes],
             f"{'stable' if res.stable else 'UNSTABLE'}: largest |multiplier| "
             f"{max(abs(m.multiplier) for m in res.modes):.6f} over the period"]
    emit(res.summary(), args.json, lines)
    return 0


def cmd_figures(args) -> int:
    from mbs._progress import Progress
    from mbs.figures import make_all

    res = make_all(Path(args.out), progress=Progress("figures", not args.quiet))
    f3 = res["fig3"]
    lines = [f"Fig. 3 max relative energy error: float64 {f3['float64']['max_rel_energy_error']:.2e}, "
             f"float32 {f3['float32']['max_rel_energy_error']:.2e} "
             f"(plain summation {f3['float32_plain']['max_rel_energy_error']:.2e})",
             *[f"wrote {p}" for p in res["files"]]]
    emit(res, args.json, lines)
    return 0


def register(sub, bench) -> None:
    p = sub.add_parser("figures", help="regenerate the paper's Fig. 2 and Fig. 3")
    p.add_argument("--out", default="out/figures")
    p.add_argument("--quiet", action="store_true", help="no progress bar")
    add_json(p)
    p.set_defaults(fn=cmd_figures)

    p = sub.add_parser("trim", help="periodic trim: controls, attitude and periodic rotor states by Newton "
                       "with the exact AD Jacobian of the period map")
    p.add_argument("scene", nargs="?", default="forward-flight")
    p.add_argument("--speed", type=float, default=None, help="flight speed in m/s (default: the scene's)")
    p.add_argument("--climb-rate", type=float, default=0.0, help="climb rate in m/s, up positive (default 0)")
    p.add_argument("--method", choices=("rk4", "rk8"), default="rk4", help="fixed-step method (default rk4)")
    p.add_argument("--steps-per-rev", type=int, default=None, help="steps per revolution (default: the scene's)")
    p.add_argument("--backend", choices=["compiled", "vm"], default="compiled")
    p.add_argument("--tol", type=float, default=1e-10, help="max |scaled residual| to reach (default 1e-10)")
    p.add_argument("--iterations", type=int, default=20, help="most Newton iterations (default 20)")
    p.add_argument("--write", metavar="PATH", default=None,
                   help="store the converged trim in the TOML file PATH (the format of mbs/models/bo105_trim.toml)")
    p.add_argument("--quiet", action="store_true", help="no progress bar")
    add_json(p)
    p.set_defaults(fn=cmd_trim)

    p = sub.add_parser("floquet", help="Floquet stability at the periodic trim: multipliers, exponents, modes")
    p.add_argument("scene", nargs="?", default="forward-flight")
    p.add_argument("--speed", type=float, default=None, help="flight speed in m/s (default: the scene's)")
    p.add_argument("--method", choices=("rk4", "rk8"), default="rk4", help="fixed-step method (default rk4)")
    p.add_argument("--steps-per-rev", type=int, default=None, help="steps per revolution (default: the scene's)")
    p.add_argument("--backend", choices=["compiled", "vm"], default="compiled")
    add_json(p)
    p.set_defaults(fn=cmd_floquet)

    p = sub.add_parser("scenes", help="list the scenes: bodies, degrees of freedom, force elements")
    add_json(p)
    p.set_defaults(fn=cmd_scenes)

    p = sub.add_parser("simulate", help="run a scene and write results.csv, run.json and plots")
    p.add_argument("scene")
    p.add_argument("--revs", type=float, default=1.0, help="main-rotor revolutions (default 1)")
    p.add_argument("--steps-per-rev", type=int, default=None, help="steps per revolution (default: the scene's)")
    p.add_argument("--method", choices=FIXED_METHODS, default="rk4",
                   help="fixed-step method of the generated driver (default rk4, the paper's)")
    p.add_argument("--dtype", choices=["float64", "float32"], default="float64")
    p.add_argument("--backend", choices=["compiled", "vm"], default="compiled")
    p.add_argument("--every", type=int, default=1, help="record every N-th step")
    p.add_argument("--out", default="out/simulate", help="output folder (default out/simulate)")
    p.add_argument("--quiet", action="store_true", help="no progress bar")
    add_json(p)
    p.set_defaults(fn=cmd_simulate)
