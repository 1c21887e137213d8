"""``heli view``: an offline HTML animation of a results folder, or a live meshcat server."""
from __future__ import annotations

import signal
import time
from pathlib import Path

from mbs import arguments as A
from mbs.cli import add_json, emit


def _terminate_as_exit(signum, frame):
    raise SystemExit(128 + signum)


def _follows(args) -> bool:
    """Whether the view starts following the fuselage (--camera follow, not --no-follow)."""
    return args.camera == "follow" and not args.no_follow


MODES = {"html": "the HTML page (the default)", "serve": "--serve", "simulate": "--simulate"}
ONLY = {"html": ("html",), "max_mb": ("html",), "no_trace": ("html",), "duration": ("serve",), "wait": ("simulate",),
        "port": ("serve", "simulate"), "every": ("html", "serve"), "start": ("html", "serve")}
"""Options that act in some modes only: given in another, they would do nothing, so they are refused."""


def _mode(args) -> str:
    return "simulate" if args.simulate is not None else "serve" if args.serve else "html"


def _check_options(args) -> None:
    """Refuse what would be ignored: a results folder with --simulate, and options of other modes."""
    if args.results is None and args.simulate is None:
        raise ValueError("give a results folder or results.csv, or --simulate SCENE")
    if args.results is not None and args.simulate is not None:
        raise ValueError(f"--simulate {args.simulate} runs the scene afresh and would ignore {args.results}; give one "
                         "of them")
    mode = _mode(args)
    for dest, modes in ONLY.items():
        value = getattr(args, dest)
        if value not in (None, False) and mode not in modes:
            option = "--" + dest.replace("_", "-")
            where = " or ".join(MODES[m] for m in modes)
            raise ValueError(f"{option} applies to {where} only: with {MODES[mode]} it would do nothing")


def cmd_view(args) -> int:
    _check_options(args)
    args.every, args.max_mb = args.every or 1, args.max_mb or 5.0
    if args.simulate is not None:
        return _live_simulation(args)
    if args.serve:
        return _serve(args)
    from viewer.export import export_html

    results = Path(args.results)
    out = Path(args.html) if args.html else (results if results.is_dir() else results.parent) / "viewer.html"
    exp = export_html(_source(args), out, revs=None if args.revs == 0 else args.revs, start=args.start, every=args.every,
                      slow=args.slow, trace=not args.no_trace, follow=_follows(args), backend=args.backend,
                      max_bytes=args.max_mb * 1e6)
    _say_shorter(args, exp.motion.recording)
    res = exp.summary()
    rows = "every row" if exp.every == 1 else f"1 row in {exp.every}"
    emit(res, args.json, [f"{res['scene']}: t = {exp.sim_time[0]:.4g} to {exp.sim_time[1]:.4g} s, {exp.keys} keyframes "
                          f"(from {rows}), plot of {exp.plot_rows} rows; largest joint turn between keys "
                          f"{exp.max_key_angle_deg:.1f} deg", f"wrote {exp.path} ({exp.size / 1e6:.2f} MB)"])
    return 0


def _source(args):
    """The results path, or its recording with the aircraft file of ``--aircraft`` (a file that moved)."""
    if args.aircraft is None:
        return Path(args.results)
    from viewer.motion import from_results

    return from_results(Path(args.results), args.backend, args.aircraft)


def _say_shorter(args, rec) -> None:
    """Warn when ``--revs`` asks for more revolutions than the run has (all of it is shown)."""
    from mbs.cli import warn

    if args.revs and rec.revolution:
        has = (rec.t[-1] - rec.t[0]) / rec.revolution
        if args.revs > has * (1 + 1e-6):
            warn(f"--revs {args.revs:g}: the run has {has:.4g} revolutions; all of it is shown")


def _serve(args) -> int:
    from viewer.live import LiveViewer
    from viewer.motion import motion

    mo = motion(_source(args), None if args.revs == 0 else args.revs, args.start, args.every, backend=args.backend)
    signal.signal(signal.SIGTERM, _terminate_as_exit)
    with LiveViewer(mo.recording.system, follow=_follows(args), web_port=args.port) as live:
        emit({"url": live.url, "pid": live.pid, "keys": len(mo.t)}, args.json,
             [f"meshcat viewer at {live.url} (Ctrl-C to stop)"])
        end = time.monotonic() + args.duration if args.duration else None
        try:
            while end is None or time.monotonic() < end:
                live.play(mo, slow=args.slow)
        except KeyboardInterrupt:
            pass
    return 0


