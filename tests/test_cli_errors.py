"""Every user mistake on the ``heli`` command line ends with exit status 2 and one line on
stderr naming the option and the value, before any work starts; never with a traceback.

The table runs through :func:`mbs.cli.main` in this process (the same parser and the same
handling as the ``heli`` script); the commonest mistakes, an unwritable working folder and
a read-only mount also run the installed ``heli`` in a subprocess.
"""
from __future__ import annotations

import os
import shutil
import subprocess
import sys
from pathlib import Path

import pytest

import mbs
from mbs import arguments, cli

HELI = Path(sys.executable).with_name("heli")
PACKAGE_TRIMS = Path(mbs.__file__).resolve().parent / "aircraft" / "data" / "bo105_trim.toml"
PACKAGE_TRIMS_TEXT = PACKAGE_TRIMS.read_text()
NOT_TRIMMABLE = ("demo-rotor", "demo-driven", "structural", "single-blade", "ground-resonance")
TRIMMABLE = ("trimmable scenes: elastic-rotor, elastic-rotor-modal, forward-flight, forward-flight-actuators, "
             "forward-flight-swashplate, ground-run, hover, single-blade-aero")

# (command line; words the message must contain). FILE is an existing file, DIR an existing
# folder with a results.csv in it, PKG the trims file inside the installed package.
CASES = [
    ("simulate structural --steps-per-rev 0", ["--steps-per-rev", "0 must be a whole number >= 1"]),
    ("simulate structural --every 0", ["--every", "0 must be a whole number >= 1"]),
    ("simulate structural --every 1.5", ["--every", "'1.5' is not a whole number"]),
    ("simulate structural --revs 0", ["--revs", "0 must be positive"]),
    ("simulate structural --revs nan", ["--revs", "nan is not a finite number"]),
    ("simulate structural --revs ten", ["--revs", "'ten' is not a number"]),
    ("simulate nosuch", ["SCENE", "'nosuch'", "forward-flight"]),
    ("simulate structural --dtype float16", ["--dtype", "'float16'"]),
    ("simulate structural --backend gpu", ["--backend", "'gpu'"]),
    ("simulate structural --method rk5", ["--method", "'rk5'"]),
    ("simulate forward-flight --aero bogus", ["--aero", "'bogus'", "pitt-peters"]),
    ("simulate hover --altitude 30000", ["--altitude", "30000 m is outside the ISA's range"]),
    ("simulate hover --temperature-offset 99", ["--temperature-offset", "99 K is outside"]),
    ("simulate hover --wind 1,2", ["--wind", "'1,2' is not three finite numbers"]),
    ("trim hover --wind 0,90,0", ["--wind", "within ±60 m/s"]),
    ("simulate structural --altitude 1000", ["scene 'structural'", "does not model"]),
    ("simulate ground-run --turbulence dryden", ["scene 'ground-run'", "needs a free fuselage"]),
    ("simulate ground-run --gust", ["scene 'ground-run'", "gust is a field", "needs a free fuselage"]),
    ("simulate single-blade --ground-effect", ["scene 'single-blade'", "ground_effect acts on the main rotor"]),
    ("simulate hover --turbulence karman", ["--turbulence", "invalid choice: 'karman'"]),
    ("simulate hover --set engine1_failure_time=1", ["'engine1_failure_time' is not a parameter of scene 'hover'",
                                                    "a constant-speed scene has no engine to fail"]),
    ("simulate forward-flight --set turbulence_intensity=10", ["--turbulence dryden|von-karman"]),
    ("simulate hover-engines --set altitude=30000", ["altitude = 30000 m is outside its range [-1000, 20000] m"]),
    ("autorotation hover", ["scene 'hover' cannot autorotate", "scenes: autorotation"]),
    ("autorotation engine-failure", ["scene 'engine-failure' cannot autorotate"]),
    ("autorotation --speeds 2", ["--speeds", "2 m/s is outside the speeds of a steady autorotation", "5 to 90 m/s"]),
    ("autorotation --speeds 30,x", ["--speeds", "'x' is not a number"]),
    ("trim autorotation", ["at a speed that is a state", "heli autorotation"]),
    ("performance ceiling --altitudes 30000", ["--altitudes", "outside the altitudes a sweep takes, -1000 to 20000 m"]),
    ("performance ceiling --altitudes 0:70000ft:3", ["--altitudes", "70000ft (2.134e+04 m) is outside"]),
    ("performance speed --speeds 10:20:x", ["--speeds", "must be LO:HI:N"]),
    ("performance ceiling --grounds none", ["--grounds", "invalid choice: 'none'"]),
    ("performance ceiling --grounds oge --ige-hub-height 3", ["--ige-hub-height 3", "--grounds oge has none"]),
    ("performance speed --masses -3", ["--masses", "-3 kg is outside the masses a sweep takes, 100 to 100000 kg"]),
    ("performance ceiling --temperatures 100", ["--temperatures", "outside the temperatures a sweep takes, -60 to 60 K"]),
    ("simulate structural --out /dev/null/x", ["--out", "'/dev/null/x'", "/dev/null is a file, not a folder"]),
    ("simulate structural --out FILE", ["--out", "FILE", "exists and is not a folder"]),
    ("figures --out /proc/x", ["--out", "'/proc/x'", "/proc is not writable (it accepts no new files)"]),
    ("simulate structural --bogus", ["unrecognized arguments: --bogus"]),
    *[(f"trim {scene}", [f"scene {scene!r} cannot be trimmed", TRIMMABLE]) for scene in NOT_TRIMMABLE],
    ("trim hover --speed nan", ["--speed", "nan is not a finite number"]),
    ("trim hover --climb-rate inf", ["--climb-rate", "inf is not a finite number"]),
    ("trim hover --tol 0", ["--tol", "0 must be positive"]),
    ("trim hover --iterations 0", ["--iterations", "0 must be a whole number >= 1"]),
    ("trim hover --write PKG", ["--write", "PKG", "inside the installed package"]),
    ("trim hover --write trims.txt", ["--write", "'trims.txt' must be a file name ending in .toml"]),
    ("trim hover --write /dev/null/x.toml", ["--write", "'/dev/null/x.toml'", "/dev/null exists and is not a folder"]),
    ("trim hover --write DIR", ["--write", "DIR", "must be a file name ending in .toml"]),
    ("trim hover --write BADTOML", ["--write", "BADTOML", "exists and is not a TOML file", "Expected"]),
    ("fly nosuch", ["SCENE", "'nosuch'", "forward-flight"]),
    ("fly demo-rotor", ["scene 'demo-rotor' cannot be flown", "helicopter scenes", "forward-flight"]),
    ("fly --html fly.txt", ["--html", "'fly.txt' must be a file name ending in .html"]),
    ("fly --html /dev/null/x.html", ["--html", "'/dev/null/x.html'"]),
    ("fly --speeds 0,abc", ["--speeds", "'0,abc' is not a comma-separated list of speeds"]),
    ("fly --speeds 0,500", ["--speeds", "speed 500 m/s is outside [-20, 90] m/s"]),
    ("fly --speeds 10,10", ["--speeds", "'10,10': a speed is given twice"]),
    ("fly ground-run --speeds 0,20", ["--speeds: scene 'ground-run' starts from one state",
                                      "its fuselage is not free"]),
    ("fly structural --speeds 20", ["--speeds: scene 'structural' starts from one state", "it cannot be trimmed"]),
    ("bench fly --steps 10", ["--steps", "10 must be a whole number >= 100"]),
    ("simulate hover --start bad", ["--start", "'bad' is not one of: scene, periodic, periodic:V"]),
    ("simulate hover --start periodic:fast", ["--start", "'fast' is not a speed in m/s"]),
    ("simulate hover --start periodic:inf", ["--start", "the speed must be a finite number of m/s"]),
    ("simulate hover --start scene:10", ["--start", "'scene:10' is not one of"]),
    *[(f"simulate {scene} --start periodic", [f"scene {scene!r} cannot be trimmed", TRIMMABLE])
      for scene in ("structural", "single-blade")],
    ("floquet hover --set lag_damping", ["--set", "'lag_damping'", "NAME=VALUE"]),
    ("floquet hover --sweep omega=20:60", ["--sweep", "'omega=20:60'", "NAME=LO:HI:N"]),
    ("floquet structural", ["scene 'structural' has no periodic solution"]),
    ("floquet hover --out /dev/null/x", ["--out", "'/dev/null/x'"]),
    ("derivatives ground-run", ["scene 'ground-run' has no free fuselage",
                                "forward-flight, forward-flight-actuators, forward-flight-swashplate, hover"]),
    ("derivatives hover --mat A.txt", ["--mat", "'A.txt' must be a file name ending in .mat or .npz"]),
    ("derivatives hover --mat /dev/null/A.mat", ["--mat", "'/dev/null/A.mat'"]),
    ("figures --out FILE", ["--out", "FILE", "exists and is not a folder"]),
    ("fmu build --out /dev/null/x", ["--out", "'/dev/null/x'"]),
    ("fmu build --out /dev/null/x.fmu", ["--out", "'/dev/null/x.fmu'"]),
    ("fmu build --scenes hover,nosuch", ["--scenes", "unknown scene 'nosuch'"]),
    ("fmu build --scenes hover,hover", ["--scenes", "'hover,hover': a scene is named twice"]),
    ("fmu build --scenes single-blade,forward-flight", ["cannot build the FMU of single-blade, forward-flight",
                                                        "the primary scene lacks"]),
    ("fmu bogus", ["ACTION", "'bogus'"]),
    ("demo --revs 0", ["--revs", "0 must be positive"]),
    ("demo --revs -1", ["--revs", "-1 must be positive"]),
    ("demo --revs 0.001", ["--revs", "0.001 is less than one communication step"]),
    ("demo --out /dev/null/x", ["--out", "'/dev/null/x'"]),
    ("demo --out FILE", ["--out", "FILE", "exists and is not a folder"]),
    ("view", ["give a results folder or results.csv, or --simulate SCENE"]),
    ("view DIR/missing", ["no results file at", "missing"]),
    ("view DIR --html /dev/null/x.html", ["--html", "'/dev/null/x.html'"]),
    ("view DIR --html page.htm", ["--html", "'page.htm' must be a file name ending in .html"]),
    ("view --simulate nosuch", ["--simulate", "'nosuch'"]),
    ("view DIR --revs -1", ["--revs", "-1 must be >= 0"]),
    ("view DIR --slow 0", ["--slow", "0 must be positive"]),
    ("view DIR --every 0", ["--every", "0 must be a whole number >= 1"]),
    ("view DIR --serve --port 70000", ["--port", "70000 must be a whole number from 1 to 65535"]),
    ("sweep trim hover --speed 0:10", ["--speed", "'0:10' must be LO:HI:N"]),
    ("sweep trim hover --speed 0:10:0", ["--speed", "'0:10:0'"]),
    ("sweep trim nosuch --speed 0:10:2", ["SCENE", "'nosuch'"]),
    ("sweep trim ground-run --speed 0:20:2", ["cannot sweep 'speed'", "no free fuselage: no flight speed"]),
    ("sweep trim hover --speed 0:10:2 --out /dev/null/x", ["--out", "'/dev/null/x'"]),
    ("sweep simulate hover --param collective", ["--param", "'collective' must be NAME=LO:HI:N"]),
    ("sweep simulate hover --revs 0 --param collective=0.2:0.3:2", ["--revs", "0 must be positive"]),
    ("sweep simulate hover --workers -1 --param collective=0.2:0.3:2", ["--workers", "-1 must be a whole number >= 0"]),
    ("sweep floquet ground-resonance --omega 20:60:30 --set lag_damping", ["--set", "'lag_damping'"]),
    ("bench fmu --revs 0", ["--revs", "0 must be positive"]),
    ("bench fmu --repeats 0", ["--repeats", "0 must be a whole number >= 1"]),
    ("bench stability --revs 0", ["--revs", "0 must be positive"]),
    ("bench stability --scene nosuch", ["--scene", "'nosuch'"]),
    ("bench work-precision --revs -1", ["--revs", "-1 must be positive"]),
    ("bench work-precision --repeats 0", ["--repeats", "0 must be a whole number >= 1"]),
    ("bench work-precision --out FILE", ["--out", "FILE", "exists and is not a folder"]),
    ("bench scaling --out /dev/null/x", ["--out", "'/dev/null/x'"]),
    ("bench scaling --max-instructions 0", ["--max-instructions", "0 must be a whole number >= 1"]),
    ("bench nosuch", ["BENCHMARK", "'nosuch'"]),
    # options that would do nothing, or be overridden
    ("simulate structural --out EMPTY", ["--out", "'' is empty"]),
    ("figures --out EMPTY", ["--out", "'' is empty"]),
    ("floquet hover --out EMPTY", ["--out", "'' is empty"]),
    ("derivatives hover --mat EMPTY", ["--mat", "'' is empty"]),
    ("trim hover --write EMPTY", ["--write", "'' is empty"]),
    ("view DIR --html EMPTY", ["--html", "'' is empty"]),
    ("simulate structural --revs 0.001", ["--revs 0.001 is less than one step", "100 steps per revolution"]),
    ("simulate elastic-rotor --revs 0.001", ["--revs 0.001 is less than one step", "300 steps per revolution"]),
    ("trim ground-run --speed 20", ["--speed 20", "scene 'ground-run' has no free fuselage"]),
    ("floquet ground-run --speed 5", ["--speed 5", "scene 'ground-run' has no free fuselage"]),
    ("trim ground-run --climb-rate 5", ["--climb-rate 5", "scene 'ground-run' has no free fuselage"]),
    ("trim elastic-rotor --speed 0", ["--speed 0", "scene 'elastic-rotor' has no free fuselage"]),
    ("floquet hover --set collective=0.3", ["--set collective", "the trim sets the controls of scene 'hover'", "omega"]),
    ("floquet hover --sweep collective=0.2:0.3:3", ["--sweep collective", "the trim sets the controls"]),
    ("floquet ground-run --set omega=40 --sweep omega=30:40:3", ["--set omega", "--sweep omega", "drop one"]),
    ("floquet hover --set lag_damping=50", ["--set lag_damping", "'lag_damping' is not a parameter of scene 'hover'"]),
    ("floquet hover --set speed=10", ["--set speed", "the flight speed is --speed"]),
    ("floquet ground-run --set omega=80", ["--set omega=80", "outside its range [22.2, 53.3] rad/s"]),
    ("scenes --markdown --json", ["--markdown and --json"]),
    ("view DIR --simulate hover", ["--simulate hover", "would ignore", "give one of them"]),
    ("view DIR --duration 5", ["--duration applies to --serve only"]),
    ("view DIR --wait 3", ["--wait applies to --simulate only"]),
    ("view DIR --port 7001", ["--port applies to --serve or --simulate only"]),
    ("view DIR --serve --html page.html", ["--html applies to the HTML page"]),
    ("view DIR --serve --max-mb 3", ["--max-mb applies to the HTML page"]),
    ("view DIR --serve --no-trace", ["--no-trace applies to the HTML page"]),
    ("view --simulate hover --every 2", ["--every applies to", "with --simulate it would do nothing"]),
    ("view --simulate hover --start 0.1", ["--start applies to"]),
    # --set and --inputs of simulate: names and ranges from the scene's model, before anything is built
    ("simulate hover --set colective=0.3", ["--set colective=0.3", "'colective' is not a parameter of scene 'hover'",
                                            "collective", "speed"]),
    ("simulate hover --set collective=1", ["--set collective=1", "collective = 1 rad is outside its range"]),
    ("simulate hover --set collective", ["--set", "'collective'", "NAME=VALUE"]),
    ("simulate hover --set collective=0.2 --set collective=0.3", ["--set collective is given more than once"]),
    ("simulate ground-run --set speed=20", ["--set speed=20", "scene 'ground-run' has no free fuselage"]),
    ("simulate hover --set speed=200", ["--set speed=200", "[-20, 90] m/s"]),
    ("simulate demo-rotor --set omega=40", ["--set omega=40", "'omega' is not a parameter of scene 'demo-rotor'"]),
    ("simulate hover --inputs DIR/missing.csv", ["--inputs", "missing.csv: no such file"]),
    ("simulate hover --inputs EMPTYFILE", ["--inputs", "is empty"]),
    ("simulate hover --inputs IN_NOTIME", ["--inputs", "the first column must be 'time' (s), not 't'"]),
    ("simulate hover --inputs IN_TEXT", ["--inputs", "line 3, column 'collective': 'high' is not a number"]),
    ("simulate hover --inputs IN_SHORT", ["--inputs", "line 3 has 1 values for 2 columns"]),
    ("simulate hover --inputs IN_BACK", ["--inputs", "line 4: time 0.01 s is before the previous row's 0.02 s"]),
    ("simulate hover --inputs IN_LATE", ["--inputs", "the first row is at time 0.1 s", "give a row at time 0"]),
    ("simulate hover --inputs IN_NAME", ["--inputs", "'colective' is not a parameter of scene 'hover'"]),
    ("simulate hover --inputs IN_RANGE", ["--inputs", "line 4: collective = 0.5 rad is outside its range"]),
    ("simulate hover --inputs IN_SPEED", ["--inputs", "column 'speed'", "--set speed=V"]),
    ("simulate hover --inputs IN_GOOD --set collective=0.3", ["column 'collective' is also given by --set"]),
    # heli view: files that are no run to show, found before any work
    ("view SWEEP", ["is not a results table of 'heli simulate'", "first column is 'parameter'", "sweep"]),
    ("view EMPTYFILE", ["is empty: not a results table"]),
    ("view CORRUPT", ["line 3, column 'fuselage.x': 'nan?' is not a number"]),
    ("view HEADER_ONLY", ["has a header but no rows"]),
    ("view DIVERGED", ["the run stopped before its end", "state became non-finite", "--steps-per-rev"]),
    ("view NAN", ["column 'blade1.flap' is nan at t = 0.01 s"]),
    ("view BADJSON", ["run.json is not valid JSON"]),
    # a run too large for its output limit: size and time said, with the --every that fits
    ("simulate hover --revs 1e5", ["results.csv would be about", "GB", "more than --max-gb 1", "--every"]),
    ("derivatives hover --mat A.MAT.txt", ["--mat", "'A.MAT.txt' must be a file name ending in .mat or .npz"]),
    # a new user's mistakes: each named, with what to do
    ("simulate hover --speed 10", ["unrecognized arguments: --speed 10", "--set speed=V", "heli simulate --help"]),
    ("simulate hover --aicraft lynx", ["unrecognized arguments: --aicraft lynx", "did you mean --aircraft?"]),
    ("trim hover --sped 10", ["did you mean --speed?", "heli trim --help"]),
    ("simulate structural --out A --out B", ["--out is given 2 times; give it once"]),
    ("simulate structural --revs 0.5 --revs 1", ["--revs is given 2 times"]),
    ("simulate structural --every 1000", ["--every 1000 is more than the run's 100 steps", "give --every 10 or less"]),
    ("simulate hover --set collective=15", ["collective = 15 rad is outside", "15 deg would be 0.2618 rad"]),
    ("simulate ground-run --set omega=400", ["omega = 400 rad/s is outside", "400 rpm would be 41.89 rad/s"]),
    ("simulate forward-flight --set speed=10kt", ["'speed=10kt'", "without the unit 'kt'"]),
    ("simulate hover --set collective=0.3,lateral_cyclic=0.01", ["one NAME=VALUE per --set; repeat --set"]),
    ("simulate hover --dtype float32 --backend vm", ["--dtype float32 needs --backend compiled"]),
    ("simulate hover --step-tol 5", ["--step-tol", "must be at most 1 (0.01 is 1 %; 5 would be 500 %)"]),
    ("simulate hover --aero full,none", ["'full' stands alone"]),
    ("simulate hover --aero pitt-peters,pitt-peters", ["switch 'pitt-peters' is named twice"]),
    ("simulate hover --inputs IN_SEMI", ["--inputs", "separate the columns with commas, not ';'"]),
    ("simulate hover --inputs IN_OMEGA", ["column 'omega' changes from 44.4 to 40", "--set omega=VALUE"]),
    ("simulate hover --aircraft lynx.toml", ["lynx.toml: no such file", "did you mean lynx?"]),
    ("simulate hover --aircraft Bo105", ["did you mean bo105?"]),
    ("simulate hover --aircraft mine", ["mine: no such file", "did you mean mine.toml?"]),
    ("simulate structural --start trim", ["--start trim", "scene 'structural' has no periodic trim"]),
    ("simulate structural --out run.csv", ["--out", "'run.csv' is named like a file", "'run'"]),
    ("trim hover --tol 1", ["--tol", "1 is too loose for a periodic solution"]),
    ("trim hover --speed 1e3", ["--speed", "1e3 m/s is outside the flight speeds the model covers", "-20 to 90 m/s"]),
    ("trim hover --speed 100", ["--speed", "100 kt would be 51.4 m/s, or write 100kt"]),
    ("trim hover --speed 60knots", ["--speed", "unknown unit 'knots'", "kt, kn, km/h, ft/s, mph"]),
    ("derivatives hover --speed 200kt", ["--speed", "200kt (102.9 m/s) is outside the flight speeds", "-20 to 90"]),
    ("trim hover --climb-rate 50", ["--climb-rate", "50 m/s is outside the climb rates"]),
    ("loads --speed 300", ["--speed", "300 m/s is outside the flight speeds"]),
    ("loads ground-run --speed 20", ["--speed 20", "scene 'ground-run' has no free fuselage"]),
    ("loads ground-run --sweep 0:20:3", ["--sweep 0:20:3", "no free fuselage, so no flight speed to sweep"]),
    ("loads hover --steps-per-rev 20", ["--steps-per-rev 20", "21/rev", "give --steps-per-rev 50 or more"]),
    ("loads hover --sweep 0:60:1", ["--sweep", "N = 1 gives 0 m/s only, never 60"]),
    ("sweep trim hover --speed 0:70:1", ["--speed", "N = 1 gives LO (0) only, never HI (70)"]),
    ("sweep trim hover --speed 0:200:3", ["--speed", "200 m/s is outside the flight speeds"]),
    ("sweep trim hover --speed 0:10:100000", ["100000 points on one axis", "give fewer"]),
    ("sweep simulate hover --param collective=0.2:0.3:5 --revs 1e9", ["--revs", "give 10000 or fewer"]),
    ("floquet ground-resonance --sweep omega=20:60:1", ["--sweep", "N = 1 gives 20 only, never 60"]),
    ("demo --revs 1e6", ["--revs", "results.csv of about 100 GB", "give 10000 or fewer"]),
    ("cosim --stop 0.0001", ["--stop 0.0001 s is less than one communication step"]),
    ("cosim --stop 1e6", ["--stop", "give 3600 or less"]),
    ("aircraft check DIR", ["is a folder; give an aircraft file"]),
    ("aircraft list bo105", ["unrecognized arguments: bo105", "'heli aircraft check NAME' shows one"]),
    ("scenes hover", ["unrecognized arguments: hover", "'heli scenes' lists every scene and takes none"]),
    ("view RECORD", ["is a run record, not its table", "give the folder of the run"]),
    ("view CHART", ["is not a text table (a binary file, such as a chart)"]),
    ("view --simulate hover --aircraft nosuch.toml", ["--aircraft", "nosuch.toml: no such file"]),
    ("fmu linearize NOTZIP", ["argument fmu", "is not an FMU: an FMU is a zip archive"]),
    ("fmu linearize EMPTYZIP", ["argument fmu", "without a modelDescription.xml"]),
    ("fmu linearize DIR", ["argument fmu", "is a folder; give an .fmu file"]),
    ("", ["the following arguments are required: COMMAND"]),
    ("nosuch", ["COMMAND", "'nosuch'"]),
]


