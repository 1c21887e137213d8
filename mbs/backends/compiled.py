"""Evaluator 2: the model's CasADi functions as generated C, compiled and called via ctypes.

The generated source (plus a small driver that loops fixed steps in C, so a whole
communication step or simulation chunk is one call) is compiled with the machine's C
compiler into a shared library, cached on disk under a hash of the source and flags (and
found again without generating the source through :mod:`mbs.backends.index`).
The source is cut into translation units (functions that call one another stay together),
compiled in parallel, each with the flags its size calls for, then linked. The library
directory holds the sources (``model.c``, ``model_1.c``, ...), ``model.so`` and ``info.json``
(with the digest files of the last two, checked before a cached folder is used); loading it needs only numpy
and ctypes (no CasADi), which is what the FMU ships.
"""
from __future__ import annotations

import ctypes
import functools
import hashlib
import logging
import os
import re
import shutil
import subprocess
import tempfile
import time
from pathlib import Path

import numpy as np

from mbs.backends.info import ModelInfo
from mbs.backends.system import Bound, System

_CINT = ctypes.c_longlong
_REALS = {"float64": ("double", ctypes.c_double), "float32": ("float", ctypes.c_float)}

DRIVER = r"""
#include <stdlib.h>
/* Fixed-step loop: x <- project(x + incr(x)), with compensated (Kahan) summation carried in
   comp[] (in/out) unless `compensated` is 0; rows every `every` steps and at the end. Returns 0 on success, 1 on a
   non-finite state, 2 on an evaluation error, 3 when out of memory. */
CASADI_SYMBOL_EXPORT int mbs_run_{m}(const casadi_real* x0, double t0, double h, long long k0,
    long long n, long long every, const casadi_real* p, casadi_real* out, casadi_real* comp,
    int compensated, long long* done) {{
  casadi_int a1, r1, i1, w1, a2, r2, i2, w2, i, k, row = 0;
  int status = 0;
  incr_{m}_work(&a1, &r1, &i1, &w1);
  project_work(&a2, &r2, &i2, &w2);
  a1 = a1 > a2 ? a1 : a2; r1 = r1 > r2 ? r1 : r2; i1 = i1 > i2 ? i1 : i2; w1 = w1 > w2 ? w1 : w2;
  const casadi_real** arg = malloc(sizeof(void*) * (a1 + 1));
  casadi_real** res = malloc(sizeof(void*) * (r1 + 1));
  casadi_int* iw = malloc(sizeof(casadi_int) * (i1 + 1));
  casadi_real* w = malloc(sizeof(casadi_real) * (w1 + 3 * {nx} + 3));
  *done = 0;
  if (!arg || !res || !iw || !w) status = 3;
  casadi_real *xa = w + w1, *dx = xa + {nx}, *xs = dx + {nx}, tt, hh = (casadi_real) h, y, s;
  for (i = 0; !status && i < {nx}; ++i) xa[i] = x0[i];
  for (k = 0; !status && k < n; ++k) {{
    tt = (casadi_real) (t0 + (double) (k0 + k) * h);
    arg[0] = xa; arg[1] = &tt; arg[2] = &hh; arg[3] = p; res[0] = dx;
    if (incr_{m}(arg, res, iw, w, 0)) {{ status = 2; break; }}
    for (i = 0; i < {nx}; ++i) {{
      y = dx[i] - comp[i]; s = xa[i] + y; comp[i] = compensated ? (s - xa[i]) - y : 0; xs[i] = s;
    }}
    arg[0] = xs; res[0] = xa;
    if (project(arg, res, iw, w, 0)) {{ status = 2; break; }}
    for (i = 0; i < {nx}; ++i) {{
      if (xa[i] != xs[i]) comp[i] = 0;
      if (!isfinite(xa[i])) status = 1;
    }}
    if (status) break;
    *done = k + 1;
    if ((k + 1) % every == 0 || k + 1 == n) {{
      for (i = 0; i < {nx}; ++i) out[row * {nx} + i] = xa[i];
      ++row;
    }}
  }}
  free(arg); free(res); free(iw); free(w);
  return status;
}}
"""


