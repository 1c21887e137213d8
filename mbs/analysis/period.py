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
main-rotor revolutions. A flapping one repeats then too, its blades' states exchanged: after
``P`` blade passages the blade at blade ``j``'s place is blade ``j - P`` (mod ``N``), so ``S`` is
that permutation of the tail blades' states, and the whole period is reached when the blades
are back at their own places.

A gear ratio without a short common period (more than :data:`mbs.aircraft.checks.MAX_PERIOD_REVS`
revolutions; the UH-60A's 4.6155 repeats after 500) is replaced, in the periodic analyses
only, by the nearest ratio that repeats within it (:func:`mbs.aircraft.checks.periodic_gear`:
60/13 for the UH-60A, a tail-rotor speed 0.0025 % low): :func:`periodic_scene` is the scene
whose model turns at that ratio, :attr:`RotorPeriod.gear` states it and its error. Simulations
keep the aircraft's ratio.
"""
from __future__ import annotations

import math
import re
from dataclasses import dataclass, replace
from fractions import Fraction

import numpy as np

TEETER_STATES = ("seesaw.teeter", "seesaw.teeter_rate")


@dataclass(frozen=True)
class RotorPeriod:
    """Shooting interval and symmetry of a model.

    revs: main-rotor revolutions shot over (the shortest interval after which the model
    repeats up to ``S``); full_revs: revolutions of the true common period; flip: indices of
    the states whose sign ``S`` reverses; omega: rad/s; source: ``(S x)[k] = ± x[source[k]]``,
    the states ``S`` exchanges (empty: none); gear: the tail-rotor gear ratio of the analyses
    and the aircraft's (None without a tail rotor).
    """

    revs: int
    full_revs: int
    flip: tuple[int, ...]
    omega: float
    source: tuple[int, ...] = ()
    gear: "checks.PeriodicGear | None" = None

    @property
    def revolution(self) -> float:
        """Main-rotor revolution ``2π/Ω``, s."""
        return 2 * np.pi / abs(self.omega)

    @property
    def duration(self) -> float:
        """Shooting interval ``revs · 2π/Ω``, s."""
        return self.revs * self.revolution

    def symmetry(self, nx: int) -> np.ndarray:
        """The signs of ``S`` (nx,): ``(S x)[k] = sign[k] x[source[k]]``."""
        s = np.ones(nx)
        s[list(self.flip)] = -1.0
        return s

    def permutation(self, nx: int) -> np.ndarray:
        """``source`` (nx,) of ``S``: the identity unless the interval exchanges blades' states."""
        return np.asarray(self.source, dtype=int) if self.source else np.arange(nx)

    def apply(self, x: np.ndarray) -> np.ndarray:
        """``S x`` of states ``x`` (nx, ...) along the first axis."""
        x = np.asarray(x)
        return (self.symmetry(len(x)) * x[self.permutation(len(x))].T).T if self.source or self.flip else x


def scene_period(sc, system, p=None) -> RotorPeriod:
    """The period of the scene ``sc``'s model ``system`` at the parameters ``p`` (its
    aircraft's gear ratio; ``sc`` as :func:`periodic_scene` gives it)."""
    from mbs.aircraft import checks

    gear = sc.aircraft.data["tail_rotor"]["gear_ratio"] if sc.aircraft is not None else None
    out = rotor_period(system.info, 2 * np.pi / sc.revolution(system, p), gear)
    published = sc.aircraft.data.meta.get("tail_rotor", {}).get("gear_ratio", {}).get("published") \
        if out.gear is not None else None
    if published is None:
        return out
    revs, exact = checks.rotor_period(published, checks.tail_blade_symmetry(sc.aircraft.data["tail_rotor"]))
    return replace(out, gear=replace(out.gear, ratio=published, exact_revs=revs if exact else None))


def periodic_scene(sc, max_revs: int | None = None):
    """``sc`` (a :class:`mbs.scenes.Scene`) as the periodic analyses model it: itself unless its
    aircraft's tail rotor does not repeat within ``max_revs`` (default
    :data:`mbs.aircraft.checks.MAX_PERIOD_REVS`) revolutions; then its aircraft with the gear
    ratio of :func:`mbs.aircraft.checks.periodic_gear` (the data's ``meta`` keeps the aircraft's
    own). Without ``max_revs``, a scene whose ratio repeats within the bound is itself (idempotent)."""
    from mbs import aircraft as ac
    from mbs.aircraft import checks

    craft = getattr(sc, "aircraft", None)
    if craft is None:
        return sc
    tr = craft.data["tail_rotor"]
    if max_revs is None and checks.periodic_gear(tr["gear_ratio"], checks.tail_blade_symmetry(tr)).exact:
        return sc
    gear = _aircraft_gear(craft, max_revs)
    if gear.used == tr["gear_ratio"]:
        return sc
    data = ac.Data({k: dict(v) if isinstance(v, dict) else v for k, v in craft.data.items()})
    data.meta = {k: dict(v) for k, v in craft.data.meta.items()}
    data["tail_rotor"]["gear_ratio"] = gear.used
    data.meta["tail_rotor"]["gear_ratio"] = {**data.meta["tail_rotor"].get("gear_ratio", {}), "published": gear.ratio,
                                             "note": gear.text()}
    return replace(sc, aircraft=replace(craft, data=data))


def _aircraft_gear(craft, max_revs: int | None = None) -> "checks.PeriodicGear":
    """The periodic gear of an aircraft, from its own ratio (before :func:`periodic_scene`)."""
    from mbs.aircraft import checks

    tr = craft.data["tail_rotor"]
    ratio = craft.data.meta.get("tail_rotor", {}).get("gear_ratio", {}).get("published", tr["gear_ratio"])
    return checks.periodic_gear(ratio, checks.tail_blade_symmetry(tr), max_revs or checks.MAX_PERIOD_REVS)


def rotor_period(info, omega: float, gear_ratio: float | None = None) -> RotorPeriod:
    """The period of a model described by ``info`` (:class:`mbs.backends.info.ModelInfo`).

    gear_ratio: tail-rotor speed over main-rotor speed, needed when the model has a tail rotor
    (output ``tail_rotor.azimuth``). ValueError when the rotors repeat only after more than
    :data:`mbs.aircraft.checks.MAX_PERIOD_REVS` revolutions (:func:`periodic_scene` first).
    """
    from mbs.aircraft import checks

    if "tail_rotor.azimuth" not in info.output_names:
        return RotorPeriod(1, 1, (), omega)
    if gear_ratio is None:
        raise ValueError("the model has a tail rotor: its period needs the tail-rotor gear ratio")
    teetering = all(n in info.state_names for n in TEETER_STATES)
    blades = _tail_blades(info)
    gear = checks.periodic_gear(gear_ratio, 1 if teetering else max(1, len(blades)))
    if not gear.exact:
        raise ValueError(f"{gear.text()}: this analysis needs a tail-rotor speed that repeats sooner; give the "
                         f"aircraft file's tail rotor a gear ratio of e.g. {gear.used:.6g} (gear_ratio, or its omega or "
                         "tip_speed to match)")
    if teetering:
        half = Fraction(2 * gear_ratio).limit_denominator(1000).denominator
        flip = tuple(info.state_names.index(n) for n in TEETER_STATES) if half != gear.revs else ()
        return RotorPeriod(half if flip else gear.revs, gear.revs, flip, omega, gear=gear)
    source, order = _exchange(info, blades, round(gear_ratio * len(blades) * gear.revs))
    return RotorPeriod(gear.revs, gear.revs * order, (), omega, source, gear)


def _tail_blades(info) -> list[str]:
    return [n for n in info.body_names if re.fullmatch(r"tail_blade\d+", n)]


def _exchange(info, blades: list[str], passages: int) -> tuple[tuple[int, ...], int]:
    """``source`` of ``S`` after ``passages`` blade passages (empty when the blades have no
    states or are back at their own places) and the number of intervals until they are."""
    n, names = len(blades), info.state_names
    own = [i for i, s in enumerate(names) if s.split(".")[0] in blades]
    shift = passages % n if n else 0
    if not shift or not own:
        return (), 1
    index = {s: i for i, s in enumerate(names)}
    source = list(range(len(names)))
    for i in own:
        blade, rest = names[i].split(".", 1)
        k = int(blade[len("tail_blade"):]) - 1
        source[i] = index[f"tail_blade{(k - shift) % n + 1}.{rest}"]
    return tuple(source), n // math.gcd(shift, n)


def tail_collective_error(speed_error: float, thrust_coefficient: float, sigma_a: float, inflow_ratio: float) -> float:
    """Estimated error (rad) of a trim's tail collective when the tail rotor turns
    ``1 + speed_error`` times too fast: at the thrust the trim needs, ``C_T ∝ 1/Ω_T²`` and the
    inflow ratio ``λ ∝ 1/Ω_T``, so blade-element momentum theory's ``C_T = σ a/2 (θ/3 − λ/2)``
    moves the collective by ``−ε (12 C_T/(σ a) + 3 λ/2)``."""
    return -speed_error * (12 * thrust_coefficient / sigma_a + 1.5 * inflow_ratio)