INPUT_TABLES = {  # --inputs files: name -> text
    "IN_GOOD": "time,collective\n0,0.25\n0.1,0.25\n0.1,0.26\n",
    "IN_NOTIME": "t,collective\n0,0.25\n",
    "IN_TEXT": "time,collective\n0,0.25\n0.1,high\n",
    "IN_SHORT": "time,collective\n0,0.25\n0.1\n",
    "IN_BACK": "time,collective\n0,0.25\n0.02,0.25\n0.01,0.26\n",
    "IN_LATE": "time,collective\n0.1,0.25\n",
    "IN_NAME": "time,colective\n0,0.25\n",
    "IN_RANGE": "time,collective\n0,0.25\n\n0.1,0.5\n",  # a blank line 3 does not count as a row
    "IN_SPEED": "time,speed\n0,10\n",
    "IN_SEMI": "time;collective\n0;0.25\n",
    "IN_OMEGA": "time,omega\n0,44.4\n0.5,40\n",
}
RUN_JSON = '{"scene": "hover", "result": "successful"}'
FOLDERS = {  # results folders heli view must refuse: name -> (results.csv, run.json)
    "SWEEP": ("parameter,value,status\nspeed,0,ok\n", None),
    "CORRUPT": ("time,fuselage.x\n0,1\n0.01,nan?\n", RUN_JSON),
    "HEADER_ONLY": ("time,fuselage.x\n", RUN_JSON),
    "DIVERGED": ("time,blade1.flap\n0,0.01\n0.01,0.02\n", '{"scene": "hover", "result": "nonfinite", "message": '
                 '"the state became non-finite (at t = 0.02 s, step 3)"}'),
    "NAN": ("time,blade1.flap\n0,0.01\n0.01,nan\n", RUN_JSON),
    "BADJSON": ("time,blade1.flap\n0,0.01\n", '{"scene": "hover",'),
}


