"""The period of a rotorcraft model with a driven main rotor and, optionally, a tail rotor.

The driven hubs make the equations of motion time-periodic. The main rotor repeats after one
revolution ``T = 2π/Ω``; the Bo105 tail rotor turns ``g = 5.25`` times faster, so main and
tail rotor azimuths repeat together after 4 main-rotor revolutions (21 tail revolutions).

A two-bladed teetering tail rotor also repeats after half a tail revolution with the teeter
angle reversed: turned by π about its shaft, the seesaw at teeter ``β`` is the seesaw at
``-β`` with its (identical) blades exchanged. After 2 main-rotor revolutions the tail rotor
has turned 10.5 times, so the whole model satisfies

    f(x, t + 2T) = S f(S x, t),   S = diag(±1) reversing ``seesaw.teeter`` and its rate,

and a solution with ``x(2T) = S x(0)`` repeats after ``4T``. The trim therefore shoots over
``2T`` with the symmetry ``S`` (half the cost of ``4T``), and the monodromy of the full
period is ``(S M_2T)²``.

A rigid tail rotor of ``N`` identical blades has no states of its own: the model repeats when
the tail rotor has turned by a multiple of ``2π/N``, after the denominator of ``g N``
main-rotor revolutions. A ratio without a small denominator gives no usable period: refused
beyond :data:`mbs.aircraft.checks.MAX_PERIOD_REVS` revolutions.
"""
from __future__ import annotations

from dataclasses import dataclass
from fractions import Fraction

import numpy as np

TEETER_STATES = ("seesaw.teeter", "seesaw.teeter_rate")


@dataclass(frozen=True)
class RotorPeriod:
    """Shooting interval and symmetry of a model.

    revs: main-rotor revolutions shot over (the shortest interval after which the model
    repeats up to ``S``); full_revs: revolutions of the true common period; flip: indices of
    the states whose sign ``S`` reverses (empty when ``revs == full_revs``); omega: rad/s.
    """

    revs: int
    full_revs: int
    flip: tuple[int, ...]
    omega: float

    @property
    def revolution(self) -> float:
        """Main-rotor revolution ``2π/Ω``, s."""
        return 2 * np.pi / abs(self.omega)

    @property
    def duration(self) -> float:
        """Shooting interval ``revs · 2π/Ω``, s."""
        return self.revs * self.revolution

    def symmetry(self, nx: int) -> np.ndarray:
        """``S`` as a vector of signs (nx,): ``x(revs T) = S x(0)`` on a periodic solution."""
        s = np.ones(nx)
        s[list(self.flip)] = -1.0
        return s


def scene_period(sc, system, p=None) -> RotorPeriod:
    """The period of the scene ``sc``'s model ``system`` at the parameters ``p`` (its
    aircraft's gear ratio)."""
    gear = sc.aircraft.data["tail_rotor"]["gear_ratio"] if sc.aircraft is not None else None
    return rotor_period(system.info, 2 * np.pi / sc.revolution(system, p), gear)


def rotor_period(info, omega: float, gear_ratio: float | None = None) -> RotorPeriod:
    """The period of a model described by ``info`` (:class:`mbs.backends.info.ModelInfo`).

    gear_ratio: tail-rotor speed over main-rotor speed, needed when the model has a tail rotor
    (output ``tail_rotor.azimuth``). ValueError when the rotors repeat only after more than
    :data:`mbs.aircraft.checks.MAX_PERIOD_REVS` revolutions.
    """
    from mbs.aircraft import checks

    if "tail_rotor.azimuth" not in info.output_names:
        return RotorPeriod(1, 1, (), omega)
    if gear_ratio is None:
        raise ValueError("the model has a tail rotor: its period needs the tail-rotor gear ratio")
    teetering = all(n in info.state_names for n in TEETER_STATES)
    blades = 1 if teetering else max(1, sum(n.startswith("tail_blade") for n in info.body_names))
    problem = checks.period_problem(gear_ratio, blades)
    if problem:
        raise ValueError(problem)
    full = checks.rotor_period(gear_ratio, blades)[0]
    half = Fraction(2 * gear_ratio).limit_denominator(1000).denominator
    if not teetering or half == full:
        return RotorPeriod(full, full, (), omega)
    return RotorPeriod(half, full, tuple(info.state_names.index(n) for n in TEETER_STATES), omega)
