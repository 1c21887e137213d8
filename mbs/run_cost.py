"""What a run will cost before it starts: its time and the size of its results.

The figures are measured on the run itself, not guessed: the time of one step from the first
revolution that the step-error check runs anyway (:mod:`mbs.step_error`), and the time and
bytes of one recorded row (outputs and energies evaluated, formatted as ``results.csv`` writes
it) from a sample of that revolution's rows. A run whose ``results.csv`` would exceed the
limit (``heli simulate --max-gb``, default 1 GB) is refused before it starts, with the
``--every`` that would fit.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

DEFAULT_MAX_GB = 1.0
SAY_ABOVE_S = 10.0
SAY_ABOVE_BYTES = 100e6


@dataclass
class RunCost:
    """``steps`` of ``step_s`` s each, ``rows`` recorded rows of ``columns`` columns at ``row_s`` s
    (outputs, energies and CSV formatting) and ``row_bytes`` bytes of ``results.csv`` each;
    ``every``: the recording stride."""

    steps: int
    rows: int
    columns: int
    step_s: float
    row_s: float
    row_bytes: float
    every: int = 1

    @property
    def seconds(self) -> float:
        return self.steps * self.step_s + self.rows * self.row_s

    @property
    def size_bytes(self) -> float:
        return self.rows * self.row_bytes

    def worth_saying(self) -> bool:
        """Long or large enough to announce before it starts."""
        return self.seconds > SAY_ABOVE_S or self.size_bytes > SAY_ABOVE_BYTES

    def every_within(self, max_bytes: float) -> int:
        """The smallest recording stride whose ``results.csv`` stays within ``max_bytes``."""
        rows_allowed = max(1.0, max_bytes / self.row_bytes - 1)
        return max(1, math.ceil(self.steps / rows_allowed))

    def message(self) -> str:
        return (f"{self.steps} steps, about {duration(self.seconds)} ({duration(self.steps * self.step_s)} "
                f"stepping, {duration(self.rows * self.row_s)} for outputs, energies and writing); results.csv "
                f"about {size(self.size_bytes)} ({self.rows} rows of {self.columns} columns)")

    def summary(self) -> dict:
        return {"steps": self.steps, "rows": self.rows, "columns": self.columns, "step_s": self.step_s,
                "row_s": self.row_s, "row_bytes": self.row_bytes, "estimated_s": self.seconds,
                "estimated_bytes": self.size_bytes}


def check_size(cost: RunCost, max_gb: float) -> None:
    """Refuse (ValueError) a run whose ``results.csv`` would exceed ``max_gb`` GB."""
    if cost.size_bytes <= max_gb * 1e9:
        return
    raise ValueError(f"results.csv would be about {size(cost.size_bytes)} ({cost.rows} rows of {cost.columns} "
                     f"columns) and the run would take about {duration(cost.seconds)}: more than --max-gb "
                     f"{max_gb:g}; record every N-th step with --every {cost.every_within(max_gb * 1e9)} "
                     "(or more), or raise --max-gb")


def duration(seconds: float) -> str:
    """``"12 s"``, ``"3.5 min"``, ``"2.1 h"``."""
    if seconds < 90:
        return f"{seconds:.2g} s" if seconds < 10 else f"{seconds:.0f} s"
    if seconds < 5400:
        return f"{seconds / 60:.1f} min"
    return f"{seconds / 3600:.1f} h"


def size(n_bytes: float) -> str:
    """``"350 kB"``, ``"12 MB"``, ``"4.5 GB"``."""
    for unit, scale in (("GB", 1e9), ("MB", 1e6), ("kB", 1e3)):
        if n_bytes >= scale:
            return f"{n_bytes / scale:.3g} {unit}"
    return f"{n_bytes:.0f} B"