@pytest.fixture
def places(tmp_path, monkeypatch) -> dict[str, str]:
    """Stand-ins of the table: an existing file, a results folder, the package's trims file,
    input tables, results folders that are no run to show, an empty name; the working folder
    is a fresh temporary one."""
    monkeypatch.chdir(tmp_path)
    (tmp_path / "a-file").write_text("not a folder")
    (tmp_path / "empty.csv").write_text("")
    (tmp_path / "trims.toml").write_text("[hover\nspeed = 0\n")
    (tmp_path / "results").mkdir()
    (tmp_path / "results" / "results.csv").write_text("time\n0\n")
    (tmp_path / "record.json").write_text('{"scene": "hover"}')
    (tmp_path / "chart.png").write_bytes(b"\x89PNG\r\n\x1a\n\x00\x00")
    (tmp_path / "notzip.fmu").write_text("not a zip")
    (tmp_path / "mine.toml").write_text("# an aircraft file")
    import zipfile
    with zipfile.ZipFile(tmp_path / "empty.fmu", "w") as z:
        z.writestr("readme.txt", "no model description")
    out = {"FILE": str(tmp_path / "a-file"), "DIR": str(tmp_path / "results"), "PKG": str(PACKAGE_TRIMS), "EMPTY": "",
           "EMPTYFILE": str(tmp_path / "empty.csv"), "BADTOML": str(tmp_path / "trims.toml"),
           "RECORD": str(tmp_path / "record.json"), "CHART": str(tmp_path / "chart.png"),
           "NOTZIP": str(tmp_path / "notzip.fmu"), "EMPTYZIP": str(tmp_path / "empty.fmu")}
    for name, text in INPUT_TABLES.items():
        (tmp_path / f"{name.lower()}.csv").write_text(text)
        out[name] = str(tmp_path / f"{name.lower()}.csv")
    for name, (table, run) in FOLDERS.items():
        folder = tmp_path / name.lower()
        folder.mkdir()
        (folder / "results.csv").write_text(table)
        if run:
            (folder / "run.json").write_text(run)
        out[name] = str(folder)
    return out


