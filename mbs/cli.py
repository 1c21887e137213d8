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
                   "mbs.bench.modal", "mbs.bench.loops", "mbs.validate.commands", "mbs.drivetrain.commands",
                   "mbs.performance.commands", "mbs.bench.drivetrain", "viewer.fly.commands")


_json_out = None
"""The real stdout while a ``--json`` command runs (:func:`main` sends the rest of stdout to stderr)."""
_prog = "heli"


def emit(result: dict, as_json: bool, lines: list[str]) -> None:
    """Print ``lines``; with ``as_json`` print them on stderr and ``result`` as one JSON object on stdout."""
    _clear_bars()
    for line in lines:
        print(line, file=sys.stderr if as_json else sys.stdout)
    if as_json:
        print(json.dumps(result, default=_jsonable), file=_json_out or sys.stdout, flush=True)


def warn(message: str) -> None:
    """``heli <command>: warning: <message>`` on stderr."""
    _clear_bars()
    print(f"{_prog}: warning: {message}", file=sys.stderr, flush=True)


def say(line: str) -> None:
    """A line about the work (what it starts from, what it stored) on stderr: stdout is the result's."""
    _clear_bars()
    print(line, file=sys.stderr, flush=True)


def _clear_bars() -> None:
    from mbs._progress import clear

    clear()


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
    ap = Parser(prog="heli", description="Helicopter multibody simulation: any single-main-rotor helicopter from an "
                "aircraft file ('heli aircraft new NAME'); the Bo105 (the default), the Lynx and the Puma come with it.")
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
        _clear_bars()
        print(self.format(record), file=sys.stderr, flush=True)


def _show_messages(quiet: bool) -> None:
    """Messages of the ``mbs`` logger on stderr: long builds (INFO) unless ``quiet``, cache
    repairs (WARNING) always."""
    log = logging.getLogger("mbs")
    if not any(isinstance(h, _Stderr) for h in log.handlers):
        log.addHandler(_Stderr())
    log.setLevel(logging.WARNING if quiet else logging.INFO)


HINTS = {("simulate", "--speed"): "the initial speed of a run is --set speed=V (m/s)",
         ("simulate", "--climb-rate"): "a run has no climb-rate option; 'heli trim SCENE --climb-rate W' trims a climb"}
"""What to say of an option that a command does not have but another does: (command, option) -> hint."""


def _chosen(ap: argparse.ArgumentParser, args) -> argparse.ArgumentParser:
    """The (sub)parser of the command that ``args`` names, e.g. that of ``heli sweep trim``."""
    for action in ap._actions:
        if isinstance(action, argparse._SubParsersAction):
            name = getattr(args, action.dest, None)
            if name in action.choices:
                return _chosen(action.choices[name], args)
    return ap


def _unknown(ap: argparse.ArgumentParser, args, extras: list[str]) -> None:
    """Refuse arguments the command does not take, on the command's own parser (its help page),
    with the hint of :data:`HINTS` or the closest option it has."""
    import difflib

    sub = _chosen(ap, args)
    flag = next((e.split("=")[0] for e in extras if e.startswith("--")), None)
    options = [o for a in sub._actions for o in a.option_strings if o.startswith("--")]
    command = " ".join(str(getattr(args, k)) for k in ("command", "aircraft_command") if getattr(args, k, None))
    hint = HINTS.get((getattr(args, "command", None), flag)) or (WORDS.get(command) if flag is None else None)
    close = difflib.get_close_matches(flag, options, n=1, cutoff=0.75) if flag else []
    if hint is None and close:
        hint = f"did you mean {close[0]}?"
    sub.error(f"unrecognized arguments: {' '.join(extras)}" + (f"; {hint}" if hint else ""))


WORDS = {"scenes": "'heli scenes' lists every scene and takes none; 'heli scenes --json' gives their details",
         "aircraft list": "'heli aircraft list' takes no name; 'heli aircraft check NAME' shows one"}
"""What to say of words a command does not take: command -> hint."""


def _repeated(ap: argparse.ArgumentParser, args, argv: list[str]) -> None:
    """Refuse a single-valued option given more than once (argparse keeps the last silently)."""
    sub = _chosen(ap, args)
    single = [a for a in sub._actions if a.option_strings and isinstance(a, argparse._StoreAction)]
    counts: dict[str, int] = {}
    for token in argv:
        if not token.startswith("--"):
            continue
        name = token.split("=", 1)[0]
        match = [a for a in single if name in a.option_strings] or \
            [a for a in single if any(o.startswith(name) for o in a.option_strings)]
        if len(match) == 1:
            flag = match[0].option_strings[-1]
            counts[flag] = counts.get(flag, 0) + 1
    twice = [f for f, n in counts.items() if n > 1]
    if twice:
        sub.error(f"{twice[0]} is given {counts[twice[0]]} times; give it once (only the last would count)")


def main(argv: list[str] | None = None) -> int:
    ap = parser()
    argv = sys.argv[1:] if argv is None else list(argv)
    args, extras = ap.parse_known_args(argv)
    if extras:
        _unknown(ap, args, extras)
    _repeated(ap, args, argv)
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
        _clear_bars()
        print(f"{prog}: error: this needs the Python package {exc.name!r}, which is not installed "
              f"(pip install {exc.name.split('.')[0]})", file=sys.stderr)
        return 2
    except USER_ERRORS as exc:
        _clear_bars()
        text = exc.args[0] if isinstance(exc, KeyError) and exc.args else exc
        print(f"{prog}: error: {text}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        _clear_bars()
        print(f"{prog}: interrupted", file=sys.stderr)
        return 130
    finally:
        _json_out = None


if __name__ == "__main__":
    sys.exit(main())
