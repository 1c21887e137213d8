"""``heli performance ceiling|speed``: hover ceilings and the largest level speed of the Bo105
against altitude, mass and temperature, from trims swept on Dask (:mod:`mbs.performance.ceiling`)."""
from __future__ import annotations

import json
from pathlib import Path

import numpy as np

from mbs import arguments as A
from mbs.cli import add_json, emit

FT = 0.3048


def values(flag: str, low: float, high: float, unit: str, units: dict | None = None):
    """Type: ``A,B,C`` or ``LO:HI:N`` of finite numbers within ``[low, high]`` (``unit``), each
    bare or with one of ``units`` (name -> factor to ``unit``: ``0:10000ft:6``, ``2000lb``)."""
    within = A.Within(low, high, unit, f"the {flag[2:]} a sweep takes", units=units or {})

    def parse(text: str) -> np.ndarray:
        from mbs.sweep.grid import parse_range

        try:
            if ":" in text:
                out = parse_range(flag, text, lambda a, b: A.range_ends(a, b, within))
            else:
                out = np.array([within(t) for t in text.split(",") if t.strip()])
        except A.Bad as exc:
            raise ValueError(f"{flag} {text!r}: {exc}") from None
        except ValueError as exc:
            raise ValueError(str(exc) if ":" in text else f"{flag} {text!r} must be A,B,... or LO:HI:N") from None
        if not out.size:
            raise ValueError(f"{flag} {text!r} must be A,B,... or LO:HI:N")
        return out
    return parse


ALTITUDES = values("--altitudes", -1000.0, 20000.0, "m", {"m": 1.0, "km": 1000.0, "ft": 0.3048})
MASSES = values("--masses", 100.0, 100000.0, "kg", {"kg": 1.0, "lb": 0.45359237, "t": 1000.0})
TEMPERATURES = values("--temperatures", -60.0, 60.0, "K", {"K": 1.0, "C": 1.0})
SPEEDS = values("--speeds", 5.0, 100.0, "m/s", A.SPEED_UNITS)
HUB_HEIGHTS = values("--ige-hub-height", 0.5, 50.0, "m", {"m": 1.0, "ft": 0.3048})


def cmd_ceiling(args) -> int:
    from mbs._progress import Progress
    from mbs.performance.ceiling import hover_ceilings

    grounds = tuple(g for g in ("oge", "ige") if g in args.grounds.split(","))
    if args.ige_hub_height is not None and "ige" not in grounds:
        raise ValueError(f"--ige-hub-height {args.ige_hub_height}: sets the hover in ground effect, and --grounds "
                         f"{args.grounds} has none: give --grounds ige or oge,ige, or leave it out")
    if args.aircraft is not None and "ige" in grounds and args.ige_hub_height is None:
        from mbs.cli import warn
        from mbs.performance.ceiling import HUB_ABOVE_SKIDS, IGE_SKID_CLEARANCE

        warn(f"in ground effect the main-rotor hub is taken {IGE_SKID_CLEARANCE + HUB_ABOVE_SKIDS:g} m above the "
             "ground (the Bo105's hub over its skids, the skids 1 m up): give --ige-hub-height for this aircraft's")
    res = hover_ceilings(ALTITUDES(args.altitudes), _masses(args), TEMPERATURES(args.temperatures), grounds,
                         workers=args.workers, progress=Progress("performance ceiling", not args.quiet),
                         aircraft=args.aircraft,
                         hub_height=None if args.ige_hub_height is None else float(HUB_HEIGHTS(args.ige_hub_height)[0]))
    rows = [{**c.__dict__} for c in res]
    lines = ["hover ceiling (pressure altitude; power required from the trims, available from the engine model):"]
    for c in res:
        where = (f"{c.ceiling:7.0f} m ({c.ceiling / FT:6.0f} ft)" if c.ceiling is not None else
                 _no_crossing(c.altitudes, c.margins, "m", "altitude", "--altitudes"))
        lines.append(f"  {c.ground.upper()} {c.mass:6.0f} kg ISA{c.offset:+.0f}: {where}"
                     + (f" ({c.failed} trims failed)" if c.failed else ""))
    files = _write(args.out, "ceiling", rows, lambda path: _plot_ceiling(res, path)) if args.out else {}
    emit({"ceilings": rows, "files": files}, args.json, lines + [f"wrote {p}" for p in files.values()])
    return 0


