"""WebAssembly builds of the native FMU's model and of the hover-hold controller, for the browser
page of ``heli fly``.

The model: the native FMU's own C, generated as for the FMU by :mod:`fmu.native.build`
(``heli_data.c``, ``heli_model_<group>.c``) and the model core (``heli_core.c``), compiled with
``zig cc`` (the ``ziglang`` package) for ``wasm32-wasi``, with ``heli_wasm.c`` as its entry
points and two things the FMU does not ship: the model's generated ``poses`` function (body
poses for the 3D view, ``heli_wasm_poses_<group>.c``) and, in place of the derivative files
(``heli_ad_<group>.c``, megabytes of C that a page never calls), functions that report an error.
The FMI wrappers are not compiled: the page drives the core directly.

The controller: ``controller_fmi2.c`` and ``hover_hold_data.h`` exactly as shipped in the
controller FMU's ``sources/``, with ``fmu/controller/controller_wasm.c`` as entry points.

Flags (:data:`FLAGS`): ``-Os`` (the smallest: 367 kB for the default family against 465 kB at
``-O2``, and as fast in Chromium's V8: ``heli bench fly``),
no fused multiply-adds (``-ffp-contract=off``, as the FMU), math from WASI's libc (musl). Both
are cached under ``<cache>/wasm/<key>/`` like the FMUs, with their digests.
"""
from __future__ import annotations

import hashlib
import importlib.metadata
import json
import os
import shutil
import subprocess
import sys
import tempfile
import zipfile
from dataclasses import dataclass
from pathlib import Path

from fmu.native import build as native

HERE = Path(__file__).resolve().parent
TARGET = "wasm32-wasi"
FLAGS = ["-Os", "-fno-math-errno", "-ffp-contract=off", "-DHELI_LIBM_LINKED"]
LINK = ["-mexec-model=reactor", "-Wl,-z,stack-size=1048576", "-Wl,--strip-debug"]
DRIVER = "heli_wasm.c"
CONTROLLER_DRIVER = HERE.parent / "controller" / "controller_wasm.c"


@dataclass
class WasmModel:
    """A built model: ``wasm`` (the module's path), ``spec`` (the plan of :func:`fmu.native.build.native_spec`
    with the page's additions: ``poses``, the number of pose values per group), ``build_s``
    (seconds, 0 from the cache)."""

    wasm: Path
    spec: dict
    build_s: float


def zig() -> list[str]:
    """The command of ``zig cc`` (the ``ziglang`` package); RuntimeError saying how to install it."""
    try:
        importlib.metadata.version("ziglang")
    except importlib.metadata.PackageNotFoundError:
        raise RuntimeError("building the WebAssembly model needs zig's C compiler: pip install ziglang") from None
    return [sys.executable, "-m", "ziglang", "cc"]


def zig_version() -> str:
    return importlib.metadata.version("ziglang")


# -- sources ------------------------------------------------------------------------------------

def no_derivatives(groups) -> str:
    """C of the derivative functions (``ad_fwd``, ``ad_adj`` and their work sizes) of every group,
    each reporting an error: the page never asks for derivatives."""
    out = ["/* Directional and adjoint derivatives are not part of the WebAssembly model. */\n"]
    for g in groups:
        for f in native.AD_FUNCTIONS:
            name = f"heli_{g}_d_{f}"
            out.append(f"int {name}(const double** a, double** r, long long* i, double* w, int m) "
                       "{ (void) a, (void) r, (void) i, (void) w, (void) m; return 1; }\n"
                       f"int {name}_work(long long* a, long long* r, long long* i, long long* w) "
                       "{ *a = *r = *i = *w = 0; return 0; }\n")
    return "".join(out)


def poses_table(spec: dict, groups: dict) -> str:
    """``heli_wasm_data.c``: each group's ``poses`` function, its work sizes and number of values."""
    lines = ['#include "heli_model.h"\n',
             "typedef struct { heli_eval_fn poses; heli_work_fn work; int n; } heli_wasm_poses;\n"]
    entries = []
    for g, (vm, _) in groups.items():
        prefix = f"heli_{g}_fly_"
        lines.append(f"int {prefix}poses(const double**, double**, long long*, double*, int);\n"
                     f"int {prefix}poses_work(long long*, long long*, long long*, long long*);\n")
        entries.append(f"{{{prefix}poses, {prefix}poses_work, {vm.functions['poses'].numel_out(0)}}}")
    lines.append("const heli_wasm_poses heli_wasm_poses_of[] = {" + ", ".join(entries) + "};\n")
    return "".join(lines)


