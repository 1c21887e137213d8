"""The platforms the native FMU's library is compiled for, here, with Debian's cross compilers.

==============  ================  ======================  =====================================
FMI 2.0 folder  FMI 3.0 folder    compiler                run here by
==============  ================  ======================  =====================================
linux64         x86_64-linux      the machine's ``cc``    the tests' C host and fmpy
win64           x86_64-windows    x86_64-w64-mingw32-gcc  a C host built by mingw, under Wine
(sources/)      aarch64-linux     aarch64-linux-gnu-gcc   a C host built for ARM, under qemu-aarch64
==============  ================  ======================  =====================================

FMI 2.0 has no standard folder for ARM Linux: its FMU ships ``sources/`` for that (and any other
platform). macOS is not built here (see the README for the one command that builds it there).
A platform whose compiler is missing is left out of the FMU, and the build says so.
"""
from __future__ import annotations

import os
import shutil
from dataclasses import dataclass


@dataclass(frozen=True)
class Platform:
    fmi2: str | None         # folder under binaries/ in the FMI 2.0 FMU (None: not shipped there)
    fmi3: str                # the FMI 3.0 platform tuple
    compiler: str | None     # cross compiler (None: the machine's own, mbs.backends.compiled.find_compiler)
    suffix: str
    cflags: tuple[str, ...]
    ldflags: tuple[str, ...]


LINUX = Platform("linux64", "x86_64-linux", None, ".so", ("-fPIC",), ("-lm",))
WINDOWS = Platform("win64", "x86_64-windows", "x86_64-w64-mingw32-gcc", ".dll", (),
                   ("-static-libgcc", "-Wl,--exclude-all-symbols"))
ARM = Platform(None, "aarch64-linux", "aarch64-linux-gnu-gcc", ".so", ("-fPIC",), ("-lm",))
PLATFORMS = (LINUX, WINDOWS, ARM)
HOST_LIBS = {"x86_64-linux": ("-ldl",), "x86_64-windows": (), "aarch64-linux": ("-ldl",)}
"""Libraries a C host (``host.c``) needs on each platform."""


def compiler(p: Platform) -> str | None:
    """The compiler of ``p`` on this machine (its path), or None when it is not installed."""
    if p.compiler is None:
        from mbs.backends.compiled import find_compiler

        return find_compiler()
    return shutil.which(p.compiler)


def available() -> list[Platform]:
    """The platforms whose compiler is here (the machine's own first)."""
    return [p for p in PLATFORMS if compiler(p)]


def missing() -> list[Platform]:
    return [p for p in PLATFORMS if not compiler(p)]


def key() -> list[str]:
    """What the set of platforms built depends on (for the cache key): the compilers found."""
    return [f"{p.fmi3}={os.path.basename(compiler(p) or '')}" for p in PLATFORMS]
