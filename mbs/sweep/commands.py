"""``heli sweep trim|simulate|floquet``: sweeps as Dask tasks (:mod:`mbs.sweep`)."""
from __future__ import annotations

import argparse
import time
from pathlib import Path

from mbs import arguments as A
from mbs.envelope import CLIMB_RANGE
from mbs.cli import add_json, emit


def cmd_sweep(args) -> int:
    from mbs._progress import Progress
    from mbs.sweep import run, run_info

    axes, options = _axes(args), _options(args)
    out = args.out or A.output_folder(f"out/sweep/{args.kind}-{args.scene}")
    if args.kind == "simulate":
        _warn_untrimmed(args)
    start = time.perf_counter()
    result = run(args.kind, args.scene, axes, options, out=out, workers=args.workers, scheduler=args.scheduler,
                 progress=Progress(f"sweep {args.kind} {args.scene}", not args.quiet))
    res = _summary(args, result, run_info(result), out, time.perf_counter() - start)
    emit(res, args.json, _lines(res))
    return 0 if res["errors"] == 0 and res["ok"] > 0 else 1


def _warn_untrimmed(args) -> None:
    """Say when every point of a simulate sweep starts from the closed-form estimate."""
    from mbs import scenes
    from mbs.cli import warn
    from mbs.trims.start import estimate_warning

    text = estimate_warning(scenes.get(args.scene, aircraft=args.aircraft), "every point of the sweep")
    if text:
        warn(text)


def _axes(args) -> dict:
    """The grid of the command line: the kind's own axis first, then each ``--param``."""
    from mbs.sweep.grid import parse_axis, parse_range

    axes = {}
    if args.kind == "trim":
        axes["speed"] = parse_range("--speed", args.speed, A.speed_ends)
    if args.kind == "floquet":
        axes["omega"] = parse_range("--omega", args.omega)
    for item in args.param or []:
        name, values = parse_axis("--param", item)
        if name in axes:
            raise ValueError(f"--param {item!r}: {name} is already an axis of this sweep")
        axes[name] = values
    if not axes:
        raise ValueError(f"sweep {args.kind}: give at least one --param NAME=LO:HI:N")
    return axes


def _options(args) -> dict:
    """The settings shared by every point (recorded with the table)."""
    from mbs.sweep.models import aircraft_option

    out = {"backend": args.backend, "method": args.method, "steps_per_rev": args.steps_per_rev}
    if args.aircraft is not None:
        out["aircraft"] = aircraft_option(args.aircraft)
    if args.kind == "trim":
        out.update(climb_rate=args.climb_rate, tol=args.tol, iterations=args.iterations)
    if args.kind == "simulate":
        out.update(revs=args.revs, dtype=args.dtype)
    if args.kind == "floquet":
        from mbs.analysis.fanplot import parse_settings

        out.update(settings=parse_settings(args.set), frame=args.frame)
    return out


def _summary(args, result, info: dict, out: Path, wall_s: float) -> dict:
    """The JSON result: counts, run figures, files and every row."""
    from mbs.sweep.table import settings_of

    status = result.column("status").to_pylist() if result.num_rows else []
    files = sorted(str(p) for p in out.iterdir() if p.suffix in (".parquet", ".csv", ".png"))
    return {"kind": args.kind, "scene": args.scene, "axes": settings_of(result).get("axes", []),
            "points": result.num_rows, "ok": status.count("ok"), "failed": status.count("failed"),
            "errors": status.count("error"), **info, "out": str(out), "files": files, "wall_s": wall_s,
            "rows": result.to_pylist()}


def _lines(res: dict) -> list[str]:
    """The human-readable report: counts, the points without a result, the files."""
    bad = [r for r in res["rows"] if r["status"] != "ok"]
    return [f"{res['kind']} sweep of {res['scene']}: {res['points']} points ({res['computed']} computed, "
            f"{res['reused']} reused) in {res['wall_s']:.1f} s: {res['ok']} ok, {res['failed']} failed, "
            f"{res['errors']} errors",
            *[f"  {_point(r, res['axes'])}: {r['status']}: {r['message']}" for r in bad],
            *[f"wrote {f}" for f in res["files"]]]


def _point(row: dict, axes: list[str]) -> str:
    """``speed = 70, omega = 44.4``: the inputs of ``row``."""
    return ", ".join(f"{k} = {row[k]:g}" for k in axes)


_point_revs = A.positive_at_most(10_000, lambda text, revs: f"{text} revolutions a point is about {revs * 100:.3g} "
                                 "steps each (hours per point); give 10000 or fewer")
"""Type of ``sweep simulate --revs``: positive, at most 10000 revolutions a point."""