def run_main(argv: list[str], capsys) -> tuple[int, str]:
    """``mbs.cli.main(argv)``: (exit status, stderr)."""
    try:
        code = cli.main(argv)
    except SystemExit as exc:
        code = exc.code
    return code, capsys.readouterr().err


def assert_one_line_error(code: int, err: str, words: list[str]) -> None:
    lines = err.strip().splitlines()
    assert code == 2, err
    assert len(lines) == 1 and "error:" in lines[0] and "Traceback" not in err, err
    for w in words:
        assert w in lines[0], f"{w!r} not in {lines[0]!r}"


@pytest.mark.parametrize("line, words", CASES, ids=[c[0] or "(nothing)" for c in CASES])
def test_bad_invocation_is_one_line_and_exit_2(line, words, places, capsys, tmp_path):
    argv = [places.get(w, w) for w in line.split()]
    words = [w for w in words if w]
    before = sorted(p.name for p in tmp_path.iterdir())
    code, err = run_main(argv, capsys)
    assert_one_line_error(code, err, [places.get(w, w) for w in words])
    assert sorted(p.name for p in tmp_path.iterdir()) == before  # nothing written (no out/ folder)
    assert PACKAGE_TRIMS.read_text() == PACKAGE_TRIMS_TEXT  # the package's trims untouched


