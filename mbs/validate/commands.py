"""``heli validate``: the model against published trims, derivatives and eigenvalues."""
from __future__ import annotations

import argparse

from mbs import arguments as A


def data_file(text: str):
    """Type: a validation file (TOML or CSV) or a packaged validation's name, read and checked;
    its first problem, naming the entry, refuses it."""
    from mbs.validate.data import ValidationError
    from mbs.validate.files import load

    try:
        return load(text)
    except ValidationError as exc:
        raise argparse.ArgumentTypeError(str(exc)) from None


def cmd_validate(args) -> int:
    from mbs._progress import Progress
    from mbs.cli import emit
    from mbs.validate import charts, report
    from mbs.validate.runner import validate

    v = args.data
    res = validate(v, aircraft=args.aircraft, aero=args.aero, method=args.method, steps_per_rev=args.steps_per_rev,
                   backend=args.backend, progress=Progress(f"validate {v.name}", not args.quiet))
    out, lines = report.summary(res), report.lines(res)
    if not args.no_charts:
        out["files"] = [str(p) for p in charts.write_all(res, args.out / v.name)]
        lines += [f"wrote {p}" for p in out["files"]]
    emit(out, args.json, lines)
    return 1 if args.check and not res.all_within else 0


def register(sub, bench) -> None:
    from mbs.cli import add_json
    from mbs.commands import _aero, _backend, _quiet, _steps_per_rev
    from mbs.validate.files import packaged

    p = sub.add_parser("validate", help="the model against published trims, derivatives and eigenvalues: tables, "
                                        "differences and charts, with the data's conventions")
    p.add_argument("data", type=data_file, metavar="DATA",
                   help="validation file (.toml or .csv: published values with units, sources and tolerances; "
                        f"docs/validation.md) or a packaged one: {', '.join(packaged())}")
    p.add_argument("--aircraft", metavar="FILE", type=A.aircraft_file, default=None,
                   help="aircraft file (or a packaged aircraft's name) to validate instead of the one the data "
                        "file names")
    p.add_argument("--out", type=A.output_folder, default="out/validate",
                   help="folder of the charts (a subfolder per validation; default out/validate)")
    p.add_argument("--no-charts", action="store_true", help="tables only, no charts")
    p.add_argument("--check", action="store_true",
                   help="exit status 1 when a point with a tolerance, or an eigenvalue, falls outside it")
    p.add_argument("--method", choices=("rk4", "rk8"), default="rk4", help="fixed-step method (default rk4)")
    _steps_per_rev(p)
    _backend(p)
    _aero(p)
    _quiet(p)
    add_json(p)
    p.set_defaults(fn=cmd_validate)
