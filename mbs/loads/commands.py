"""``heli loads``: rotor loads at the periodic trim (hub loads and their harmonics, blade root
and spanwise loads, shaft and engine power), at one speed or over a speed sweep; and ``heli
bench loads``, the cost of the loads outputs."""
from __future__ import annotations

from pathlib import Path

from mbs import arguments as A
from mbs.envelope import SPEED_RANGE
from mbs import commands as core
from mbs.cli import add_json, emit


def cmd_loads(args) -> int:
    if args.sweep and args.speed is not None:
        raise ValueError(f"give --speed or --sweep, not both (--speed {args.speed:g}, --sweep {args.sweep})")
    scene = core._scene(args)
    _check(args, scene)
    if args.sweep:
        return _sweep(args, scene)
    from mbs._progress import Progress
    from mbs.loads import files
    from mbs.loads.analysis import rotor_loads

    res = rotor_loads(scene, args.speed, args.steps_per_rev, args.backend,
                      progress=Progress(f"loads {args.scene}", not args.quiet))
    out, lines = res.summary(), loads_lines(res)
    if args.out:
        out["files"] = [str(p) for p in files.write(res, Path(args.out))]
        lines += [f"wrote {f}" for f in out["files"]]
    emit(out, args.json, lines)
    return 0


def _cell(x: float) -> str:
    return f"{x:11.4g}"


def loads_lines(res) -> list[str]:
    """The human-readable report of :func:`mbs.loads.analysis.rotor_loads`."""
    nb = res.n_blades
    lines = [f"{res.title}: loads over {res.revs} main-rotor revolution(s) of the periodic "
             f"solution, {len(res.t)} samples ({res.trim_reason}; {res.wall_s:.2f} s)"]
    for rotor in ("main_rotor", "tail_rotor"):
        rows = res.hub_rows(rotor)
        if rows:
            own = [k for k in rows[0] if k.endswith("/rev")]
            per = "main-rotor" if rotor == "main_rotor" else "tail-rotor"
            lines += [f"  {rotor.replace('_', '-')} hub loads on the airframe, body axes (N, N m): harmonics per "
                      f"{per} revolution; other and fractional orders (@) per main-rotor revolution",
                      f"    {'':10s} {'mean':>11s} " + " ".join(f"{k:>11s}" for k in own)
                      + f" {'other':>18s} {'fractional':>18s}"]
            for r in rows:
                lines.append(f"    {r['output'].rsplit('.', 1)[1]:10s} {_cell(r['mean'])} "
                             + " ".join(_cell(r[k]) for k in own)
                             + _at(r["other"], r["other_order"]) + _at(r["fractional"], r["fractional_order"]))
    lines += _blade_lines(res) + _power_lines(res) + _span_lines(res)
    lines.append(f"  (other: the largest other harmonic of that rotor's speed; fractional: the largest content at "
                 f"orders that are none, from the other rotor through the airframe; {nb} identical blades pass "
                 f"only 0, {nb}, {2 * nb} ... /rev into the hub)")
    return lines


def _at(value: float, order: float | None) -> str:
    """A load and the order it appears at, or a dash where the spectrum has no such order."""
    return f" {value:10.3g} @{order:<6g}" if order is not None else f" {'-':>10s}  {'':6s}"


def _blade_lines(res) -> list[str]:
    rows = res.blade_rows()
    if not rows:
        return []
    keys = [k for k in rows[0] if k.endswith("/rev")]
    return ["  blade 1 root loads (hub on blade, blade axes; rotating frame; N, N m)",
            f"    {'':12s} {'mean':>11s} " + " ".join(f"{k:>11s}" for k in keys),
            *[f"    {r['output'].rsplit('.', 1)[1]:12s} {_cell(r['mean'])} " + " ".join(_cell(r[k]) for k in keys)
              for r in rows]]


def _power_lines(res) -> list[str]:
    rows = res.power_rows()
    return ["  power (W, period mean)", *[f"    {r['output']:24s} {r['mean']:12.6g}" for r in rows]] if rows else []


def _span_lines(res) -> list[str]:
    rows = res.span_rows()
    if len(rows) <= 1:
        return []
    return ["  blade 1 along the span (N m): radius, mean and 1/rev of flap, lag bending, torsion",
            *[f"    {r['station']:16s} {r['radius']:6.3f} m " + " ".join(
                f"{r[f'{w}_mean']:10.4g} {r[f'{w}_1/rev']:10.4g}" for w in ("flap", "lag", "torsion")) for r in rows]]