class CompilerNotFound(ValueError, RuntimeError):
    """No C compiler: the compiled evaluator is unavailable (a ValueError, as for every bad
    input, and a RuntimeError for callers that catch environment problems)."""


def find_compiler() -> str:
    """The C compiler to use: ``$CC``, else ``cc``, ``gcc`` or ``clang`` on the PATH."""
    names = [os.environ["CC"]] if os.environ.get("CC") else ["cc", "gcc", "clang"]
    for name in names:
        path = shutil.which(name)
        if path:
            return path
    raise CompilerNotFound(f"no C compiler found (looked for {', '.join(names)}); install one "
                           "(e.g. apt-get install gcc) or use the virtual machine: backend='vm'")


def cache_dir() -> Path:
    """Where compiled models are kept: ``$MBS_CACHE_DIR`` or ``~/.cache/mbs``."""
    return Path(os.environ.get("MBS_CACHE_DIR") or Path.home() / ".cache" / "mbs")


CFLAGS = ["-O2", "-fPIC", "-shared", "-fno-math-errno"]
LARGE_SOURCE_BYTES = 800_000
"""Above this size of one translation unit, compile with ``-O1``: gcc's ``-O2`` time grows
steeply with the size of one generated function (its register allocation), ``-O1``'s about
linearly. The 100-link chain's right-hand side (1.8 MB): 61 s at ``-O2``, 8 s at ``-O1``,
whose code runs about 10 % slower; the 40-link chain's (0.7 MB): 9 s and 6 s."""


ANNOUNCE_SOURCE_BYTES = LARGE_SOURCE_BYTES
"""A compile of more C than this (tens of seconds to minutes) is announced on the ``mbs``
logger (level INFO; the ``heli`` command shows it on stderr), so a first run does not wait
in silence."""


CONSTANT_ARRAY = re.compile(r"static const casadi_real casadi_c\d+\[\d+\] = \n?\s*\{[^}]*\};")
"""A constant array of the generated code (an airfoil table's coefficients): its size costs the
compiler next to nothing, so it does not count towards :data:`LARGE_SOURCE_BYTES`."""


def compile_flags(source: str) -> list[str]:
    """The compiler flags for ``source`` (one translation unit): :data:`CFLAGS`, with ``-O1``
    above :data:`LARGE_SOURCE_BYTES` of code (constant arrays not counted)."""
    if len(source) <= LARGE_SOURCE_BYTES or code_bytes(source) <= LARGE_SOURCE_BYTES:
        return list(CFLAGS)
    return ["-O1" if f == "-O2" else f for f in CFLAGS]


def code_bytes(source: str) -> int:
    """The size of ``source`` without its constant arrays (:data:`CONSTANT_ARRAY`)."""
    return len(source) - sum(len(m.group(0)) for m in CONSTANT_ARRAY.finditer(source))


NOT_GENERATED = ("parts",)
"""Functions of a model that run only symbolically: ``parts`` (the composite path's ``Mt``,
O(n²) entries on a chain) serves the held-fuselage analyses and the tests; a right-hand side
that needs it carries it along."""

UNIT_SEPARATOR = "\n/* ---- next translation unit ---- */\n"
"""Between the translation units of one generated source (each compiled on its own, in parallel)."""


