"""Sweep grids: ``LO:HI:N`` ranges, ``NAME=LO:HI:N`` axes and their points.

A point is one combination of axis values (a dict name -> value); the grid is the
Cartesian product of the axes, in the order given, the first axis varying slowest.
"""
from __future__ import annotations

import itertools

import numpy as np

KEY_DIGITS = 9
"""Input values are matched (resume) after rounding to this many decimals, so that the same
point of ``0:70:15`` and ``0:70:29`` is recognised despite round-off in ``linspace``."""


MAX_POINTS = 1000
"""Points on one axis at most."""


def parse_range(flag: str, text: str, ends=None) -> np.ndarray:
    """``"LO:HI:N"`` -> N evenly spaced values from LO to HI (inclusive); ``flag`` names the
    option in errors, e.g. ``--speed '0:70' must be LO:HI:N``. ``ends(lo, hi)`` reads LO and HI
    (default: plain numbers; :func:`mbs.arguments.speed_ends` takes them with a unit)."""
    from mbs.arguments import Bad

    parts = str(text).split(":")
    try:
        if len(parts) != 3:
            raise ValueError
        (lo, hi), n = (ends or (lambda a, b: (float(a), float(b))))(parts[0], parts[1]), int(parts[2])
    except Bad as exc:
        raise ValueError(f"{flag} {text!r}: {exc}") from None
    except (ValueError, IndexError):
        raise ValueError(f"{flag} {text!r} must be LO:HI:N (e.g. 0:70:15{', or 0:100kt:11' if ends else ''})") from None
    if n < 1 or not (np.isfinite(lo) and np.isfinite(hi)):
        raise ValueError(f"{flag} {text!r}: N must be >= 1 and LO, HI finite")
    if n > MAX_POINTS:
        raise ValueError(f"{flag} {text!r}: {n} points on one axis is more than a sweep can finish (at most "
                         f"{MAX_POINTS}: each point is a trim, a run or a Floquet analysis of seconds); give fewer")
    if n == 1 and lo != hi:
        raise ValueError(f"{flag} {text!r}: N = 1 gives LO ({lo:g}) only, never HI ({hi:g}); give N >= 2")
    return np.linspace(lo, hi, n)


def parse_axis(flag: str, text: str) -> tuple[str, np.ndarray]:
    """``"NAME=LO:HI:N"`` -> ``(NAME, values)``."""
    name, sep, rng = str(text).partition("=")
    try:
        if not sep or not name.strip():
            raise ValueError
        return name.strip(), parse_range(flag, rng)
    except ValueError:
        raise ValueError(f"{flag} {text!r} must be NAME=LO:HI:N with N >= 1 (e.g. collective=0.2:0.3:5)") from None


def points(axes: dict[str, np.ndarray]) -> list[dict[str, float]]:
    """Every combination of the axis values, the first axis varying slowest."""
    names = list(axes)
    return [dict(zip(names, map(float, combo))) for combo in itertools.product(*axes.values())]


def key(inputs: dict[str, float], names: list[str]) -> tuple[float, ...]:
    """The identity of a point: its inputs in axis order, rounded to :data:`KEY_DIGITS`."""
    return tuple(round(float(inputs[n]), KEY_DIGITS) for n in names)
