"""The native FMU's libraries for every platform, run here: the Windows DLL under Wine with a C
host built by mingw, the ARM library under qemu-aarch64 with a C host built for ARM, each for
one revolution of forward flight against the x86_64 Linux library; what each library needs
(the platform's C runtime and libm only) and exports (the FMI functions only); ``fmpy validate``
of both FMUs.

The cross compilers, Wine and qemu come from Debian (``.ci/run`` installs them). Where one is
missing these tests skip, except with ``MBS_REQUIRE_CROSS=1`` (as in CI), where they fail.
"""
from __future__ import annotations

import math
import os
import re
import shutil
import subprocess
import zipfile
from pathlib import Path

import numpy as np
import pytest

from fmu.native import build as native_build
from fmu.native import platforms, run

FAMILY = ("forward-flight", "hover", "ground-run")
ARM_SYSROOT = "/usr/aarch64-linux-gnu"
RUNNERS = {"x86_64-linux": [], "x86_64-windows": ["wine"], "aarch64-linux": ["qemu-aarch64", "-L", ARM_SYSROOT]}
TOOLS = {"x86_64-windows": ("x86_64-w64-mingw32-gcc", "wine", "x86_64-w64-mingw32-objdump"),
         "aarch64-linux": ("aarch64-linux-gnu-gcc", "qemu-aarch64", "objdump")}


def need(*tools: str) -> None:
    """Skip without ``tools`` (they are Debian packages), or fail with MBS_REQUIRE_CROSS=1."""
    missing = [t for t in tools if not (Path(t, "lib").is_dir() if t.startswith("/") else shutil.which(t))]
    if not missing:
        return
    message = f"{', '.join(missing)} not installed (apt-get install gcc-mingw-w64-x86-64 gcc-aarch64-linux-gnu wine " \
              "qemu-user libc6-dev-arm64-cross)"
    if os.environ.get("MBS_REQUIRE_CROSS"):
        pytest.fail(message)
    pytest.skip(message)


@pytest.fixture(scope="module")
def fmu3() -> Path:
    return native_build.ensure_native_fmu(FAMILY, fmi=3)[0]


@pytest.fixture(scope="module")
def unzipped(fmu3, tmp_path_factory) -> Path:
    return run.extract(fmu3, tmp_path_factory.mktemp("fmi3") / "fmu")


@pytest.fixture(scope="module")
def facts(fmu3) -> dict:
    return run.facts(native_build.ensure_native_fmu(FAMILY)[0])  # the C hosts speak FMI 2.0: the same library


def _library(unzipped: Path, platform, identifier: str) -> Path:
    return run.library(unzipped, identifier, platform.fmi3, platform.suffix)


def _one_revolution(platform, unzipped, facts, tmp_path) -> dict:
    exe = tmp_path / f"host_{platform.fmi3}{'.exe' if platform is platforms.WINDOWS else ''}"
    run.compile_host(exe, platform)
    env_runner = RUNNERS[platform.fmi3]
    return run.run_host(exe, _library(unzipped, platform, facts["identifier"]), facts, "forward-flight", facts["step"],
                        100, {}, facts["outputs"], env_runner)


@pytest.mark.parametrize("platform", [platforms.WINDOWS, platforms.ARM], ids=lambda p: p.fmi3)
def test_cross_built_library_runs_one_revolution_like_the_linux_one(platform, unzipped, facts, tmp_path, monkeypatch):
    """Windows (Wine) and ARM (qemu): every output over one revolution (100 steps) within 1e-9 of
    the largest magnitude of that output in the x86_64 Linux run (ARM: bit for bit, the same
    libm and no fused multiply-adds; Windows: the C runtime's own math functions)."""
    need(*TOOLS[platform.fmi3][:2], *([ARM_SYSROOT] if platform is platforms.ARM else []))
    monkeypatch.setenv("WINEDEBUG", "-all")
    linux = _one_revolution(platforms.LINUX, unzipped, facts, tmp_path)
    other = _one_revolution(platform, unzipped, facts, tmp_path)
    assert len(other["time"]) == len(linux["time"]) == 100
    worst = 0.0
    for name in facts["outputs"]:
        a, b = np.array(other[name]), np.array(linux[name])
        scale = max(np.max(np.abs(b)), 1e-300)
        worst = max(worst, np.max(np.abs(a - b)) / scale)
        assert np.max(np.abs(a - b)) <= 1e-9 * scale, name
    if platform is platforms.ARM:
        assert worst == 0.0
    print(f"{platform.fmi3}: largest difference {worst:.1e} of each output's magnitude")