def _range(flag: str, limits=None):
    """Type of a ``LO:HI:N`` axis; ``limits`` (:class:`mbs.arguments.Within`) checks its ends."""
    def parse(text: str):
        from mbs.sweep.grid import parse_range

        values = parse_range(flag, text, A.speed_ends if limits is A.flight_speed else None)
        for v in (values[0], values[-1]) if limits else ():
            try:
                limits.check(v)
            except A.Bad as exc:
                raise ValueError(f"{text!r}: {exc}") from None
        return values
    return parse


def _axis(text: str):
    from mbs.sweep.grid import parse_axis

    return parse_axis("--param", text)


def _setting(text: str):
    from mbs.analysis.fanplot import parse_settings

    return parse_settings([text])


def _common(p: argparse.ArgumentParser) -> None:
    """Arguments of every sweep: scene, aircraft, where to run, where to write."""
    A.add_scene(p)
    A.add_aircraft(p)
    p.add_argument("--param", action="append", metavar="NAME=LO:HI:N", type=A.checked_by(_axis),
                   help="sweep a run-time parameter too (repeatable; the grid is every combination)")
    where = p.add_mutually_exclusive_group()
    where.add_argument("--workers", type=A.non_negative_int, default=None,
                       help="worker processes of a local Dask cluster (default: the machine's cores; 0: no Dask)")
    where.add_argument("--scheduler", metavar="ADDRESS", default=None,
                       help="run on an existing Dask cluster, e.g. tcp://host:8786 (its workers must see "
                            "this machine's compiled-model cache folder, $MBS_CACHE_DIR)")
    p.add_argument("--out", type=A.output_folder, default=None,
                   help="output folder (default out/sweep/KIND-SCENE); an existing one "
                   "resumes: its finished points are not computed again")
    p.add_argument("--backend", choices=["compiled", "vm"], default="compiled",
                   help="evaluator: generated C (default) or CasADi's virtual machine")
    p.add_argument("--steps-per-rev", type=A.positive_int, default=None,
                   help="steps per revolution (default: the scene's)")
    p.add_argument("--quiet", action="store_true", help="no progress bar")
    add_json(p)


def register(sub, bench) -> None:
    p = sub.add_parser("sweep", help="sweeps as Dask tasks: trims over speed, simulations over parameters, "
                       "Floquet analyses over rotor speed; one Parquet/CSV table and charts")
    kinds = p.add_subparsers(dest="kind", required=True, metavar="KIND")
    t = kinds.add_parser("trim", help="periodic trim at every speed (and parameter value)")
    _common(t)
    t.add_argument("--speed", required=True, metavar="LO:HI:N", type=A.checked_by(_range("--speed", A.flight_speed)),
                   help="speeds in m/s, e.g. 0:70:15, or with a unit: 0:100kt:11")
    t.add_argument("--climb-rate", type=A.climb_rate, default=0.0,
                   help=f"climb rate in m/s, up positive, {CLIMB_RANGE[0]:g} to {CLIMB_RANGE[1]:g} (default 0)")
    t.add_argument("--method", choices=("rk4", "rk8"), default="rk4", help="fixed-step method (default rk4)")
    t.add_argument("--tol", type=A.tolerance, default=1e-10,
                   help="max |scaled residual| to reach, at most 1e-3 (default 1e-10)")
    t.add_argument("--iterations", type=A.positive_int, default=20, help="most Newton iterations (default 20)")
    s = kinds.add_parser("simulate", help="simulation at every parameter value; min, max, mean of each output")
    _common(s)
    s.add_argument("--revs", type=_point_revs, default=1.0,
                   help="main-rotor revolutions per point, at most 10000 (default 1)")
    s.add_argument("--method", choices=("euler", "rk4", "rk8"), default="rk4", help="fixed-step method (default rk4)")
    s.add_argument("--dtype", choices=["float64", "float32"], default="float64",
                   help="precision of the compiled code (default float64)")
    f = kinds.add_parser("floquet", help="Floquet analysis at every rotor speed (fan plot)")
    _common(f)
    f.add_argument("--omega", required=True, metavar="LO:HI:N", type=A.checked_by(_range("--omega")),
                   help="rotor speeds in rad/s, e.g. 20:60:30")
    f.add_argument("--set", action="append", metavar="NAME=VALUE", type=A.checked_by(_setting),
                   help="fixed run-time parameter (repeatable)")
    f.add_argument("--frame", choices=("fixed", "rotating"), default="fixed",
                   help="rotor-mode frequencies in the fixed frame (multi-blade coordinates, default) or per blade")
    f.add_argument("--method", choices=("rk4", "rk8"), default="rk4", help="fixed-step method (default rk4)")
    for q in (t, s, f):
        q.set_defaults(fn=cmd_sweep)