# -- the commonest mistakes, through the installed script ----------------------------------------------

@pytest.mark.parametrize("line, words", [
    ("simulate structural --steps-per-rev 0", ["argument --steps-per-rev: 0"]),
    ("simulate structural --every 0", ["argument --every: 0"]),
    ("demo --revs 0", ["argument --revs: 0"]),
    ("demo --revs -1", ["argument --revs: -1"]),
    ("demo --out /dev/null/x", ["argument --out: cannot write to '/dev/null/x'"]),
    ("trim structural", [TRIMMABLE]),
])
def test_heli_script_examples(line, words, tmp_path):
    proc = subprocess.run([str(HELI), *line.split()], cwd=tmp_path, capture_output=True, text=True, timeout=120)
    assert_one_line_error(proc.returncode, proc.stderr, words)
    assert proc.stdout == "" and list(tmp_path.iterdir()) == []


def _read_only_mount_works() -> bool:
    if not shutil.which("unshare"):
        return False
    probe = subprocess.run(["unshare", "-rm", "sh", "-c", "mount -t tmpfs -o ro none /mnt && ! touch /mnt/x"],
                           capture_output=True)
    return probe.returncode == 0


@pytest.mark.skipif(not _read_only_mount_works(), reason="no user namespace to mount a read-only file system")
@pytest.mark.parametrize("line, words", [
    ("simulate structural --out RO/out", ["argument --out: cannot write to 'RO/out'", "Read-only file system"]),
    ("figures --out RO", ["argument --out: cannot write to 'RO'", "Read-only file system"]),
    ("fmu build --out RO/x.fmu", ["argument --out: cannot write 'RO/x.fmu'", "Read-only file system"]),
    ("demo", ["argument --out: cannot write to 'out/demo'", "Read-only file system"]),  # default, in a read-only cwd
])
def test_read_only_mount(line, words, tmp_path):
    ro = tmp_path / "ro"
    ro.mkdir()
    script = f'mount -t tmpfs -o ro none "{ro}" && cd "{ro}" && exec "{HELI}" {line.replace("RO", str(ro))}'
    proc = subprocess.run(["unshare", "-rm", "sh", "-c", script], capture_output=True, text=True, timeout=120)
    assert_one_line_error(proc.returncode, proc.stderr, [w.replace("RO", str(ro)) for w in words])


