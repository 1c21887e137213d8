"""Tip loss as an effective blade radius ``B R``: no lift outboard of it.

Prandtl's tip-loss factor, approximated for a rotor in hover by the effective radius
``B = 1 − sqrt(2 C_T) / N_b`` (Prandtl via W. Johnson, *Helicopter Theory*, §3.5; Padfield,
*Helicopter Flight Dynamics*, §3.2). An effective radius rather than Prandtl's radial
function ``F(r)``: ``F`` falls from 0.9 to 0 over the outer 2–3 % of the radius, which eight
strips of 0.1 R cannot resolve, while ``B R`` cuts the outer strip's lift by the fraction
beyond it, a constant, smooth in every state. The momentum balance then acts on the
effective disc ``B² A``, so the induced velocity rises by ``1/B`` at the same thrust.
"""
from __future__ import annotations

import numpy as np


def effective_radius_factor(thrust_coefficient: float, n_blades: int) -> float:
    """Prandtl's ``B = 1 − sqrt(2 C_T) / N_b`` (–)."""
    return 1.0 - np.sqrt(2.0 * thrust_coefficient) / n_blades


def lift_factors(radii: np.ndarray, width: float, tip_radius: float) -> list[float]:
    """Share (0..1) of each strip (mid-radii ``radii``, width ``width``, m) inboard of
    ``tip_radius`` (m): the lift factor of its strip; 1.0 exactly where it is whole."""
    share = np.clip((tip_radius - (radii - width / 2)) / width, 0.0, 1.0)
    return [1.0 if s >= 1.0 else float(s) for s in share]