def write_sources(folder: Path, spec: dict, groups: dict, guid: str) -> list[str]:
    """Every C file of the WebAssembly model into ``folder``; returns the ones compiled."""
    folder.mkdir(parents=True, exist_ok=True)
    for name in (*native.HAND_WRITTEN, DRIVER):
        shutil.copy2(HERE / name, folder / name)
    (folder / "heli_config.h").write_text(native.config_header(spec, groups))
    (folder / "heli_data.c").write_text(native.data_source(spec, groups, guid))
    (folder / "heli_wasm_data.c").write_text(poses_table(spec, groups))
    (folder / "heli_wasm_no_derivatives.c").write_text(no_derivatives(groups))
    files = [DRIVER, "heli_libm.c", "heli_data.c", "heli_wasm_data.c", "heli_wasm_no_derivatives.c"]
    for g, (vm, functions) in groups.items():
        (folder / f"heli_model_{g}.c").write_text(native.model_source(g, functions, vm.info.nx))
        poses = native.model_source(g, vm.functions, vm.info.nx, ("poses",), False, f"heli_{g}_fly_")
        (folder / f"heli_wasm_poses_{g}.c").write_text(poses)
        files += [f"heli_model_{g}.c", f"heli_wasm_poses_{g}.c"]
    return files


# -- compiling ------------------------------------------------------------------------------------

def compile_wasm(folder: Path, files: list[str], out: Path, flags=FLAGS) -> None:
    """Compile ``files`` of ``folder`` (in parallel) and link them into the module ``out``."""
    cc, procs = zig(), []
    for f in files:
        obj = folder / f"{f}.o"
        cmd = [*cc, "-target", TARGET, *flags, "-I", str(folder), "-c", str(folder / f), "-o", str(obj)]
        procs.append((f, obj, subprocess.Popen(cmd, stderr=subprocess.PIPE, text=True)))
    errors = [f"{f}:\n{p.communicate()[1][-2000:]}" for f, _, p in procs if p.wait()]
    if errors:
        raise RuntimeError("compiling the WebAssembly model failed:\n" + "\n".join(errors))
    proc = subprocess.run([*cc, "-target", TARGET, *LINK, *[str(o) for _, o, _ in procs], "-o", str(out)],
                          capture_output=True, text=True)
    if proc.returncode:
        raise RuntimeError(f"linking the WebAssembly model failed:\n{proc.stderr[-2000:]}")


def build_model(scene_names, dest: Path, aircraft=None, flags=FLAGS) -> dict:
    """Generate and compile the WebAssembly model of ``scene_names`` into ``dest``; returns its spec."""
    spec, groups = native.native_spec(scene_names, aircraft)
    spec["poses"] = {g: vm.functions["poses"].numel_out(0) for g, (vm, _) in groups.items()}
    with tempfile.TemporaryDirectory(prefix="heli-wasm-") as tmp:
        files = write_sources(Path(tmp), spec, groups, native.guid_of(cache_key(scene_names, aircraft, flags)))
        compile_wasm(Path(tmp), files, Path(dest), flags)
    return spec


def build_controller(controller_fmu: Path, dest: Path, flags=FLAGS) -> dict:
    """Compile the C of the controller FMU ``controller_fmu`` (its ``sources/``) with
    ``controller_wasm.c`` into ``dest``; returns the design shipped in the FMU."""
    with tempfile.TemporaryDirectory(prefix="heli-wasm-controller-") as tmp, zipfile.ZipFile(controller_fmu) as z:
        for name in z.namelist():
            if name.startswith("sources/"):
                (Path(tmp) / Path(name).name).write_bytes(z.read(name))
        shutil.copy2(CONTROLLER_DRIVER, Path(tmp) / CONTROLLER_DRIVER.name)
        design = json.loads(z.read("resources/design.json"))
        files = [f.name for f in sorted(Path(tmp).glob("*.c"))]
        compile_wasm(Path(tmp), files, Path(dest), flags)
    return design


# -- cache --------------------------------------------------------------------------------------------

