"""Drive the native FMU from the C host (``host.c``, a minimal FMI master compiled here with
the machine's C compiler) and read the facts a master needs from ``modelDescription.xml``."""
from __future__ import annotations

import subprocess
import tempfile
import zipfile
from pathlib import Path

HERE = Path(__file__).resolve().parent


def facts(fmu: str | Path) -> dict:
    """GUID, model identifier, value references by name, inputs and outputs (names, in
    order) and the default step (s) of an FMU."""
    from fmpy import read_model_description

    md = read_model_description(str(fmu))
    variables = md.modelVariables
    return {"guid": md.guid, "identifier": md.coSimulation.modelIdentifier,
            "vr": {v.name: v.valueReference for v in variables},
            "inputs": [v.name for v in variables if v.causality == "input"],
            "outputs": [v.name for v in variables if v.causality == "output"],
            "step": float(md.defaultExperiment.stepSize)}


def compile_host(dest: Path, platform=None) -> Path:
    """Compile ``host.c`` into the executable ``dest`` for ``platform`` (default this machine; a
    :class:`fmu.native.platforms.Platform` for a cross build: mingw for Windows, gcc for ARM),
    FMI headers from the installed fmpy; it does not link the C math library, so an FMU library
    that needs libm must bring it."""
    from fmu.native import platforms
    from fmu.native.build import fmi_headers_dir

    platform = platform or platforms.LINUX
    cc = platforms.compiler(platform)
    if cc is None:
        raise RuntimeError(f"no C compiler for {platform.fmi3}: install {platform.compiler}")
    static = ["-static"] if platform is platforms.WINDOWS else []  # the DLL then needs only the C runtime
    proc = subprocess.run([cc, "-O2", "-I", str(fmi_headers_dir()), str(HERE / "host.c"), "-o", str(dest), *static,
                           *platforms.HOST_LIBS[platform.fmi3]], capture_output=True, text=True)
    if proc.returncode:
        raise RuntimeError(f"compiling the C host for {platform.fmi3} failed:\n{proc.stderr[-3000:]}")
    return dest


def extract(fmu: str | Path, folder: Path) -> Path:
    """Unzip ``fmu`` into ``folder``; returns the folder."""
    with zipfile.ZipFile(fmu) as z:
        z.extractall(folder)
    return folder


def library(unzipdir: Path, identifier: str, folder: str = "linux64", suffix: str = ".so") -> Path:
    """The shared library of an unzipped FMU in ``binaries/<folder>``."""
    return Path(unzipdir) / "binaries" / folder / f"{identifier}{suffix}"


def _join(values) -> str:
    return ",".join(str(v) if isinstance(v, int) else repr(float(v)) for v in values)


def host_command(host: Path, so: Path, f: dict, scene: str, dt: float, steps: int, inputs: dict,
                 outputs: list[str], quiet: bool = False) -> list[str]:
    return [str(host), "run", str(so), f["guid"], f"{f['vr']['scene']}={scene}", repr(float(dt)), str(steps),
            _join(f["vr"][n] for n in inputs), _join(inputs.values()), _join(f["vr"][n] for n in outputs),
            *(["quiet"] if quiet else [])]


def run_host(host: Path, so: Path, f: dict, scene: str, dt: float, steps: int, inputs: dict,
             outputs: list[str], runner: list[str] = ()) -> dict:
    """``steps`` communication steps of ``dt`` (s) of ``scene`` with ``inputs`` (name -> rad)
    held; returns ``{"time": [...], name: [...]}`` after each step. ``runner`` goes before the
    host's command (e.g. ``["wine"]``, ``["qemu-aarch64", "-L", sysroot]``)."""
    proc = subprocess.run([*runner, *host_command(host, so, f, scene, dt, steps, inputs, outputs)],
                          capture_output=True, text=True, timeout=600)
    if proc.returncode:
        raise RuntimeError(f"the C host failed ({proc.returncode}):\n{proc.stderr[-3000:]}")
    rows = [[float(x) for x in line.split()] for line in proc.stdout.splitlines()]
    return {"time": [r[0] for r in rows], **{n: [r[i + 1] for r in rows] for i, n in enumerate(outputs)}}


def time_host(host: Path, so: Path, f: dict, scene: str, dt: float, steps: int, inputs: dict,
              outputs: list[str]) -> dict:
    """``{"wall_s", "cpu_s"}`` of the C host's stepping loop (setReal, doStep, getReal of
    ``outputs`` per step)."""
    proc = subprocess.run(host_command(host, so, f, scene, dt, steps, inputs, outputs, quiet=True),
                          capture_output=True, text=True, timeout=600)
    if proc.returncode:
        raise RuntimeError(f"the C host failed ({proc.returncode}):\n{proc.stderr[-3000:]}")
    words = proc.stdout.split()
    return {"cpu_s": float(words[3]), "wall_s": float(words[5])}


def host_cycles(host: Path, so: Path, f: dict, scene: str, n: int) -> tuple[int, int]:
    """Resident memory (kB) of the C host after 10 and after ``n`` instantiate/free cycles."""
    proc = subprocess.run([str(host), "cycles", str(so), f["guid"], f"{f['vr']['scene']}={scene}", str(n)],
                          capture_output=True, text=True, timeout=600)
    if proc.returncode:
        raise RuntimeError(f"the C host failed ({proc.returncode}):\n{proc.stderr[-3000:]}")
    _, before, after = proc.stdout.split()
    return int(before), int(after)


def ensure_host(folder: Path | None = None) -> Path:
    """The compiled C host in ``folder`` (default: a new temporary folder)."""
    folder = Path(folder or tempfile.mkdtemp(prefix="heli-fmi-host-"))
    exe = folder / "heli_fmi_host"
    return exe if exe.exists() else compile_host(exe)