def translation_units(functions: dict, methods) -> list[list[str]]:
    """The names of ``functions`` grouped into translation units: functions that call one
    another or a common function share a unit, so that each generated function is generated and
    compiled once (an airfoil table's interpolant, whose constant data is megabytes of C, ties the
    right-hand side and the outputs into one unit); the unit of the fixed-step drivers' functions
    (``incr_<method>``, ``project``) first."""
    root = {n: n for n in functions}

    def find(n: str) -> str:
        while root[n] != n:
            n = root[n]
        return n
    owner: dict[str, str] = {}
    for name, f in functions.items():
        for callee in [name, *(g.name() for g in f.find_functions())]:
            root[find(owner.setdefault(callee, name))] = find(name)
    driven = [n for n in [*(f"incr_{m}" for m in methods), "project"] if n in functions and methods]
    for n in driven[1:]:
        root[find(n)] = find(driven[0])
    groups: dict[str, list[str]] = {}
    for n in sorted(functions, key=lambda n: n not in driven):
        groups.setdefault(find(n), []).append(n)
    return list(groups.values())


def generate(functions: dict, info: ModelInfo, dtype: str) -> str:
    """C source of ``functions`` (CasADi; without :data:`NOT_GENERATED`) plus one fixed-step
    driver per method, as translation units joined by :data:`UNIT_SEPARATOR`."""
    import casadi as ca

    functions = {n: f for n, f in functions.items() if n not in NOT_GENERATED}
    units = []
    for k, names in enumerate(translation_units(functions, info.methods)):
        gen = ca.CodeGenerator(f"model_{k}.c" if k else "model.c", {"casadi_real": _REALS[dtype][0],
                                                                    "with_header": False})
        for name in names:
            gen.add(functions[name])
        units.append(gen.dump())
    units[0] += "".join(DRIVER.format(m=m, nx=info.nx) for m in info.methods)
    return UNIT_SEPARATOR.join(units)


def compile_source(source: str, info: ModelInfo, directory: Path | None = None) -> Path:
    """Compile ``source`` into ``<cache>/<name>-<hash>/model.so`` unless cached; returns that folder.

    The hash covers the source, the model description and the compiler command. A cached
    folder is used only when ``model.so`` and ``info.json`` match the digests recorded when
    they were built (:mod:`mbs.backends.cache`); otherwise the model is compiled again in a
    fresh folder that then replaces the bad one. Raises
    :class:`~mbs.backends.cache.CacheNotWritable` when a build is needed and the cache
    folder cannot be written.
    """
    from mbs.backends.cache import replace_dir, writable_dir

    cc, flags = find_compiler(), [" ".join(compile_flags(u)) for u in source.split(UNIT_SEPARATOR)]
    key = hashlib.sha256("\n".join([source, info.to_json(), cc, *flags]).encode()).hexdigest()[:20]
    folder = (directory or cache_dir()) / f"{info.name}-{key}"
    bad = library_problem(folder)
    if bad is None:
        return folder
    if folder.exists():
        logging.getLogger(__name__).warning("rebuilding %s: %s", folder, bad)
    tmp = Path(tempfile.mkdtemp(dir=writable_dir(folder.parent, "compiled-model cache"), prefix=".build-"))
    if len(source) > ANNOUNCE_SOURCE_BYTES:
        logging.getLogger(__name__).info("compiling %s: %.1f MB of C, once (cached in %s) ...", info.name,
                                         len(source) / 1e6, folder.parent)
    try:
        _compile_into(tmp, cc, source, info)
    except BaseException:
        shutil.rmtree(tmp, ignore_errors=True)
        raise
    if library_problem(folder) is None:  # another process finished a good one first
        shutil.rmtree(tmp, ignore_errors=True)
        return folder
    return replace_dir(tmp, folder)


def _compile_into(folder: Path, cc: str, source: str, info: ModelInfo) -> None:
    """Compile ``source`` into ``folder/model.so`` (:func:`_compile_units`, then one link) and
    write ``info.json``, recording the digests of the library and of the description."""
    from mbs.backends.cache import record

    start, units = time.perf_counter(), source.split(UNIT_SEPARATOR)
    objects = _compile_units(folder, cc, units)
    _run([cc, "-shared", "-o", str(folder / "model.so"), *map(str, objects), "-lm"], info.name)
    for o in objects:
        o.unlink()
    info.extra["compile_s"] = time.perf_counter() - start
    info.extra["cflags"] = compile_flags(max(units, key=len))
    info.extra["units"] = [{"bytes": len(u), "cflags": compile_flags(u)} for u in units]
    (folder / "info.json").write_text(info.to_json())
    for name in LIBRARY_FILES:
        record(folder / name)


