"""The ``heli`` command (also ``python -m mbs``).

Each area registers its subcommands from its own module (``register(sub, bench)``), so the
core, the benchmarks, the FMU and the viewer stay independent. Every subcommand prints
human-readable lines; with ``--json`` the last line on stdout is one JSON object.
Progress bars go to stderr.
"""
from __future__ import annotations

import argparse
import importlib
import json
import sys

COMMAND_MODULES = ("mbs.commands", "mbs.bench.commands", "mbs.bench.stability", "mbs.bench.work_precision",
                   "mbs.bench.scaling", "mbs.sweep.commands", "fmu.commands", "viewer.commands")


def emit(result: dict, as_json: bool, lines: list[str]) -> None:
    """Print ``lines``; with ``as_json`` also one JSON object as the last line."""
    for line in lines:
        print(line)
    if as_json:
        print(json.dumps(result, default=_jsonable))


def _jsonable(o):
    if hasattr(o, "tolist"):
        return o.tolist()
    return str(o)


def add_json(p: argparse.ArgumentParser) -> None:
    p.add_argument("--json", action="store_true", help="print one machine-readable JSON object last")


def parser() -> argparse.ArgumentParser:
    ap = argparse.ArgumentParser(prog="heli", description="Rotor multibody simulation (Bo105).")
    sub = ap.add_subparsers(dest="command", required=True, metavar="COMMAND")
    bench = sub.add_parser("bench", help="benchmarks (speed, accuracy, stability, scaling)")
    bench_sub = bench.add_subparsers(dest="bench", required=True, metavar="BENCHMARK")
    for name in COMMAND_MODULES:
        try:
            module = importlib.import_module(name)
        except ModuleNotFoundError as exc:
            if exc.name in (name, name.split(".")[0]):
                continue
            raise
        module.register(sub, bench_sub)
    return ap


def main(argv: list[str] | None = None) -> int:
    args = parser().parse_args(argv)
    try:
        return int(args.fn(args) or 0)
    except (ValueError, RuntimeError, FileNotFoundError, KeyError) as exc:
        print(f"heli: error: {exc}", file=sys.stderr)
        return 2


if __name__ == "__main__":
    sys.exit(main())
