"""Timing helper: medians over batches, robust on a shared, noisy machine; the machine and the
tool chain a benchmark ran on."""
from __future__ import annotations

import platform
import time
from typing import Callable

import numpy as np


def median_time(fn: Callable[[], object], min_batch_s: float = 0.05, batches: int = 9,
                clock: Callable[[], float] = time.perf_counter) -> float:
    """Median time of one call of ``fn`` in s, over ``batches`` batches of >= ``min_batch_s``;
    ``clock`` the wall clock, or ``time.thread_time`` for the CPU time of this thread (what a
    run costs when other jobs share the cores and preempt it)."""
    fn()
    n, t0 = 1, clock()
    fn()
    single = max(clock() - t0, 1e-7)
    n = max(1, int(min_batch_s / single))
    samples = []
    for _ in range(batches):
        t0 = clock()
        for _ in range(n):
            fn()
        samples.append((clock() - t0) / n)
    return float(np.median(samples))


def machine() -> dict:
    """Machine and versions a benchmark ran on."""
    import casadi
    import scipy

    cpu = platform.processor() or platform.machine()
    try:
        with open("/proc/cpuinfo") as f:
            cpu = next(line.split(":", 1)[1].strip() for line in f if line.startswith("model name"))
    except (OSError, StopIteration):
        pass
    import os
    return {"cpu": cpu, "cores": os.cpu_count(), "python": platform.python_version(),
            "numpy": np.__version__, "scipy": scipy.__version__, "casadi": casadi.__version__}


def toolchain() -> dict:
    """Versions beyond :func:`machine`: the C compiler and the reference engines."""
    import importlib
    import subprocess

    from mbs.backends.compiled import CompilerNotFound, find_compiler

    out = {}
    try:
        cc = find_compiler()
        out["cc"] = subprocess.run([cc, "--version"], capture_output=True, text=True).stdout.splitlines()[0]
    except (CompilerNotFound, OSError, IndexError) as exc:
        out["cc"] = f"unavailable ({exc})"
    for name in ("pinocchio", "mujoco"):
        try:
            out[name] = importlib.import_module(name).__version__
        except ImportError:
            out[name] = "not installed"
    return out