def _imports_and_exports(platform, lib: Path) -> tuple[set, set]:
    tool = "x86_64-w64-mingw32-objdump" if platform is platforms.WINDOWS else "objdump"
    text = subprocess.run([tool, "-p", str(lib)], capture_output=True, text=True, check=True).stdout
    if platform is platforms.WINDOWS:
        imports = set(re.findall(r"DLL Name: (\S+)", text))
        table = text.split("[Ordinal/Name Pointer] Table", 1)[1].split("\n\n", 1)[0]
        exports = set(re.findall(r"\]\s+(\w+)", table))
    else:
        imports = set(re.findall(r"NEEDED\s+(\S+)", text))
        dynsym = subprocess.run(["nm", "-D", "--defined-only", str(lib)], capture_output=True, text=True).stdout
        exports = {line.split()[-1] for line in dynsym.splitlines() if " T " in line}
    return imports, exports


@pytest.mark.parametrize("platform", platforms.PLATFORMS, ids=lambda p: p.fmi3)
def test_libraries_need_only_the_c_runtime_and_export_only_fmi(platform, unzipped, facts):
    if platform is not platforms.LINUX:
        need(TOOLS[platform.fmi3][0], TOOLS[platform.fmi3][2])
    imports, exports = _imports_and_exports(platform, _library(unzipped, platform, facts["identifier"]))
    allowed = {"KERNEL32.dll", "msvcrt.dll"} if platform is platforms.WINDOWS else {"libc.so.6", "libm.so.6"}
    assert imports and imports <= allowed, imports
    assert {"fmi2Instantiate", "fmi2GetDirectionalDerivative", "fmi3InstantiateModelExchange",
            "fmi3GetAdjointDerivative", "fmi3DoStep"} <= exports
    assert all(n.startswith(("fmi2", "fmi3")) for n in exports), sorted(n for n in exports if not n.startswith("fmi"))


def test_both_fmus_ship_their_platforms_and_validate(fmu3):
    from fmpy.validation import validate_fmu

    fmu2 = native_build.ensure_native_fmu(FAMILY)[0]
    need(*(t for p in ("x86_64-windows", "aarch64-linux") for t in TOOLS[p][:1]))
    assert validate_fmu(str(fmu2)) == [] and validate_fmu(str(fmu3)) == []
    folders = lambda f: {n.split("/")[1] for n in zipfile.ZipFile(f).namelist() if n.startswith("binaries/")}  # noqa
    assert folders(fmu2) == {"linux64", "win64"}  # FMI 2.0 has no name for ARM Linux: sources/ serve it
    assert folders(fmu3) == {"x86_64-linux", "x86_64-windows", "aarch64-linux"}
    assert "sources/buildDescription.xml" in zipfile.ZipFile(fmu3).namelist()


MACHO_CPU = {"x86_64-macos": 0x01000007, "aarch64-macos": 0x0100000C}


@pytest.mark.parametrize("target", sorted(MACHO_CPU))
def test_sources_compile_and_link_for_macos(target, unzipped, tmp_path):
    """macOS is not run here: the FMU's sources compile and link into a Mach-O library for Intel
    and Apple silicon with ``zig cc`` (the ``ziglang`` package), every symbol resolved."""
    import importlib.util
    import struct
    import sys
    from xml.etree import ElementTree

    if importlib.util.find_spec("ziglang") is None:
        message = "ziglang (pip install ziglang) not installed"
        pytest.fail(message) if os.environ.get("MBS_REQUIRE_CROSS") else pytest.skip(message)
    build = ElementTree.parse(unzipped / "sources" / "buildDescription.xml").getroot()
    files = [str(unzipped / "sources" / f.get("name")) for f in build.iter("SourceFile")]
    lib = tmp_path / "heli.dylib"
    proc = subprocess.run([sys.executable, "-m", "ziglang", "cc", "-target", target, "-shared", "-O0",
                           "-ffp-contract=off", "-I", str(unzipped / "sources"), *files, "-o", str(lib)],
                          capture_output=True, text=True, timeout=900)
    assert proc.returncode == 0, proc.stderr[-3000:]
    magic, cpu = struct.unpack("<II", lib.read_bytes()[:8])
    assert magic == 0xFEEDFACF and cpu == MACHO_CPU[target]


