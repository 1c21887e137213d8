"""Progress display for long runs (on stderr, so ``--json`` output stays clean)."""
from __future__ import annotations

import sys
import time

_DRAWN: list["Progress"] = []
"""Bars drawn and not finished (a loop that ends early, such as a converged trim): :func:`clear`
erases them before the next line is printed."""


class Progress:
    """``Progress("simulate")(done, total)`` draws a bar on stderr, at most ~10 times a second,
    with the time spent and, once 1 % and a second have passed, an estimate of the time left:
    the rate since the first report carried to the end (so that set-up before the first
    report, such as compiling, does not count as work still to come)."""

    def __init__(self, label: str, enabled: bool = True, stream=None):
        self.label, self.enabled = label, enabled
        self.stream = stream or sys.stderr
        self.start = self._last = time.perf_counter()
        self._first: tuple[float, int] | None = None
        self.width = 0
        self.tty = bool(getattr(self.stream, "isatty", lambda: False)())
        self._tenth = -1  # a file or pipe gets a line at each tenth done, not a redrawn bar

    def __call__(self, done: int, total: int) -> None:
        now = time.perf_counter()
        if self._first is None:
            self._first = (now, done)
        if not self.enabled or (now - self._last < 0.1 and done < total):
            return
        self._last = now
        frac = done / total if total else 1.0
        bar = "#" * int(30 * frac)
        line = f"{self.label} [{bar:<30}] {100 * frac:5.1f}%  {now - self.start:6.1f} s{self._left(now, done, total)}"
        if not self.tty:
            self._line(line.rstrip(), int(10 * frac), done >= total)
            return
        self.width = max(self.width, len(line))
        self.stream.write("\r" + line)
        if done >= total:
            self.stream.write("\n")
            _forget(self)
        elif self not in _DRAWN:
            _DRAWN.append(self)
        self.stream.flush()

    def _line(self, line: str, tenth: int, finished: bool) -> None:
        """A whole line when a tenth more is done (a log keeps no carriage returns)."""
        if tenth > self._tenth or finished:
            self._tenth = 10 if finished else tenth
            self.stream.write(line + "\n")
            self.stream.flush()

    def _left(self, now: float, done: int, total: int) -> str:
        t0, d0 = self._first
        rate = (done - d0) / (now - t0) if done > d0 and now > t0 else 0.0
        return left(now - t0, (done - d0) / (total - d0) if total > d0 else 1.0) if rate else " " * 22

    def clear(self) -> None:
        """Erase the bar's line (it stays when finished: its last line is a record)."""
        if not self.tty:
            return
        self.stream.write("\r" + " " * self.width + "\r")
        self.stream.flush()
        _forget(self)


def _forget(bar: Progress) -> None:
    if bar in _DRAWN:
        _DRAWN.remove(bar)


def clear() -> None:
    """Erase every bar left unfinished (before a line of output)."""
    for bar in list(_DRAWN):
        bar.clear()


def left(elapsed: float, frac: float) -> str:
    """``", about 2.5 min left"`` at the fraction ``frac`` done after ``elapsed`` s ('' too early or when done)."""
    remaining = elapsed * (1 - frac) / frac if frac > 0 else 0.0
    if frac >= 1.0 or frac < 0.01 or elapsed < 1.0 or remaining < 1.0:
        return " " * 22
    from mbs.run_cost import duration

    return f", about {duration(remaining)} left".ljust(22)
