"""The ``heli`` command (also ``python -m mbs``).

Each area registers its subcommands from its own module (``register(sub, bench)``), so the
core, the benchmarks, the FMU and the viewer stay independent. Every subcommand prints
human-readable lines; with ``--json`` stdout is exactly one JSON object (``heli ... --json |
python -m json.tool`` works) and every human-readable line goes to stderr. Progress bars and
warnings (``heli <command>: warning: <what, and what to do>``) go to stderr.

Every argument is checked while the command line is parsed (types in :mod:`mbs.arguments`),
before any work starts. A user's mistake, found then or later, ends with one line on stderr,
``heli <command>: error: <what, naming the option and the value>``, and exit status 2;
never with a traceback.
"""
from __future__ import annotations

import argparse
import contextlib
import importlib
import json
import logging
import sys

COMMAND_MODULES = ("mbs.commands", "mbs.aircraft.commands", "mbs.bench.commands", "mbs.bench.stability", "mbs.bench.work_precision",
                   "mbs.bench.scaling", "mbs.sweep.commands", "fmu.commands", "viewer.commands", "mbs.loads.commands",
                   "mbs.bench.modal", "mbs.bench.loops", "mbs.validate.commands", "viewer.fly.commands")


_json_out = None
"""The real stdout while a ``--json`` command runs (:func:`main` sends the rest of stdout to stderr)."""
_prog = "heli"


def emit(result: dict, as_json: bool, lines: list[str]) -> None:
    """Print ``lines``; with ``as_json`` print them on stderr and ``result`` as one JSON object on stdout."""
    for line in lines:
        print(line, file=sys.stderr if as_json else sys.stdout)
    if as_json:
        print(json.dumps(result, default=_jsonable), file=_json_out or sys.stdout, flush=True)


def warn(message: str) -> None:
    """``heli <command>: warning: <message>`` on stderr."""
    print(f"{_prog}: warning: {message}", file=sys.stderr, flush=True)


def _jsonable(o):
    if hasattr(o, "tolist"):
        return o.tolist()
    return str(o)


def add_json(p: argparse.ArgumentParser) -> None:
    p.add_argument("--json", action="store_true",
                   help="print one machine-readable JSON object on stdout (the human-readable lines go to stderr)")


class Parser(argparse.ArgumentParser):
    """argparse's parser with a one-line error: the message and where to find the usage
    (subcommand parsers are of this class too)."""

    def error(self, message: str):
        self.exit(2, f"{self.prog}: error: {message} (see '{self.prog} --help')\n")


def version() -> str:
    """``rotor-mbs <version>`` with the versions of Python and CasADi."""
    import importlib.metadata as md
    import platform

    def of(dist: str) -> str:
        try:
            return md.version(dist)
        except md.PackageNotFoundError:
            return "not installed"

    return f"rotor-mbs {of('rotor-mbs')} (Python {platform.python_version()}, CasADi {of('casadi')})"


def parser() -> argparse.ArgumentParser:
    ap = Parser(prog="heli", description="Rotor multibody simulation (Bo105).")
    ap.add_argument("--version", action="version", version=f"%(prog)s: {version()}",
                    help="print the version of rotor-mbs, Python and CasADi and exit")
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


USER_ERRORS = (ValueError, RuntimeError, OSError, KeyError, argparse.ArgumentTypeError)
"""What a command raises for a bad input or setting (a bad scene, parameter or file, an
unwritable folder, a missing compiler): reported in one line, exit status 2."""


class _Stderr(logging.Handler):
    """Log records of the ``mbs`` package as plain lines on the current ``sys.stderr``."""

    def emit(self, record: logging.LogRecord) -> None:
        print(self.format(record), file=sys.stderr, flush=True)


def _show_messages(quiet: bool) -> None:
    """Messages of the ``mbs`` logger on stderr: long builds (INFO) unless ``quiet``, cache
    repairs (WARNING) always."""
    log = logging.getLogger("mbs")
    if not any(isinstance(h, _Stderr) for h in log.handlers):
        log.addHandler(_Stderr())
    log.setLevel(logging.WARNING if quiet else logging.INFO)


def main(argv: list[str] | None = None) -> int:
    ap = parser()
    args = ap.parse_args(argv)
    _show_messages(bool(getattr(args, "quiet", False)))
    global _prog, _json_out
    prog = _prog = " ".join(["heli", *(getattr(args, k) for k in ("command", "bench", "fmu_command", "aircraft_command",
                                                                   "kind") if isinstance(getattr(args, k, None), str))])
    as_json = bool(getattr(args, "json", False))
    _json_out = sys.stdout if as_json else None
    try:
        with contextlib.redirect_stdout(sys.stderr) if as_json else contextlib.nullcontext():
            return int(args.fn(args) or 0)
    except ModuleNotFoundError as exc:  # an optional package this command needs
        print(f"{prog}: error: this needs the Python package {exc.name!r}, which is not installed "
              f"(pip install {exc.name.split('.')[0]})", file=sys.stderr)
        return 2
    except USER_ERRORS as exc:
        text = exc.args[0] if isinstance(exc, KeyError) and exc.args else exc
        print(f"{prog}: error: {text}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        print(f"{prog}: interrupted", file=sys.stderr)
        return 130
    finally:
        _json_out = None


if __name__ == "__main__":
    sys.exit(main())
