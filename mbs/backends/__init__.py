"""Evaluators of a model's generated functions and the :func:`build` entry point."""
from __future__ import annotations

from mbs.backends.compiled import CompiledSystem, CompilerNotFound, compile_source, generate
from mbs.backends.info import ModelInfo, info_of
from mbs.backends.system import Result, System, Trajectory
from mbs.backends.vm import VMSystem

BACKENDS = ("compiled", "vm")


def build(model, backend: str = "compiled", dtype: str = "float64") -> System:
    """Build ``model`` (a :class:`mbs.Model`) into a runnable :class:`System`.

    backend: ``"compiled"`` (generated C, cached on disk; float64 or float32) or ``"vm"``
    (CasADi's virtual machine, float64). Raises :class:`CompilerNotFound` if the compiled
    evaluator is asked for and no C compiler exists.
    """
    from mbs.dynamics import symbolic

    if backend not in BACKENDS:
        raise ValueError(f"unknown backend {backend!r}; choose one of {BACKENDS}")
    if dtype not in ("float64", "float32"):
        raise ValueError(f"unknown dtype {dtype!r}; choose 'float64' or 'float32'")
    vm = VMSystem(symbolic(model), dtype if backend == "vm" else "float64")
    if backend == "vm":
        return vm
    folder = compile_source(generate(vm.functions, vm.info, dtype), vm.info)
    return CompiledSystem(folder, dtype)


__all__ = ["build", "BACKENDS", "System", "Trajectory", "Result", "ModelInfo", "VMSystem",
           "CompiledSystem", "CompilerNotFound", "info_of"]