def _check(args, scene) -> None:
    """Refuse, before any work: a scene without periodic solution, a speed (or a speed sweep)
    on a scene that does not fly, and steps too few to resolve the orders the loads report."""
    import math

    from mbs.loads.analysis import check_scene, highest_order, steps_resolving

    check_scene(scene)
    if args.sweep and not core._model_facts(scene)[1]:
        raise ValueError(f"--sweep {args.sweep}: scene {scene.name!r} has no free fuselage, so no flight speed to sweep "
                         "(its rotor turns in still air); sweep forward-flight or hover")
    core._check_speed(args, scene)
    order, which = highest_order(scene)
    if args.steps_per_rev and args.steps_per_rev <= 2 * order:
        raise ValueError(f"--steps-per-rev {args.steps_per_rev}: the loads of scene {scene.name!r} go up to "
                         f"{order:g}/rev ({which}), which needs more than {math.floor(2 * order)} samples per "
                         f"revolution; give --steps-per-rev {steps_resolving(order)} or more")


def _sweep(args, scene) -> int:
    from mbs._progress import Progress
    from mbs.loads import charts, files
    from mbs.loads.sweep import speed_sweep

    speeds = A.parse_speeds(args.sweep)
    res = speed_sweep(scene, speeds, args.steps_per_rev, args.backend,
                      Progress(f"loads sweep {args.scene}", not args.quiet))
    out_dir = Path(args.out or f"out/loads/{args.scene}")
    paths = [files.sweep_csv(res.rows(), out_dir / f"vibratory_hub_loads_{res.scene}.csv"),
             charts.vibratory(res.points, out_dir / f"vibratory_hub_loads_{res.scene}.png", [v for v, _ in res.failed])]
    out = {"scene": res.scene, "speeds": speeds.tolist(), "rows": res.rows(), "files": [str(p) for p in paths],
           "setup_s": res.setup_s, "wall_s": res.wall_s}
    emit(out, args.json, sweep_lines(res, paths))
    return 0 if res.points else 1


def sweep_lines(res, paths) -> list[str]:
    """The human-readable report of :func:`mbs.loads.sweep.speed_sweep`."""
    from mbs.loads.outputs import COMPONENTS

    nb = res.points[0].n_blades if res.points else 4
    cols = [f"main_rotor.hub.{c}.{nb}/rev" for c in COMPONENTS]
    lines = [f"{res.scene}: loads at {len(res.points) + len(res.failed)} speeds in {res.wall_s:.1f} s "
             f"({res.setup_s:.1f} s set-up); main-rotor hub loads' {nb}/rev amplitude (N, N m), engine power (kW)",
             f"  {'speed':>6s} " + " ".join(f"{c.split('.')[2]:>9s}" for c in cols) + f" {'engine':>9s}"]
    for r in res.rows():
        if r["status"] != "ok":
            lines.append(f"  {r['speed']:6.1f}  no trim: {r['message']}")
            continue
        lines.append(f"  {r['speed']:6.1f} " + " ".join(f"{r[c]:9.4g}" for c in cols)
                     + f" {r.get('engine.power', float('nan')) * 1e-3:9.1f}")
    return lines + [f"wrote {p}" for p in paths]


def cmd_bench_loads(args) -> int:
    from mbs.loads import bench

    res = bench.run(args.scene, args.sweep)
    emit(res, args.json, bench.lines(res))
    return 0


def register(sub, bench) -> None:
    p = sub.add_parser("loads", help="rotor loads at the periodic trim: hub loads in body axes and their harmonics, "
                       "blade root and spanwise loads, shaft and engine power; --sweep: against speed")
    A.add_scene(p, nargs="?", default="forward-flight", what="scene (default forward-flight)")
    A.add_aircraft(p)
    p.add_argument("--speed", type=A.flight_speed, default=None,
                   help=f"flight speed in m/s, {SPEED_RANGE[0]:g} to {SPEED_RANGE[1]:g}, or with a unit: 60kt, "
                        "100km/h, ft/s, mph (default: the scene's)")
    p.add_argument("--sweep", metavar="LO:HI:N", default=None, type=A.checked_by(A.parse_speeds),
                   help="loads at N speeds from LO to HI m/s (e.g. 0:72:13, or 0:140kt:15): table, CSV and the chart of the "
                        "vibratory hub loads and the power against speed (in --out, default out/loads/SCENE)")
    core._steps_per_rev(p)
    core._backend(p)
    p.add_argument("--out", type=A.output_folder, default=None,
                   help="output folder: the period's loads and their harmonics (CSV) and charts (default: print only)")
    core._aero(p)
    core._air(p)
    core._quiet(p)
    add_json(p)
    p.set_defaults(fn=cmd_loads)

    p = bench.add_parser("loads", help="cost of the loads outputs per step against an RK4 step, and a loads sweep")
    A.add_scene(p, nargs="?", default="forward-flight", what="scene (default forward-flight)")
    p.add_argument("--sweep", metavar="LO:HI:N", default="0:72:13", type=A.checked_by(A.parse_speeds),
                   help="speeds of the timed sweep (default 0:72:13)")
    add_json(p)
    p.set_defaults(fn=cmd_bench_loads)
