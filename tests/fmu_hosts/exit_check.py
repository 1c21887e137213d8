"""Run the pythonfmu FMU from C hosts linked to libpython, each run a fresh process, and count
the runs that do not exit cleanly (the exit test of the FMU's front end, ``fmu/pythonfmu/shim``).

- :func:`compile_python_host`: ``python_host.c`` compiled against this interpreter's libpython;
- :func:`runs`: ``n`` fresh runs of one mode (``embed``: the host starts Python itself;
  ``linked``: pythonfmu's library starts it), each checked for exit code 0 and complete output.
"""
from __future__ import annotations

import os
import site
import subprocess
import sysconfig
import zipfile
from pathlib import Path

import fmu

HERE = Path(__file__).resolve().parent
PROJECT = Path(fmu.__file__).resolve().parents[1]  # the folder that holds fmu/ and mbs/


def compile_python_host(dest: Path) -> Path:
    """Compile ``python_host.c`` into ``dest``, linked to this interpreter's shared libpython."""
    from mbs.backends.compiled import find_compiler

    from fmu.native.build import fmi_headers_dir

    libdir, version = sysconfig.get_config_var("LIBDIR"), sysconfig.get_config_var("VERSION")
    cmd = [find_compiler(), "-O2", "-I", str(fmi_headers_dir()), "-I", sysconfig.get_paths()["include"],
           str(HERE / "python_host.c"), "-o", str(dest), f"-L{libdir}", f"-Wl,-rpath,{libdir}",
           f"-lpython{version}{sysconfig.get_config_var('ABIFLAGS') or ''}", "-ldl"]
    proc = subprocess.run(cmd, capture_output=True, text=True)
    if proc.returncode:
        raise RuntimeError(f"compiling the Python-linked C host failed ({' '.join(cmd)}):\n{proc.stderr[-3000:]}")
    return dest


def unzip(fmu: Path, folder: Path) -> dict:
    """Extract ``fmu`` into ``folder``; the host's arguments: library, GUID, resources URI."""
    from fmpy import read_model_description

    with zipfile.ZipFile(fmu) as z:
        z.extractall(folder)
    md = read_model_description(str(fmu))
    ident = md.coSimulation.modelIdentifier
    return {"so": str(folder / "binaries" / "linux64" / f"{ident}.so"), "guid": md.guid,
            "uri": (folder / "resources").as_uri(), "vr": next(v.valueReference for v in md.modelVariables
                                                                if v.name == "blade1.flap")}


def runs(host: Path, fmu: dict, mode: str, n: int, steps: int = 5, dt: float = 1e-3) -> dict:
    """``n`` fresh runs of ``host`` in ``mode``: exit codes (counts) and the failures' stderr."""
    env = {**os.environ, "PYTHONPATH": os.pathsep.join([*site.getsitepackages(), str(PROJECT)])}
    codes: dict[int, int] = {}
    failures = []
    for _ in range(n):
        proc = subprocess.run([str(host), mode, fmu["so"], fmu["guid"], fmu["uri"], str(steps), repr(dt),
                               str(fmu["vr"])], capture_output=True, text=True, env=env, timeout=120)
        complete = len(proc.stdout.splitlines()) == steps
        code = proc.returncode if complete or proc.returncode else -1000
        codes[code] = codes.get(code, 0) + 1
        if code:
            failures.append(proc.stderr[-800:])
    return {"codes": codes, "failures": failures[:3]}
