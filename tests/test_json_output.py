"""``--json`` is pipe-clean: stdout is exactly one JSON object, every human-readable line (and
anything a library prints) goes to stderr. ``heli simulate hover --json | python -m json.tool``
runs through a real pipe; the other commands are parsed from stdout whole, here or in their
own test files (:data:`ELSEWHERE`), and every command with ``--json`` is in one of the lists."""
from __future__ import annotations

import argparse
import json
import subprocess
import sys
from pathlib import Path

import pytest

from mbs import cli

HELI = Path(sys.executable).with_name("heli")

HERE = {  # command -> arguments of a cheap run (OUT: a fresh folder, RUN: a simulate results folder)
    "heli scenes": ["scenes"],
    "heli simulate": ["simulate", "hover", "--revs", "0.2", "--out", "OUT"],
    "heli trim": ["trim", "hover", "--steps-per-rev", "50"],
    "heli view": ["view", "RUN", "--html", "OUT/page.html"],
    "heli aircraft check": ["aircraft", "check", "lynx"],
    "heli aircraft new": ["aircraft", "new", "My rotorcraft", "--out", "OUT/my.toml"],
    "heli aircraft list": ["aircraft", "list"],
    "heli sweep simulate": ["sweep", "simulate", "hover", "--revs", "0.1", "--param", "collective=0.2:0.25:2",
                            "--workers", "0", "--out", "OUT"],
    "heli bench stability": ["bench", "stability", "--scene", "demo-rotor", "--revs", "5", "--case", "none"],
    "heli autorotation": ["autorotation", "--speeds", "30"],
    "heli performance speed": ["performance", "speed", "--speeds", "60", "--altitudes", "0", "--workers", "0",
                               "--quiet", "--out", "OUT"],
    "heli performance ceiling": ["performance", "ceiling", "--altitudes", "0", "--temperatures", "0", "--grounds",
                                 "oge", "--workers", "0", "--quiet"],
}
ELSEWHERE = {  # command -> the test that parses its whole stdout as one JSON object
    "heli validate": "tests/test_validate_published.py::test_command_json_is_one_object",
    "heli floquet": "tests/test_floquet.py::test_hover_chart_and_table_in_the_fixed_frame",
    "heli derivatives": "tests/test_derivatives.py::test_heli_derivatives_prints_the_table_and_writes_matlab",
    "heli figures": "tests/test_bo105.py::test_heli_figures_writes_both_figures",
    "heli sweep trim": "tests/test_sweep.py::test_heli_sweep_trim_writes_the_table_and_charts_and_reports_json",
    "heli sweep floquet": "the fan plot's sweep (slow); pipe-clean by test_a_command_that_prints_stays_pipe_clean",
    "heli bench speed": "slow; pipe-clean by test_a_command_that_prints_stays_pipe_clean",
    "heli bench work-precision": "tests/test_work_precision.py (quick fixture)",
    "heli bench scaling": "slow; pipe-clean by test_a_command_that_prints_stays_pipe_clean",
    "heli bench fmu": "fresh-process FMU runs (slow); pipe-clean by test_a_command_that_prints_stays_pipe_clean",
    "heli fmu build": "an FMU build (slow); pipe-clean by test_a_command_that_prints_stays_pipe_clean",
    "heli fmu linearize": "tests/test_fmu_derivatives.py::test_heli_fmu_linearize_command",
    "heli bench fmu-me": "tests/test_fmu_derivatives.py::test_heli_bench_fmu_me_reports_exact_and_differenced_jacobians",
    "heli demo": "tests/test_fmu.py (the demo run); pipe-clean by test_a_command_that_prints_stays_pipe_clean",
    "heli loads": "tests/test_loads_rotor.py::test_heli_loads_reports_tables_and_writes_its_files",
    "heli bench loads": "a loads sweep (slow); pipe-clean by test_a_command_that_prints_stays_pipe_clean",
    "heli cosim": "the 60 s co-simulation (slow); pipe-clean by test_a_command_that_prints_stays_pipe_clean",
    "heli bench cosim": "repeated co-simulations (slow); pipe-clean by test_a_command_that_prints_stays_pipe_clean",
    "heli bench modal": "three rotors' trims and Floquet analyses (slow); pipe-clean by "
                        "test_a_command_that_prints_stays_pipe_clean",
    "heli bench loops": "five forward-flight models compiled (slow); pipe-clean by "
                        "test_a_command_that_prints_stays_pipe_clean",
    "heli validate": "tests/test_validate_published.py::test_command_json_is_one_object",
    "heli bench drivetrain": "five forward-flight models compiled (slow); pipe-clean by "
                             "test_a_command_that_prints_stays_pipe_clean",
    "heli fly": "tests/test_fly.py::test_heli_fly_writes_a_self_contained_page",
    "heli bench fly": "Chromium runs of four WebAssembly builds (slow); pipe-clean by "
                      "test_a_command_that_prints_stays_pipe_clean",
}