def _compile_units(folder: Path, cc: str, units: list[str]) -> list[Path]:
    """Write the translation units (``model.c``, ``model_1.c``, ...) and compile them to object
    files all at once, each with its :func:`compile_flags`; returns the object files."""
    jobs = []
    for k, unit in enumerate(units):
        path = folder / (f"model_{k}.c" if k else "model.c")
        path.write_text(unit)
        flags = [f for f in compile_flags(unit) if f != "-shared"]
        cmd = [cc, *flags, "-c", "-o", str(path.with_suffix(".o")), str(path)]
        jobs.append((path.with_suffix(".o"), subprocess.Popen(cmd, stderr=subprocess.PIPE, text=True)))
    errors = [err for _, p in jobs if (err := p.communicate()[1]) and p.returncode]
    if errors:
        raise RuntimeError(f"compiling {folder.name} failed:\n{errors[0][-2000:]}")
    return [o for o, _ in jobs]


def _run(cmd: list[str], name: str) -> None:
    proc = subprocess.run(cmd, capture_output=True, text=True)
    if proc.returncode:
        raise RuntimeError(f"compiling {name} failed:\n{proc.stderr[-2000:]}")


LIBRARY_FILES = ("model.so", "info.json")
"""The files of a compiled model folder whose digests are recorded and checked."""


def library_problem(folder: Path) -> str | None:
    """Why the cached model ``folder`` must not be used (a file missing, without a digest,
    truncated or changed), or None when every file matches its recorded digest."""
    from mbs.backends.cache import problem

    for name in LIBRARY_FILES:
        reason = problem(Path(folder) / name)
        if reason:
            return reason
    return None


def check_library(folder: Path) -> None:
    """Refuse a model ``folder`` whose files have digest files they do not match (raises
    :class:`~mbs.backends.cache.CacheCorrupt`). A folder without digest files, such as the
    one shipped inside the FMU, is not checked."""
    folder = Path(folder)
    if not any((folder / name).with_name(name + ".digest").exists() for name in LIBRARY_FILES):
        return
    from mbs.backends.cache import CacheCorrupt

    reason = library_problem(folder)
    if reason:
        raise CacheCorrupt(f"refusing to load the compiled model in {folder}: {reason}; delete the folder "
                           "to have it rebuilt")


