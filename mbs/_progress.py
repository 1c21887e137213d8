"""Progress display for long runs (on stderr, so ``--json`` output stays clean)."""
from __future__ import annotations

import sys
import time


class Progress:
    """``Progress("simulate")(done, total)`` draws a bar on stderr, at most ~10 times a second,
    with the time spent and, once 1 % and a second have passed, an estimate of the time left
    (the rate so far carried to the end)."""

    def __init__(self, label: str, enabled: bool = True, stream=None):
        self.label, self.enabled = label, enabled
        self.stream = stream or sys.stderr
        self.start = self._last = time.perf_counter()

    def __call__(self, done: int, total: int) -> None:
        now = time.perf_counter()
        if not self.enabled or (now - self._last < 0.1 and done < total):
            return
        self._last = now
        frac = done / total if total else 1.0
        bar = "#" * int(30 * frac)
        self.stream.write(f"\r{self.label} [{bar:<30}] {100 * frac:5.1f}%  {now - self.start:6.1f} s"
                          f"{left(now - self.start, frac)}")
        if done >= total:
            self.stream.write("\n")
        self.stream.flush()


def left(elapsed: float, frac: float) -> str:
    """``", about 2.5 min left"`` at the fraction ``frac`` done after ``elapsed`` s ('' too early or when done)."""
    remaining = elapsed * (1 - frac) / frac if frac > 0 else 0.0
    if frac >= 1.0 or frac < 0.01 or elapsed < 1.0 or remaining < 1.0:
        return " " * 22
    from mbs.run_cost import duration

    return f", about {duration(remaining)} left".ljust(22)
