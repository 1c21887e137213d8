"""``heli fly``: the flight page of a scene (one self-contained HTML file); ``heli bench fly``."""
from __future__ import annotations

import math
import sys
from pathlib import Path

from mbs import arguments as A
from mbs.cli import add_json, emit


def _log(message: str) -> None:
    print(message, file=sys.stderr, flush=True)


def speeds(text: str) -> list[float]:
    """Type of ``--speeds``: comma-separated trim speeds in m/s within the FMU's range, each once."""
    from fmu.build import FORWARD_SPEED_RANGE

    try:
        values = [float(v) for v in text.split(",")] if text.strip() else []
    except ValueError:
        raise A.Bad(f"{text!r} is not a comma-separated list of speeds in m/s (e.g. 0,20,40)") from None
    low, high = FORWARD_SPEED_RANGE
    for v in values:
        if not (math.isfinite(v) and low <= v <= high):
            raise A.Bad(f"speed {v:g} m/s is outside [{low:g}, {high:g}] m/s")
    if len(set(values)) < len(values):
        raise A.Bad(f"{text!r}: a speed is given twice")
    return values


def cmd_fly(args) -> int:
    from mbs import scenes
    from viewer.fly import check, write_page

    check(scenes.get(args.scene, args.aircraft), args.speeds)
    out = args.html or Path("out") / "fly" / f"{args.scene}.html"
    A.output_file(".html")(str(out))
    res = write_page(args.scene, out, args.aircraft, args.speeds, log=_log)
    lines = [f"{res.scene}: {len(res.starts)} start{'s' * (len(res.starts) > 1)} ({'; '.join(res.starts)}), "
             f"WebAssembly model {res.wasm_bytes / 1e3:.0f} kB, stability augmentation "
             f"{'in' if res.controller else 'not available'}" + (f"; {res.note}" if res.note else ""),
             f"wrote {res.path} ({res.size / 1e6:.2f} MB, {res.build_s:.1f} s): open it in a browser (works offline, "
             "from the file)"]
    emit(res.summary(), args.json, lines)
    return 0


def cmd_bench_fly(args) -> int:
    from viewer.fly import bench

    res = bench.run(args.scene, args.steps, args.repeats, log=_log)
    emit(res, args.json, bench.lines(res))
    return 0


def register(sub, bench) -> None:
    p = sub.add_parser("fly", help="fly a scene in the browser: one self-contained HTML page with the model as "
                                   "WebAssembly, piloted by keyboard, on-screen controls or a gamepad")
    A.add_scene(p, nargs="?", default="forward-flight", what="scene to fly (default forward-flight)")
    A.add_aircraft(p)
    p.add_argument("--html", metavar="OUT.html", type=A.output_file(".html"), default=None,
                   help="output file (default out/fly/<scene>.html)")
    p.add_argument("--speeds", type=speeds, default=None, metavar="V,V,...",
                   help="speeds (m/s) of the periodic trims the page starts from, computed when it is written, "
                        "besides the scene's own (default 0,10,20,40,60; a scene without a free fuselage has one start)")
    add_json(p)
    p.set_defaults(fn=cmd_fly)

    p = bench.add_parser("fly", help="the flight page's WebAssembly RK4 step in headless Chromium against the same "
                                     "step compiled natively, page size and time to the first frame")
    A.add_scene(p, nargs="?", default="forward-flight", what="scene (default forward-flight)")
    p.add_argument("--steps", type=A.whole_number(100), default=10000, help="steps timed per run (default 10000)")
    p.add_argument("--repeats", type=A.whole_number(1, 20), default=3, help="runs of each (default 3; the median)")
    add_json(p)
    p.set_defaults(fn=cmd_bench_fly)