def cache_key(scene_names, aircraft=None, flags=FLAGS) -> str:
    """The native FMU's key (:func:`fmu.native.build.cache_key`) with this build's files, flags and zig."""
    h = hashlib.sha256(native.cache_key(scene_names, aircraft).encode())
    for path in (HERE / DRIVER, Path(__file__)):
        h.update(path.read_bytes())
    h.update(json.dumps([TARGET, list(flags), LINK, zig_version()]).encode())
    return h.hexdigest()[:20]


def _cached(folder: Path, names) -> bool:
    from mbs.backends.cache import problem

    return all(problem(folder / n) is None for n in names)


def _install(tmp: Path, folder: Path) -> Path:
    from mbs.backends.cache import record, replace_dir

    for path in tmp.iterdir():
        record(path)
    return replace_dir(tmp, folder)


def ensure_model(scene_names, aircraft=None, log=None, flags=FLAGS) -> WasmModel:
    """The cached WebAssembly model of ``scene_names`` of ``aircraft`` (built if absent or not intact)."""
    import time

    from mbs.backends.cache import writable_dir
    from mbs.backends.compiled import cache_dir

    folder = cache_dir() / "wasm" / cache_key(scene_names, aircraft, flags)
    if _cached(folder, ("model.wasm", "spec.json")):
        return WasmModel(folder / "model.wasm", json.loads((folder / "spec.json").read_text()), 0.0)
    if log:
        log(f"compiling the model of {', '.join(scene_names)} to WebAssembly with zig cc (once; cached) ...")
    start = time.perf_counter()
    tmp = Path(tempfile.mkdtemp(dir=writable_dir(folder.parent, "WebAssembly cache"), prefix=".build-"))
    try:
        spec = build_model(scene_names, tmp / "model.wasm", aircraft, flags)
        (tmp / "spec.json").write_text(json.dumps(spec))
        folder = _install(tmp, folder)
    except BaseException:
        shutil.rmtree(tmp, ignore_errors=True)
        raise
    return WasmModel(folder / "model.wasm", spec, time.perf_counter() - start)


def ensure_controller(controller_fmu: Path, flags=FLAGS) -> tuple[Path, dict]:
    """The cached WebAssembly controller of ``controller_fmu`` and its design."""
    from mbs.backends.cache import sha256, writable_dir
    from mbs.backends.compiled import cache_dir

    h = hashlib.sha256(sha256(controller_fmu).encode() + CONTROLLER_DRIVER.read_bytes())
    h.update(json.dumps([TARGET, list(flags), LINK, zig_version()]).encode())
    folder = cache_dir() / "wasm" / f"controller-{h.hexdigest()[:20]}"
    if not _cached(folder, ("controller.wasm", "design.json")):
        tmp = Path(tempfile.mkdtemp(dir=writable_dir(folder.parent, "WebAssembly cache"), prefix=".build-"))
        try:
            design = build_controller(controller_fmu, tmp / "controller.wasm", flags)
            (tmp / "design.json").write_text(json.dumps(design))
            folder = _install(tmp, folder)
        except BaseException:
            shutil.rmtree(tmp, ignore_errors=True)
            raise
    return folder / "controller.wasm", json.loads((folder / "design.json").read_text())


def native_library(scene_names, dest: Path, aircraft=None) -> Path:
    """The same model and entry points compiled natively (the machine's C compiler, the FMU's
    flags) as a shared library ``dest``: the benchmark's native side of the same loop (``hw_run``)."""
    from mbs.backends.compiled import find_compiler

    spec, groups = native.native_spec(scene_names, aircraft)
    folder = Path(dest).parent / "sources"
    files = write_sources(folder, spec, groups, native.guid_of(cache_key(scene_names, aircraft)))
    cc = find_compiler()
    flags = ["-O2", "-fPIC", "-shared", "-fno-math-errno", "-ffp-contract=off", "-DHELI_LIBM_LINKED"]
    proc = subprocess.run([cc, *flags, "-I", str(folder), *[str(folder / f) for f in files], "-o", str(dest), "-lm"],
                          capture_output=True, text=True, env={**os.environ})
    if proc.returncode:
        raise RuntimeError(f"compiling the native library failed:\n{proc.stderr[-2000:]}")
    return Path(dest)
