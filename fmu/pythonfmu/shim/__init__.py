"""The FMU's own FMI 2.0 front end (``fmi2_shim.c``) in front of pythonfmu's binary.

pythonfmu's C++ wrapper crashes the host after a Python exception, cannot report
``fmi2Error`` from a getter or setter, mangles resource paths with ``#``, ``&``, ``%`` or
non-ASCII characters, and segfaults in a host that is not a Python process. The shim is
``binaries/linux64/<modelIdentifier>.so`` of the FMU; pythonfmu's library moves to
``binaries/linux64/pythonfmu/<modelIdentifier>.so`` and is loaded by the shim at the first
``fmi2Instantiate`` (see the comment at the top of ``fmi2_shim.c`` for what it checks).

- :func:`compile_shim`: compile the shim with the machine's C compiler (``$CC``, else
  ``cc``/``gcc``/``clang``) against the FMI 2.0 headers of the installed fmpy;
- :func:`relocate`: the entries of the packaged FMU for one entry of pythonfmu's zip.
"""
from __future__ import annotations

import importlib.util
import subprocess
from pathlib import Path

SOURCE = Path(__file__).resolve().parent / "fmi2_shim.c"
INNER_DIR = "pythonfmu"  # binaries/linux64/<INNER_DIR>/ holds pythonfmu's library (as in fmi2_shim.c)
PLATFORM = "linux64"
CFLAGS = ["-std=c99", "-O2", "-fPIC", "-shared", "-fvisibility=hidden", "-Wall", "-Wextra", "-Wno-format-truncation"]
LIBS = ["-ldl", "-lpthread"]


class ShimBuildError(RuntimeError):
    """The shim cannot be compiled (no C compiler, no FMI headers, or a compiler error)."""


def find_compiler() -> str:
    """The C compiler of :func:`mbs.backends.compiled.find_compiler` (``$CC``, else ``cc``,
    ``gcc`` or ``clang``); raises :class:`ShimBuildError` saying what it is needed for."""
    from mbs.backends.compiled import CompilerNotFound
    from mbs.backends.compiled import find_compiler as find

    try:
        return find()
    except CompilerNotFound as exc:
        raise ShimBuildError("building the FMU needs a C compiler for its FMI front end (fmu/pythonfmu/shim/fmi2_shim.c): "
                             f"{exc}; or use a cached FMU") from None


def headers_dir() -> Path:
    """The FMI 2.0 headers shipped with fmpy (``fmpy/c-code``)."""
    spec = importlib.util.find_spec("fmpy")
    if spec is None or spec.origin is None:
        raise ShimBuildError("building the FMU needs fmpy installed: its c-code/ folder has the FMI 2.0 headers")
    folder = Path(spec.origin).parent / "c-code"
    if not (folder / "fmi2Functions.h").is_file():
        raise ShimBuildError(f"fmpy's FMI 2.0 headers are missing: no fmi2Functions.h in {folder}")
    return folder


def compile_shim(out: Path, guid: str) -> Path:
    """Compile ``fmi2_shim.c`` into the shared library ``out`` for the FMU whose GUID is
    ``guid`` (it refuses any other); raises ShimBuildError."""
    cc = find_compiler()
    if not guid or '"' in guid or "\\" in guid:
        raise ShimBuildError(f"not a GUID for the FMI front end: {guid!r}")
    cmd = [cc, *CFLAGS, f"-I{headers_dir()}", f'-DHELI_GUID="{guid}"', str(SOURCE), "-o", str(out), *LIBS]
    try:
        proc = subprocess.run(cmd, capture_output=True, text=True)
    except OSError as exc:
        raise ShimBuildError(f"the C compiler {cc!r} could not be run: {exc}") from exc
    if proc.returncode:
        raise ShimBuildError(f"compiling the FMI front end failed ({' '.join(cmd)}):\n{proc.stderr[-4000:]}")
    return out


def relocate(name: str, data: bytes, shim: bytes) -> list[tuple[str, bytes]]:
    """Entries of the packaged FMU for the entry ``name`` of pythonfmu's zip: its library for
    this platform moves under ``INNER_DIR`` and the shim takes its place; binaries for
    other platforms are dropped (the model libraries are built for this platform only)."""
    parts = name.split("/")
    if parts[0] != "binaries" or len(parts) < 3:
        return [(name, data)]
    if parts[1] != PLATFORM:
        return []
    if len(parts) == 3 and parts[2].endswith(".so"):
        return [(f"binaries/{PLATFORM}/{INNER_DIR}/{parts[2]}", data), (name, shim)]
    return [(name, data)]