def json_commands(parser, path=("heli",)):
    """Every command (as ``"heli a b"``) that has a ``--json`` option."""
    for action in parser._actions:
        if isinstance(action, argparse._SubParsersAction):
            for name, sub in action.choices.items():
                yield from json_commands(sub, (*path, name))
        elif action.dest == "json":
            yield " ".join(path)


def test_every_json_command_is_checked_here_or_elsewhere():
    assert sorted(json_commands(cli.parser())) == sorted([*HERE, *ELSEWHERE])


@pytest.fixture(scope="module")
def run_folder(tmp_path_factory) -> Path:
    from mbs.simulate import simulate, write

    out = tmp_path_factory.mktemp("run")
    write(simulate("hover", 0.2), out)
    return out


@pytest.mark.parametrize("command", sorted(HERE))
def test_stdout_is_one_json_object(command, run_folder, tmp_path, capsys, monkeypatch):
    monkeypatch.chdir(tmp_path)
    argv = [str(run_folder) if a == "RUN" else a.replace("OUT", str(tmp_path / "out")) for a in HERE[command]]
    code = cli.main([*argv, "--json"])
    captured = capsys.readouterr()
    assert code in (0, 1), captured.err
    assert isinstance(json.loads(captured.out), dict)  # the whole of stdout: one object, nothing else
    assert captured.out.count("\n") == 1
    assert captured.err.strip()  # the human-readable lines are still there, on stderr


def test_heli_simulate_json_through_a_pipe(tmp_path):
    """The issue's example, in a shell: ``heli simulate hover --json | python -m json.tool``."""
    proc = subprocess.run(f'"{HELI}" simulate hover --revs 0.2 --out out --json | "{sys.executable}" -m json.tool',
                          shell=True, cwd=tmp_path, capture_output=True, text=True, timeout=300)
    assert proc.returncode == 0, proc.stderr
    assert json.loads(proc.stdout)["scene"] == "hover"
    assert "wrote out/results.csv" in proc.stderr


def test_a_command_that_prints_stays_pipe_clean(capsys, monkeypatch):
    """Whatever a command or a library prints while a --json command runs goes to stderr."""
    def noisy(args) -> int:
        print("a library's message")
        print("a tool's log line", file=sys.stdout, flush=True)
        cli.emit({"answer": 42}, args.json, ["the human-readable report"])
        return 0

    parser = cli.parser()
    monkeypatch.setattr(cli, "parser", lambda: parser)
    args = parser.parse_args(["scenes", "--json"])
    monkeypatch.setattr(argparse.ArgumentParser, "parse_args", lambda self, argv=None: args)
    monkeypatch.setattr(argparse.ArgumentParser, "parse_known_args", lambda self, argv=None, namespace=None: (args, []))
    args.fn = noisy
    assert cli.main(["scenes", "--json"]) == 0
    captured = capsys.readouterr()
    assert json.loads(captured.out) == {"answer": 42}
    assert captured.err.splitlines() == ["a library's message", "a tool's log line", "the human-readable report"]


def test_every_command_of_an_aircraft_takes_quiet():
    """A new user's '--quiet' worked for trim, sweep and validate and was refused by derivatives:
    each command that trims or runs an aircraft's model takes it."""
    def commands(parser, path=("heli",)):
        for action in parser._actions:
            if isinstance(action, argparse._SubParsersAction):
                for name, sub in action.choices.items():
                    yield from commands(sub, (*path, name))
            elif action.dest == "aircraft" and path[1] not in ("bench", "aircraft", "fmu", "demo", "cosim", "fly",
                                                                "scenes", "view"):
                yield " ".join(path), parser

    found = dict(commands(cli.parser()))
    assert {"heli trim", "heli derivatives", "heli autorotation", "heli validate"} <= set(found), sorted(found)
    assert [c for c, p in found.items() if not any(a.dest == "quiet" for a in p._actions)] == []