class CFunction:
    """One generated CasADi function called through ctypes with preallocated buffers.

    ``f(*args)`` copies the arguments into the buffers and returns copies of the outputs;
    :meth:`bind` gives a call without either (see :class:`mbs.backends.system.Bound`)."""

    def __init__(self, lib: ctypes.CDLL, name: str, ctype):
        self.name, self._np = name, np.dtype(ctype)
        sizes = [_CINT() for _ in range(4)]
        getattr(lib, name + "_work")(*[ctypes.byref(s) for s in sizes])
        self._sizes = [max(s.value, 1) for s in sizes]
        n_in, n_out = (self._query(lib, name + s, _CINT)() for s in ("_n_in", "_n_out"))
        self.ins = [np.zeros(self._nnz(lib, name + "_sparsity_in", i), self._np) for i in range(n_in)]
        self.outs = [np.zeros(self._nnz(lib, name + "_sparsity_out", i), self._np) for i in range(n_out)]
        self._lib = lib
        self._run = self._caller(self.ins, self.outs)

    @staticmethod
    def _query(lib, name, restype):
        f = getattr(lib, name)
        f.restype = restype
        return f

    def _nnz(self, lib, name, i) -> int:
        f = self._query(lib, name, ctypes.POINTER(_CINT))
        sp = f(i)  # (nrow, ncol, 1) when dense, else (nrow, ncol, colind..., row...)
        return int(sp[0] * sp[1]) if sp[2] == 1 else int(sp[2 + sp[1]])

    def _caller(self, ins: list[np.ndarray], outs: list[np.ndarray]):
        """A call of the function with every argument converted once: reads ``ins``, writes
        ``outs`` (buffers that must outlive it); returns the function's status (0: success)."""
        f = getattr(ctypes.CDLL(self._lib._name), self.name)  # own handle: its conversions are ours
        f.restype, f.argtypes = ctypes.c_int, None
        arg = (ctypes.c_void_p * self._sizes[0])(*[a.ctypes.data for a in ins])
        res = (ctypes.c_void_p * self._sizes[1])(*[a.ctypes.data for a in outs])
        iw, w = np.zeros(self._sizes[2], np.int64), np.zeros(self._sizes[3], self._np)
        keep = (arg, res, iw, w)  # referenced by the call below
        call = functools.partial(f, *[ctypes.c_void_p(ctypes.addressof(a)) for a in keep[:2]],
                                 *[ctypes.c_void_p(a.ctypes.data) for a in keep[2:]], ctypes.c_int(0))
        call.keep = keep
        return call

    def __call__(self, *args) -> list[np.ndarray]:
        for buf, a in zip(self.ins, args):
            buf[:] = a
        if self._run():
            raise FloatingPointError(f"generated function {self.name} reported an error")
        return [o.copy() for o in self.outs]

    def bind(self) -> Bound:
        """This function on buffers of its own (:class:`mbs.backends.system.Bound`)."""
        ins, outs = [np.zeros_like(a) for a in self.ins], [np.zeros_like(a) for a in self.outs]
        return Bound(self.name, ins, outs, self._caller(ins, outs))


class CompiledSystem(System):
    """Loads a compiled model folder (``model.so`` + ``info.json``)."""

    backend = "compiled"

    def __init__(self, folder: Path, dtype: str = "float64"):
        folder = Path(folder)
        check_library(folder)
        super().__init__(ModelInfo.load(folder / "info.json"), dtype)
        self.folder = folder
        self._lib = ctypes.CDLL(str(folder / "model.so"))
        size = self._query("model_casadi_real_size", ctypes.c_int)()
        if size != self.dtype.itemsize:
            raise ValueError(f"{folder} holds {8 * size}-bit code, not {dtype}")
        self._ctype = _REALS[str(self.dtype)][1]
        self._fns: dict[str, CFunction] = {}

    def _query(self, name, restype):
        f = getattr(self._lib, name)
        f.restype = restype
        return f

    def function(self, name: str) -> CFunction:
        """The generated function ``name`` (raw: no checks of its arguments)."""
        if name not in self._fns:
            self._fns[name] = CFunction(self._lib, name, self._ctype)
        return self._fns[name]

    def _eval(self, name, *args):
        return [o.astype(float) for o in self.function(name)(*args)]

    def bind(self, name: str) -> Bound:
        return self.function(name).bind()

    def _run(self, method, x0, t0, h, k0, n, every, p, comp, compensated=True):
        f = getattr(self._lib, f"mbs_run_{method}")
        rows = -(-n // every)
        out = np.zeros((rows, self.info.nx), self.dtype)
        x0, p = np.ascontiguousarray(x0, self.dtype), np.ascontiguousarray(p, self.dtype)
        c = np.ascontiguousarray(comp, self.dtype)
        done = ctypes.c_longlong()
        f.restype = ctypes.c_int
        status = f(x0.ctypes.data_as(ctypes.c_void_p), ctypes.c_double(t0), ctypes.c_double(h),
                   ctypes.c_longlong(k0), ctypes.c_longlong(n), ctypes.c_longlong(every),
                   p.ctypes.data_as(ctypes.c_void_p), out.ctypes.data_as(ctypes.c_void_p),
                   c.ctypes.data_as(ctypes.c_void_p), ctypes.c_int(int(compensated)), ctypes.byref(done))
        comp[:] = c
        return out, (2 if status > 1 else status), done.value