@pytest.mark.skipif(not hasattr(os, "geteuid") or os.geteuid() == 0, reason="root writes into read-only folders")
def test_folder_without_write_permission(tmp_path, capsys):
    locked = tmp_path / "locked"
    locked.mkdir(mode=0o555)
    code, err = run_main(["simulate", "structural", "--out", str(locked / "out")], capsys)
    assert_one_line_error(code, err, ["--out", "is not writable (Permission denied)"])


# -- the checks themselves -------------------------------------------------------------------------

def test_writable_check_creates_nothing(tmp_path):
    target = tmp_path / "a" / "b" / "c"
    assert arguments.output_folder(str(target)) == target
    assert list(tmp_path.iterdir()) == []


def test_trim_write_without_path_goes_to_the_users_data_folder(monkeypatch, tmp_path):
    from mbs import commands

    monkeypatch.setenv("XDG_DATA_HOME", str(tmp_path / "data"))
    args = cli.parser().parse_args(["trim", "hover", "--write"])
    assert args.write == tmp_path / "data" / "rotor-mbs" / "trims.toml" == commands.user_trims()


def test_version(capsys):
    with pytest.raises(SystemExit) as exit_:
        cli.main(["--version"])
    assert exit_.value.code == 0
    out = capsys.readouterr().out
    assert out.startswith("heli: rotor-mbs ") and "CasADi" in out and "Python" in out


