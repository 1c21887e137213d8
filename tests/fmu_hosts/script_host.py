"""Compile and run the scripted C host (``script_host.c``): an FMI 2.0 and 3.0 master written for
the tests, that calls an FMU's standard functions only, one command per line, and answers one
JSON object per command (status, wall time, values, the messages the FMU logged).

- :func:`compile_host`: for this machine, or cross-built (mingw for Windows, gcc for ARM), or
  linked to this interpreter's libpython for the pythonfmu FMU (``python=True``);
- :func:`run`: a script (list of command lines) in a fresh process, optionally under a runner
  (``["wine"]``, ``["qemu-aarch64", "-L", sysroot]``);
- :func:`fmu_facts`: what a script needs from an FMU's ``modelDescription.xml``.
"""
from __future__ import annotations

import json
import os
import site
import subprocess
import sysconfig
import zipfile
from pathlib import Path

import fmu

HERE = Path(__file__).resolve().parent
PROJECT = Path(fmu.__file__).resolve().parents[1]  # the folder that holds fmu/ and mbs/
SOURCE = HERE / "script_host.c"
PLATFORM_HEADER_DIR = Path(fmu.__file__).resolve().parent / "native"  # host_platform.h, shared with host.c


def compile_host(dest: Path, platform=None, python: bool = False) -> Path:
    """Compile ``script_host.c`` into ``dest`` for ``platform`` (a :class:`fmu.native.platforms.Platform`,
    default this machine), FMI headers from the installed fmpy; ``python``: linked to this
    interpreter's libpython, starting Python itself (for the pythonfmu FMU)."""
    from fmu.native import platforms
    from fmu.native.build import fmi_headers_dir

    platform = platform or platforms.LINUX
    cc = platforms.compiler(platform)
    if cc is None:
        raise RuntimeError(f"no C compiler for {platform.fmi3}: install {platform.compiler}")
    static = ["-static"] if platform is platforms.WINDOWS else []
    extra = []
    if python:
        libdir, version = sysconfig.get_config_var("LIBDIR"), sysconfig.get_config_var("VERSION")
        extra = ["-DSCRIPT_HOST_PYTHON", "-I", sysconfig.get_paths()["include"], f"-L{libdir}", f"-Wl,-rpath,{libdir}",
                 f"-lpython{version}{sysconfig.get_config_var('ABIFLAGS') or ''}"]
    cmd = [cc, "-O2", "-std=c99", "-D_POSIX_C_SOURCE=200809L", "-I", str(fmi_headers_dir()), "-I", str(PLATFORM_HEADER_DIR), str(SOURCE), "-o",
           str(dest), *static, *extra, *platforms.HOST_LIBS[platform.fmi3], "-lm"]
    proc = subprocess.run(cmd, capture_output=True, text=True)
    if proc.returncode:
        raise RuntimeError(f"compiling the scripted C host failed ({' '.join(cmd)}):\n{proc.stderr[-3000:]}")
    return dest


def python_env() -> dict:
    """The environment of a host linked to libpython: numpy and the project importable."""
    return {**os.environ, "PYTHONPATH": os.pathsep.join([*site.getsitepackages(), str(PROJECT)])}


def run(host: Path, lines: list[str], runner=(), env: dict | None = None, timeout: float = 600,
        cwd: Path | None = None) -> list[dict]:
    """Run the script ``lines`` in a fresh host process; one result per command (see ``script_host.c``).
    Raises RuntimeError when the host dies or answers fewer results than commands."""
    commands = [line for line in lines if line.strip() and not line.lstrip().startswith("#")]
    proc = subprocess.run([*runner, str(host)], input=("\n".join(commands) + "\n").encode(), capture_output=True, timeout=timeout,
                          env=env, cwd=cwd)
    out = proc.stdout.decode(errors="replace").splitlines()
    results = [json.loads(line) for line in out if line.startswith("{")]
    if proc.returncode or len(results) != len(commands):
        raise RuntimeError(f"the scripted host ended with {proc.returncode} after {len(results)} of {len(commands)} "
                           f"commands:\n{proc.stderr.decode(errors='replace')[-3000:]}")
    return results


def fmu_facts(fmu: str | Path, folder: Path, platform: str | None = None) -> dict:
    """Unzip ``fmu`` into ``folder``; its FMI version, GUID (instantiation token), library
    (``platform``: a binaries/ folder, default this machine's), resources, value references, kinds of
    variables and XML start values of its inputs and parameters (as the host writes them)."""
    from fmpy import read_model_description

    with zipfile.ZipFile(fmu) as z:
        z.extractall(folder)
    md = read_model_description(str(fmu))
    v3 = md.fmiVersion.startswith("3")
    interface = md.coSimulation or md.modelExchange
    suffix = ".dll" if platform and "win" in platform else ".so"
    platform = platform or ("x86_64-linux" if v3 else "linux64")
    variables = md.modelVariables
    starts = {v.name: v.start for v in variables if v.causality in ("input", "parameter") and v.start is not None}
    return {"folder": str(folder), "version": 3 if v3 else 2, "guid": md.guid, "resources": (Path(folder) / "resources").as_uri() if not v3
            else str(Path(folder) / "resources") + os.sep,
            "library": str(Path(folder) / "binaries" / platform / f"{interface.modelIdentifier}{suffix}"),
            "vr": {v.name: v.valueReference for v in variables}, "types": {v.name: v.type for v in variables},
            "causality": {v.name: v.causality for v in variables}, "starts": starts,
            "outputs": [v.name for v in variables if v.causality == "output"],
            "states": [d.variable.derivative.name for d in md.derivatives] if md.derivatives else [],
            "n_states": sum(int(d.variable.derivative.dimensions[0].start) if getattr(d.variable.derivative, "dimensions",
                                                                                       None) else 1
                            for d in md.derivatives or []),
            "step": float(md.defaultExperiment.stepSize) if md.defaultExperiment else None,
            "sizes": {v.name: int(v.dimensions[0].start) if getattr(v, "dimensions", None) else 1 for v in variables}}


def copy_facts(facts: dict, folder: Path) -> dict:
    """The unzipped FMU of ``facts`` copied into ``folder``: the same FMU from another library file
    (as a second copy, or another build, is loaded)."""
    import shutil

    shutil.copytree(facts["folder"], folder)
    moved = {k: v.replace(facts["folder"], str(folder)) if k in ("library", "resources") else v for k, v in facts.items()}
    return {**moved, "folder": str(folder)}


def write_values(facts: dict, values: dict) -> list[str]:
    """Commands that set ``values`` (name -> value; Strings with ``sets``, the rest with ``setr``)."""
    lines = []
    for name, value in values.items():
        vr = facts["vr"][name]
        if facts["types"][name] == "String":
            lines.append(f"sets {vr} x:{str(value).encode().hex()}")
        else:
            lines.append(f"setr {vr} = {float(value)!r}")
    return lines


def instantiate(facts: dict, kind: str = "cs", name: str = "host", slot: int = 0, lib: int = 0,
                logging: bool = False) -> list[str]:
    """Commands that load the FMU's library and instantiate it into ``slot`` (``kind``: cs or me)."""
    how = "log" if logging else ""
    return [f"load {lib} {facts['library']}",
            f"fmi{facts['version']} {slot} {lib} {kind} {name} {facts['guid']} {facts['resources']} {how}".rstrip()]