def _live_simulation(args) -> int:
    from mbs import scenes
    from mbs._progress import Progress
    from viewer.live import LiveViewer

    from mbs.cli import warn
    from mbs.trims.start import estimate_warning

    scene = scenes.get(args.simulate, aircraft=args.aircraft)
    if estimate_warning(scene, "heli view --simulate"):
        warn(estimate_warning(scene, "heli view --simulate"))
    system = scene.system(args.backend)
    signal.signal(signal.SIGTERM, _terminate_as_exit)
    with LiveViewer(system, follow=_follows(args), web_port=args.port) as live:
        print(f"meshcat viewer at {live.url}", flush=True)
        if args.wait:
            time.sleep(args.wait)
        revs = args.revs or 1.0
        try:
            t, _ = live.simulate(scene, revs, slow=args.slow, progress=Progress(f"simulate {scene.name}", not args.json))
        except KeyboardInterrupt:
            return 130
        emit({"url": live.url, "scene": scene.name, "revs": revs, "t_end": t}, args.json,
             [f"{scene.name}: {revs:g} revolutions shown live, t_end = {t:.4g} s"])
    return 0


def register(sub, bench) -> None:
    p = sub.add_parser("view", help="animate results in the browser: one offline HTML file, or a live meshcat server",
                       description="Animate the rotor tree of a results folder (results.csv + run.json from "
                                   "'heli simulate') as one self-contained HTML file (--html, the default) or on "
                                   "a local meshcat server (--serve); --simulate SCENE streams a run as it computes.")
    p.add_argument("results", nargs="?", help="results folder or results.csv (with run.json beside it)")
    p.add_argument("--html", metavar="OUT.html", type=A.output_file(".html"),
                   help="output file (default: viewer.html beside the results)")
    p.add_argument("--serve", action="store_true", help="stream to a meshcat server on 127.0.0.1 until Ctrl-C")
    A.add_scene(p, "--simulate", what="run this scene and stream each step live (implies a server)")
    p.add_argument("--aircraft", metavar="FILE", type=A.aircraft_file, default=None,
                   help="with --simulate: the aircraft (a file, or bo105, lynx, puma) whose scene runs; with results: "
                        "the run's aircraft file where it is now, when it has moved since the run (it must be the same "
                        "file: its SHA-256 is checked against run.json's)")
    p.add_argument("--revs", type=A.non_negative, default=0.0,
                   help="main-rotor revolutions shown, the last ones (default 0: the whole run)")
    p.add_argument("--start", type=A.finite, default=None,
                   help="first time shown, s (default: last --revs revolutions)")
    p.add_argument("--every", type=A.positive_int, default=None,
                   help="keep every N-th recorded row (default 1) (keys are added back where a joint would turn "
                        "60 deg or more)")
    p.add_argument("--slow", type=A.positive, default=10.0,
                   help="the page starts playing F times slower than real time (default 10; it has a speed control)")
    p.add_argument("--no-trace", action="store_true", help="no blade tip-path trace")
    p.add_argument("--no-follow", action="store_true", help="same as --camera fixed")
    p.add_argument("--camera", choices=["follow", "fixed"], default="follow",
                   help="the view starts following the fuselage (default) or fixed to the ground; the page has a toggle")
    p.add_argument("--max-mb", type=A.positive, default=None, metavar="MB",
                   help="size limit of the page in MB (default 5): longer runs show every N-th recorded row")
    p.add_argument("--backend", choices=["vm", "compiled"], default="vm",
                   help="evaluator for the poses: CasADi's virtual machine (default) or compiled C")
    p.add_argument("--port", type=A.port, default=None, help="web port of the live server (default: first free from 7000)")
    p.add_argument("--duration", type=A.positive, default=None, help="with --serve: stop after this many seconds")
    p.add_argument("--wait", type=A.non_negative, default=None, help="with --simulate: seconds to wait before running "
                                                            "(time to open the page)")
    add_json(p)
    p.set_defaults(fn=cmd_view)
