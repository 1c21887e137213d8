"""Find a model's cached library without generating its C.

Generating the C of a large model (megabytes with airfoil tables) takes longer than loading the
library it compiles to, so a library is also recorded under a key of what its code is made
from: the serialized CasADi functions (``Function.serialize``), the model description, the
number type, the CasADi version, the compiler, its flags and the source of the modules that
shape the generated code. The index (``<cache>/index/<key>``, one line naming the library's
folder) is read first; only without a valid entry is the C generated (and compiled, unless a
library of that source is cached: :func:`mbs.backends.compiled.compile_source`).

A key that misses costs one generation, never a wrong library: every input of the generated
code enters the key, and the folder it names is checked like any cached library.
"""
from __future__ import annotations

import hashlib
import os
import tempfile
from pathlib import Path

GENERATING_MODULES = ("mbs/backends/compiled.py", "mbs/backends/info.py", "mbs/backends/index.py")
"""Sources whose change can change any generated library (they enter every key)."""

STEP_MODULES = ("mbs/backends/vm.py", "mbs/integrators/*.py")
"""Sources of the fixed steps :class:`mbs.backends.vm.VMSystem` derives from the right-hand side
and projection (``step_<method>``, ``incr_<method>``): they enter a system's key in place of the
steps themselves, each of which serializes to as much as the right-hand side."""

_ROOT = Path(__file__).resolve().parents[2]


def key(functions: dict, info, dtype: str, extra: tuple = (), derived: tuple = ()) -> str:
    """Hex key of the library of ``functions`` (name -> CasADi Function; those of
    :data:`mbs.backends.compiled.NOT_GENERATED` left out) described by ``info``
    (:class:`mbs.backends.info.ModelInfo`) in ``dtype``; ``extra``: strings of any other input
    of the generated code (a caller's own generating modules, a tableau). The functions named in
    ``derived`` enter by name only: the caller vouches that the others and ``extra`` determine them."""
    import casadi as ca

    from mbs.backends.compiled import CFLAGS, LARGE_SOURCE_BYTES, NOT_GENERATED, find_compiler

    h = hashlib.sha256()
    names = sorted(n for n in functions if n not in NOT_GENERATED)
    parts = (*names, *(functions[n].serialize() for n in names if n not in derived), info.to_json(), dtype,
             ca.__version__, find_compiler(), " ".join(CFLAGS), str(LARGE_SOURCE_BYTES),
             *((_ROOT / m).read_text() for m in GENERATING_MODULES), *extra)
    for part in parts:
        h.update(part.encode())
        h.update(b"\0")
    return h.hexdigest()[:20]


def module_texts(modules: tuple) -> tuple:
    """The source of ``modules`` (paths or patterns from the project's root, each pattern's files
    in sorted order), with their paths, for :func:`key`'s ``extra``."""
    paths = [p for m in modules for p in sorted(_ROOT.glob(m))]
    return tuple(f"{p.relative_to(_ROOT)}\n{p.read_text()}" for p in paths)


def _file(k: str) -> Path:
    from mbs.backends.compiled import cache_dir

    return cache_dir() / "index" / k


def lookup(k: str) -> Path | None:
    """The valid library folder recorded under the key ``k``, or None."""
    from mbs.backends.compiled import cache_dir, library_problem

    try:
        name = _file(k).read_text().strip()
    except OSError:
        return None
    folder = cache_dir() / name
    return folder if name and "/" not in name and library_problem(folder) is None else None


def record(k: str, folder: Path) -> None:
    """Record ``folder`` under the key ``k`` (atomically; skipped when the cache is read-only or
    the folder is not in the cache)."""
    from mbs.backends.compiled import cache_dir

    target = _file(k)
    if Path(folder).parent.resolve() != cache_dir().resolve():
        return
    try:
        target.parent.mkdir(parents=True, exist_ok=True)
        fd, tmp = tempfile.mkstemp(dir=target.parent, prefix=".index-")
        with os.fdopen(fd, "w") as f:
            f.write(Path(folder).name + "\n")
        os.replace(tmp, target)
    except OSError:
        pass


def library(functions: dict, info, dtype: str = "float64", extra: tuple = (), derived: tuple = ()) -> Path:
    """The folder of the compiled library of ``functions`` (see :func:`key`): the indexed one,
    or generated, compiled (unless cached) and recorded."""
    from mbs.backends.compiled import compile_source, generate

    k = key(functions, info, dtype, extra, derived)
    folder = lookup(k)
    if folder is None:
        folder = compile_source(generate(functions, info, dtype), info)
        record(k, folder)
    return folder


def system_library(vm, dtype: str = "float64") -> Path:
    """:func:`library` of a :class:`mbs.backends.vm.VMSystem`'s functions, its fixed steps keyed
    by the code that derives them (:data:`STEP_MODULES`)."""
    steps = tuple(n for n in vm.functions if n.startswith(("step_", "incr_")))
    return library(vm.functions, vm.info, dtype, module_texts(STEP_MODULES), steps)