# -- the hover-hold controller FMU on the same platforms ---------------------------------------------

def _controller_script(facts: dict, steps: int) -> list[str]:
    """A minute-like run of the controller in the scripted host: every input of the trim plus its own
    sine (position, attitude, heading beyond +-pi, velocities, rates), the outputs after each step."""
    from fmu_hosts import conformance

    inputs = [n for n, c in facts["causality"].items() if c == "input"]
    outputs = " ".join(str(facts["vr"][n]) for n in facts["outputs"])
    lines, dt = conformance.begin(conformance.Target(facts, "cs", Path("unused"))), 0.01
    for k in range(steps):
        values = [float(facts["starts"][n]) + (4.0 if n.endswith(".yaw") else 0.3) * math.sin(0.05 * k * (j + 1))
                  for j, n in enumerate(inputs)]
        lines += [f"setr {' '.join(str(facts['vr'][n]) for n in inputs)} = {' '.join(map(repr, values))}",
                  f"step {k * dt!r} {dt!r}", f"getr {outputs}"]
    return lines


def test_controller_fmu_ships_the_native_fmus_platforms():
    from fmu import controller

    fmu, _ = controller.ensure_controller_fmu()
    need(*(t for p in ("x86_64-windows", "aarch64-linux") for t in TOOLS[p][:1]))
    names = zipfile.ZipFile(fmu).namelist()
    assert {n.split("/")[1] for n in names if n.startswith("binaries/")} == {"linux64", "win64"}
    assert "sources/controller_fmi2.c" in names and "sources/hover_hold_data.h" in names


@pytest.mark.parametrize("platform", [platforms.WINDOWS, platforms.ARM], ids=lambda p: p.fmi3)
def test_controller_under_wine_and_qemu_equals_linux(platform, tmp_path, monkeypatch):
    """The controller's Windows DLL (shipped) under Wine and its ARM library (built from the FMU's
    sources/, as FMI 2.0 has no ARM folder) under qemu, each in the scripted C host built for that
    platform, over 300 steps with every input moving (the heading through +-pi): every output equals
    the x86_64 Linux library's to 1e-12 rad."""
    from fmu import controller
    from fmu_hosts import script_host

    need(*TOOLS[platform.fmi3][:2], *([ARM_SYSROOT] if platform is platforms.ARM else []))
    monkeypatch.setenv("WINEDEBUG", "-all")
    fmu, _ = controller.ensure_controller_fmu()
    linux = script_host.fmu_facts(fmu, tmp_path / "linux")
    other = script_host.fmu_facts(fmu, tmp_path / platform.fmi3, platform.fmi2 or platform.fmi3)
    if platform is platforms.ARM:
        controller.compile_library(tmp_path / platform.fmi3 / "sources", Path(other["library"]), platform)
    exe = tmp_path / f"script_host_{platform.fmi3}{'.exe' if platform is platforms.WINDOWS else ''}"
    runs = {}
    for name, facts, host, runner in (("linux", linux, script_host.compile_host(tmp_path / "host"), []),
                                      (platform.fmi3, other, script_host.compile_host(exe, platform),
                                       RUNNERS[platform.fmi3])):
        res = script_host.run(host, _controller_script(facts, 300), runner)
        assert all(r["status"] == 0 for r in res[1:]), [r for r in res if r["status"]][:2]
        runs[name] = np.array([r["values"] for r in res if r["cmd"].startswith("getr")])
    a, b = runs[platform.fmi3], runs["linux"]
    assert a.shape == b.shape == (300, 4) and np.ptp(b, axis=0).min() > 1e-3  # the outputs moved
    worst = float(np.max(np.abs(a - b)))
    print(f"controller {platform.fmi3} vs x86_64 Linux: largest output difference {worst:.1e} rad")
    assert worst <= 1e-12
