"""Published eigenvalues against the model's at one speed: each published eigenvalue is paired
with one of the model's so that the sum of the distances in the complex plane is least (the
assignment problem; a published table rarely names its modes, and a name would not survive a
mode that changes character with speed), then judged (:class:`mbs.validate.data.EigenTolerance`):

* stability: the signs of the real parts agree (a real part within ``±neutral`` matches either);
* size: an oscillatory published mode (``|Im| >= min_frequency``) by its frequency ``|Im λ|``,
  a real one by its rate ``|λ|`` (the inverse time constant; the model's may be an overdamped
  pair), within the fraction ``frequency``; a published real eigenvalue within ``±neutral`` of
  zero (a spiral or heading mode near neutral) by its stability only.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np


@dataclass
class Pair:
    """A published eigenvalue and the model's paired with it (1/s, rad/s), the model's mode
    name, and the verdicts (``ratio`` ours / published of ``measure``; None when only the stability is judged)."""

    speed: float
    published: complex
    ours: complex
    mode: str
    same_stability: bool
    ratio: float | None
    measure: str
    within: bool

    def summary(self) -> dict:
        c = lambda z: [z.real, z.imag]  # noqa: E731
        return {"speed": self.speed, "published": c(self.published), "ours": c(self.ours), "mode": self.mode,
                "same_stability": self.same_stability, "ratio": self.ratio, "measure": self.measure,
                "within": self.within}


def stability(re: float, neutral: float) -> int:
    """-1 stable, +1 unstable, 0 neutral (``|re| <= neutral``)."""
    return 0 if abs(re) <= neutral else (1 if re > 0 else -1)


def pair(published: np.ndarray, ours: np.ndarray, names: list[str], speed: float, tol) -> list[Pair]:
    """The least-distance pairing of ``published`` (n,) with ``ours`` (m,), m >= n, complex."""
    from scipy.optimize import linear_sum_assignment

    cost = np.abs(published[:, None] - ours[None, :])
    rows, cols = linear_sum_assignment(cost)
    return [_judge(published[i], ours[j], names[j], speed, tol) for i, j in zip(rows, cols)]


def _judge(pub: complex, our: complex, name: str, speed: float, tol) -> Pair:
    a, b = stability(pub.real, tol.neutral), stability(our.real, tol.neutral)
    same = a == b or 0 in (a, b)
    measure, ratio = size(pub, our, tol)
    within = same and (ratio is None or abs(ratio - 1.0) <= tol.frequency)
    return Pair(speed, complex(pub), complex(our), name, bool(same), ratio, measure, bool(within))


def size(pub: complex, our: complex, tol) -> tuple[str, float | None]:
    """``(measure, ours / published)``: the frequency of an oscillatory published mode, the rate
    of a real one, nothing for a real one within the neutral band."""
    if abs(pub.imag) >= tol.min_frequency:
        return "frequency", float(abs(our.imag) / abs(pub.imag))
    if abs(pub.real) > tol.neutral:
        return "rate", float(abs(our) / abs(pub))
    return "stability only", None


def model_eigenvalues(derivatives) -> tuple[np.ndarray, list[str]]:
    """Every eigenvalue of the model's ``A`` (both of a complex pair) and its mode's name."""
    values, names = [], []
    for m in derivatives.modes:
        lam = complex(m.eigenvalue)
        for z in ((lam, lam.conjugate()) if abs(lam.imag) > 0 else (lam,)):
            values.append(z)
            names.append(m.name)
    return np.array(values), names


def pairs_at(eigen_set, point, tol) -> list[Pair]:
    """The pairs of one :class:`mbs.validate.data.EigenSet` with the model's point (empty when the
    model has no derivatives there)."""
    if not point.ok or point.derivatives is None:
        return []
    ours, names = model_eigenvalues(point.derivatives)
    if len(ours) < len(eigen_set.value):
        raise ValueError(f"{len(eigen_set.value)} published eigenvalues at {eigen_set.shown_speed:g} but the model "
                         f"has {len(ours)}")
    return pair(eigen_set.value, ours, names, eigen_set.shown_speed, tol)