def cmd_speed(args) -> int:
    from mbs._progress import Progress
    from mbs.performance.ceiling import level_speeds

    res = level_speeds(SPEEDS(args.speeds), ALTITUDES(args.altitudes), _masses(args),
                       TEMPERATURES(args.temperatures), workers=args.workers,
                       progress=Progress("performance speed", not args.quiet), aircraft=args.aircraft)
    rows = [{**c.__dict__} for c in res]
    lines = ["largest level speed (power required from the trims, available from the engine model):"]
    for c in res:
        where = f"{c.speed:5.1f} m/s ({c.speed / 0.514444:5.1f} kt)" if c.speed is not None else \
            _no_crossing(c.speeds, c.margins, "m/s", "speed", "--speeds")
        lines.append(f"  {c.altitude:6.0f} m {c.mass:6.0f} kg ISA{c.offset:+.0f}: {where}"
                     + (f" ({c.failed} trims failed)" if c.failed else ""))
    files = _write(args.out, "speed", rows, None) if args.out else {}
    emit({"level_speeds": rows, "files": files}, args.json, lines + [f"wrote {p}" for p in files.values()])
    return 0


def _no_crossing(x, margins, unit: str, what: str, option: str) -> str:
    """Why a sweep has no zero of its power margin (W) at the swept ``x``: where it stays positive
    or negative, with the margin at the nearest end and what to extend."""
    ok = [(float(a), float(m)) for a, m in zip(x, margins) if m is not None and np.isfinite(m)]
    if not ok:
        return "no trim converged"
    (first, m_first), (last, m_last) = ok[0], ok[-1]
    if m_last > 0:
        return (f"above the highest {what} swept, {last:g} {unit} (margin {m_last / 1e3:+.1f} kW there): "
                f"extend {option}")
    if m_first <= 0:
        return (f"below the lowest {what} swept, {first:g} {unit} (margin {m_first / 1e3:+.1f} kW there): "
                f"extend {option} or lighten the aircraft")
    return f"not within the swept {what}s"


def _masses(args) -> np.ndarray:
    """``--masses``, or the aircraft file's own mass."""
    if args.masses is not None:
        return MASSES(args.masses)
    from mbs import aircraft

    return np.array([(args.aircraft or aircraft.load()).data["aircraft"]["mass"]])


def _write(out: str, kind: str, rows: list[dict], plot) -> dict:
    folder = Path(out)
    folder.mkdir(parents=True, exist_ok=True)
    files = {"json": folder / f"{kind}.json"}
    files["json"].write_text(json.dumps(rows, indent=1, default=lambda o: None if o is None else float(o)))
    if plot:
        files["png"] = plot(folder / f"{kind}.png")
    return {k: str(v) for k, v in files.items()}


def _plot_ceiling(res, path: Path) -> Path:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(7, 4.5))
    for c in res:
        ax.plot(np.array(c.margins) / 1e3, c.altitudes, "o-",
                label=f"{c.ground.upper()} {c.mass:.0f} kg ISA{c.offset:+.0f}")
    ax.axvline(0.0, color="k", lw=0.8)
    ax.set_xlabel("power available − required (kW)")
    ax.set_ylabel("pressure altitude (m)")
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize=8)
    ax.set_title("hover: the ceiling where the margin is zero")
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path


def register(sub, bench) -> None:
    p = sub.add_parser("performance", help="hover ceilings and the largest level speed from trims swept on Dask")
    kinds = p.add_subparsers(dest="kind", required=True, metavar="KIND", parser_class=type(p))
    for kind, text in (("ceiling", "hover ceilings in and out of ground effect"),
                       ("speed", "the largest level speed")):
        q = kinds.add_parser(kind, help=text)
        q.add_argument("--altitudes", default="0:4000:5" if kind == "ceiling" else "0,2000",
                       type=A.checked_by(ALTITUDES), help="pressure altitudes in m (or ft, km: 0:10000ft:6): A,B,... or "
                       "LO:HI:N (default %(default)s)")
        A.add_aircraft(q)
        q.add_argument("--masses", default=None, type=A.checked_by(MASSES),
                       help="masses in kg (or lb: 1370lb) (default: the aircraft file's)")
        q.add_argument("--temperatures", default="0,20" if kind == "ceiling" else "0", type=A.checked_by(TEMPERATURES),
                       help="ISA temperature offsets in K (default %(default)s)")
        if kind == "ceiling":
            q.add_argument("--ige-hub-height", type=A.checked_by(HUB_HEIGHTS),
                           default=None, metavar="H", help="in ground effect: the main-rotor hub's height above the "
                           "ground, m or ft (default the Bo105's 3.8 m: skids 1 m up)")
            q.add_argument("--grounds", default="oge,ige", choices=("oge", "ige", "oge,ige"), metavar="oge|ige|oge,ige",
                           help="out of and/or in ground effect (default both)")
        else:
            q.add_argument("--speeds", default="50:80:4", type=A.checked_by(SPEEDS), help="speeds in m/s (or kt: 80kt:140kt:4) (default %(default)s)")
        q.add_argument("--workers", type=A.non_negative_int, default=None,
                       help="Dask workers (default: the machine's cores; 0: a plain loop)")
        q.add_argument("--out", type=A.output_folder, default=None, help="write the table (JSON) and a chart here")
        q.add_argument("--quiet", action="store_true", help="no progress bar")
        add_json(q)
        q.set_defaults(fn=cmd_ceiling if kind == "ceiling" else cmd_speed)
