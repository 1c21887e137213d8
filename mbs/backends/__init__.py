"""Evaluators of a model's generated functions and the :func:`build` entry point.

``mbs.backends.compiled`` and ``mbs.backends.system`` need only numpy; building a model
(``build``) and the virtual machine need CasADi.
"""
from __future__ import annotations

BACKENDS = ("compiled", "vm")


def build(model, backend: str = "compiled", dtype: str = "float64", path: str | None = None):
    """Build ``model`` (a :class:`mbs.Model`) into a runnable :class:`mbs.System`.

    backend: ``"compiled"`` (generated C, cached on disk; float64 or float32) or ``"vm"``
    (CasADi's virtual machine, float64). path: the forward-dynamics path, a key of
    :data:`mbs.dynamics.PATHS` (default: the one with fewer operations). Raises
    :class:`mbs.CompilerNotFound` if the compiled evaluator is asked for and no C compiler exists.
    """
    from mbs.backends.compiled import CompiledSystem
    from mbs.backends.index import system_library
    from mbs.backends.vm import VMSystem
    from mbs.dynamics import symbolic

    if backend not in BACKENDS:
        raise ValueError(f"unknown backend {backend!r}; choose one of {BACKENDS}")
    if dtype not in ("float64", "float32"):
        raise ValueError(f"unknown dtype {dtype!r}; choose 'float64' or 'float32'")
    vm = VMSystem(symbolic(model, path), dtype if backend == "vm" else "float64")
    if backend == "vm":
        return vm
    return CompiledSystem(system_library(vm, dtype), dtype)