def _actions(parser, path=("heli",)):
    """Every (command path, argparse action) of ``parser`` and its subcommands."""
    import argparse

    for action in parser._actions:
        if isinstance(action, argparse._SubParsersAction):
            for name, sub in action.choices.items():
                yield from _actions(sub, (*path, name))
        elif not isinstance(action, argparse._HelpAction):
            yield path, action


def test_every_argument_has_help_and_scene_arguments_list_the_scenes():
    scenes = list(mbs.scenes.all_scenes())
    actions = list(_actions(cli.parser()))
    assert len(actions) > 100
    missing = [f"{' '.join(p)} {a.dest}" for p, a in actions if not (a.help or "").strip()]
    assert missing == []
    scene_args = [(p, a) for p, a in actions if a.metavar == "SCENE"]
    assert len(scene_args) >= 9
    for path, action in scene_args:
        assert list(action.choices) == scenes, path
        assert all(s in action.help for s in scenes), path


def test_scenes_does_not_call_velocities_degrees_of_freedom(capsys):
    assert cli.main(["scenes"]) == 0
    out = capsys.readouterr().out
    dof_lines = [line for line in out.splitlines() if "degrees of freedom" in line]
    assert len(dof_lines) == len(mbs.scenes.all_scenes())
    assert all("_rate" not in line and ".u" not in line for line in dof_lines)
    assert ("  15 degrees of freedom + 4 extra states (main_rotor.inflow, main_rotor.inflow_1s, main_rotor.inflow_1c, "
            "tail_rotor.inflow)") in out
    assert "  16 position coordinates: fuselage.x, fuselage.y, fuselage.z, fuselage.qw" in out


def test_a_flight_speed_may_carry_its_unit(capsys):
    """``--speed 60kt`` (or ``60 kt``, ``100km/h``, ``ft/s``, ``mph``) is converted to m/s; a bare
    number stays m/s; the trim of ``--speed 20kt`` is the trim at 10.28888 m/s."""
    import json

    from mbs import arguments as A

    for text, ms in (("60kt", 60 * 0.514444), ("60 KT", 60 * 0.514444), ("100km/h", 100 / 3.6), ("30", 30.0),
                     ("-10 ft/s", -3.048), ("50 mph", 50 * 0.44704), ("12 m/s", 12.0), ("40kn", 40 * 0.514444)):
        assert A.flight_speed(text) == pytest.approx(ms, rel=1e-15), text
    assert cli.main(["trim", "hover", "--speed", "20kt", "--json", "--quiet"]) == 0
    assert json.loads(capsys.readouterr().out)["speed"] == pytest.approx(20 * 0.514444, rel=1e-15)
