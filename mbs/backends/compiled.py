"""Evaluator 2: the model's CasADi functions as generated C, compiled and called via ctypes.

The generated source (plus a small driver that loops fixed steps in C, so a whole
communication step or simulation chunk is one call) is compiled with the machine's C
compiler into a shared library, cached on disk under a hash of the source and flags.
The library directory holds ``model.c``, ``model.so`` and ``info.json`` (with the digest
files of the last two, checked before a cached folder is used); loading it needs only numpy
and ctypes (no CasADi), which is what the FMU ships.
"""
from __future__ import annotations

import ctypes
import hashlib
import logging
import os
import shutil
import subprocess
import tempfile
import time
from pathlib import Path

import numpy as np

from mbs.backends.info import ModelInfo
from mbs.backends.system import System

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
LARGE_SOURCE_BYTES = 1_500_000
"""Above this size of C source, compile with ``-O1``: gcc's ``-O2`` time grows steeply with the
size of one generated function (a 40-link chain, 2.7 MB: 311 s at ``-O2``, 19 s at ``-O1``,
whose code runs 2x slower, still 4x faster than the virtual machine)."""


def compile_flags(source: str) -> list[str]:
    """The compiler flags for ``source``: :data:`CFLAGS`, with ``-O1`` for large sources."""
    if len(source) <= LARGE_SOURCE_BYTES:
        return list(CFLAGS)
    return ["-O1" if f == "-O2" else f for f in CFLAGS]


def generate(functions: dict, info: ModelInfo, dtype: str) -> str:
    """C source of ``functions`` (CasADi) plus one fixed-step driver per method."""
    import casadi as ca

    gen = ca.CodeGenerator("model.c", {"casadi_real": _REALS[dtype][0], "with_header": False})
    for f in functions.values():
        gen.add(f)
    drivers = "".join(DRIVER.format(m=m, nx=info.nx) for m in info.methods)
    return gen.dump() + drivers


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

    cc, flags = find_compiler(), compile_flags(source)
    key = hashlib.sha256("\n".join([source, info.to_json(), cc, *flags]).encode()).hexdigest()[:20]
    folder = (directory or cache_dir()) / f"{info.name}-{key}"
    bad = library_problem(folder)
    if bad is None:
        return folder
    if folder.exists():
        logging.getLogger(__name__).warning("rebuilding %s: %s", folder, bad)
    tmp = Path(tempfile.mkdtemp(dir=writable_dir(folder.parent, "compiled-model cache"), prefix=".build-"))
    try:
        _compile_into(tmp, cc, flags, source, info)
    except BaseException:
        shutil.rmtree(tmp, ignore_errors=True)
        raise
    if library_problem(folder) is None:  # another process finished a good one first
        shutil.rmtree(tmp, ignore_errors=True)
        return folder
    return replace_dir(tmp, folder)


def _compile_into(folder: Path, cc: str, flags: list[str], source: str, info: ModelInfo) -> None:
    """Write ``model.c``, compile ``model.so`` and write ``info.json`` into ``folder``,
    recording the digests of the library and of the description."""
    from mbs.backends.cache import record

    (folder / "model.c").write_text(source)
    start = time.perf_counter()
    proc = subprocess.run([cc, *flags, "-o", str(folder / "model.so"), str(folder / "model.c"), "-lm"],
                          capture_output=True, text=True)
    if proc.returncode:
        raise RuntimeError(f"compiling {info.name} failed:\n{proc.stderr[-2000:]}")
    info.extra["compile_s"] = time.perf_counter() - start
    info.extra["cflags"] = flags
    (folder / "info.json").write_text(info.to_json())
    for name in LIBRARY_FILES:
        record(folder / name)


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
    """One generated CasADi function called through ctypes with preallocated buffers."""

    def __init__(self, lib: ctypes.CDLL, name: str, ctype):
        self.name, self._f, self._np = name, getattr(lib, name), np.dtype(ctype)
        self._f.restype = ctypes.c_int
        self._f.argtypes = [ctypes.c_void_p] * 4 + [ctypes.c_int]
        sizes = [_CINT() for _ in range(4)]
        getattr(lib, name + "_work")(*[ctypes.byref(s) for s in sizes])
        n_in, n_out = (self._query(lib, name + s, _CINT)() for s in ("_n_in", "_n_out"))
        self.ins = [np.zeros(self._nnz(lib, name + "_sparsity_in", i), self._np) for i in range(n_in)]
        self.outs = [np.zeros(self._nnz(lib, name + "_sparsity_out", i), self._np) for i in range(n_out)]
        self._arg = (ctypes.c_void_p * max(sizes[0].value, 1))(*[a.ctypes.data for a in self.ins])
        self._res = (ctypes.c_void_p * max(sizes[1].value, 1))(*[a.ctypes.data for a in self.outs])
        self._iw = np.zeros(max(sizes[2].value, 1), np.int64)
        self._w = np.zeros(max(sizes[3].value, 1), self._np)
        self._call_args = (self._arg, self._res, self._iw.ctypes.data, self._w.ctypes.data, 0)

    @staticmethod
    def _query(lib, name, restype):
        f = getattr(lib, name)
        f.restype = restype
        return f

    def _nnz(self, lib, name, i) -> int:
        f = self._query(lib, name, ctypes.POINTER(_CINT))
        sp = f(i)  # (nrow, ncol, 1) when dense, else (nrow, ncol, colind..., row...)
        return int(sp[0] * sp[1]) if sp[2] == 1 else int(sp[2 + sp[1]])

    def __call__(self, *args) -> list[np.ndarray]:
        for buf, a in zip(self.ins, args):
            buf[:] = a
        if self._f(*self._call_args):
            raise FloatingPointError(f"generated function {self.name} reported an error")
        return [o.copy() for o in self.outs]


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
        if name not in self._fns:
            self._fns[name] = CFunction(self._lib, name, self._ctype)
        return self._fns[name]

    def _eval(self, name, *args):
        return [o.astype(float) for o in self.function(name)(*args)]

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
