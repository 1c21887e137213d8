"""``heli aircraft check|new|list``: the aircraft files."""
from __future__ import annotations

import re
import sys
from pathlib import Path

from mbs import arguments as A
from mbs.cli import add_json, emit


def cmd_check(args) -> int:
    from mbs import aircraft
    from mbs.aircraft.report import lines

    report = aircraft.check(args.file)
    out = report.summary()
    if not report.ok:
        for line in lines(report):  # every problem, one line each, then the usual error exit
            print(f"heli aircraft check: error: {line}", file=sys.stderr)
        if args.json:
            emit(out, True, [])
        return 2
    emit(out, args.json, lines(report))
    return 0


def cmd_new(args) -> int:
    from mbs import aircraft

    path = args.out or Path(f"{_stem(args.name)}.toml")
    if path.exists() and not args.force:
        raise ValueError(f"{path} exists; choose another --out or add --force to replace it")
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(aircraft.template(args.name))
    emit({"file": str(path), "name": args.name}, args.json,
         [f"wrote {path}: every entry carries the Bo105's value (source TEMPLATE); replace them with your "
          f"aircraft's, then 'heli aircraft check {path}'"])
    return 0


def _stem(name: str) -> str:
    return re.sub(r"\W+", "_", name.strip().lower()).strip("_") or "aircraft"


def cmd_list(args) -> int:
    from mbs import aircraft

    rows = [{"name": n, "aircraft": aircraft.load(n).name, "file": str(p)} for n, p in aircraft.packaged().items()]
    emit({"aircraft": rows}, args.json, [f"{r['name']:8s} {r['aircraft']}  ({r['file']})" for r in rows])
    return 0


def _name(text: str) -> str:
    if not text.strip():
        raise A.Bad("the aircraft needs a name")
    return text.strip()


def register(sub, bench) -> None:
    p = sub.add_parser("aircraft", help="aircraft files: check one, write a template, list the packaged ones")
    asub = p.add_subparsers(dest="aircraft_command", required=True, metavar="ACTION")
    c = asub.add_parser("check", help="every problem of an aircraft file, its derived values and hover figures")
    c.add_argument("file", help="aircraft file, or the name of a packaged aircraft")
    add_json(c)
    c.set_defaults(fn=cmd_check)
    n = asub.add_parser("new", help="write a commented aircraft file to fill in (the Bo105's values as placeholders)")
    n.add_argument("name", type=_name, help="name of the aircraft (e.g. 'My helicopter')")
    n.add_argument("--out", type=A.output_file(".toml"), default=None, help="file to write (default NAME.toml here)")
    n.add_argument("--force", action="store_true", help="replace an existing file")
    add_json(n)
    n.set_defaults(fn=cmd_new)
    s = asub.add_parser("list", help="the packaged aircraft")
    add_json(s)
    s.set_defaults(fn=cmd_list)
