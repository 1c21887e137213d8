"""Timing helper: medians over batches, robust on a shared, noisy machine."""
from __future__ import annotations

import platform
import time
from typing import Callable

import numpy as np


def median_time(fn: Callable[[], object], min_batch_s: float = 0.05, batches: int = 9) -> float:
    """Median wall time of one call of ``fn`` in s, over ``batches`` batches of >= ``min_batch_s``."""
    fn()
    n, t0 = 1, time.perf_counter()
    fn()
    single = max(time.perf_counter() - t0, 1e-7)
    n = max(1, int(min_batch_s / single))
    samples = []
    for _ in range(batches):
        t0 = time.perf_counter()
        for _ in range(n):
            fn()
        samples.append((time.perf_counter() - t0) / n)
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
