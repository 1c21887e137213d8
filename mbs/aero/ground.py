"""Ground effect on a rotor's induced inflow: Cheeseman and Bennett's image rotor, in hover and
forward flight.

The ground's mirror image of the rotor's wake reduces the induced velocity at the disc. Cheeseman
and Bennett (ARC R&M 3021, 1955) estimate that at constant power a rotor at the height ``z`` (m,
hub above ground) of radius ``R`` gives the thrust

    T_IGE / T_OGE = 1 / k,   k = 1 − (R/4z)² / (1 + (V/v)²),

``V`` the speed of the air along the disc and ``v`` the induced velocity (the image's upwash swept
behind the rotor in forward flight). Momentum theory ties the induced velocity to the thrust,
``v ∝ √T``, so a rotor holding its induced power ``P_i = T v_disc`` with ``v_disc = f v`` lifts
``f^(−2/3)`` times its out-of-ground thrust: the blades here see ``f = k^(3/2)`` times the inflow
state's induced velocity, and the ideal rotor reproduces Cheeseman and Bennett's ratio exactly.
The image model holds far from the ground; near it ``(R/4z)²`` is bounded smoothly by
:data:`BOUND` (``z ≥ R/2``, where the fuselage and the ground's flow dominate; a soft clip of order
16, 2e-10 below the plain term at ``z = R``). Units: SI.
"""
from __future__ import annotations

import casadi as ca

from mbs.aero.sections import soft_clip

BOUND = 0.25  # largest (R/4z)², at z = R/2 (a smooth bound)


def image_term(height, radius: float):
    """``(R/4z)²`` bounded smoothly below :data:`BOUND` (``height`` m, any sign: a hub below the
    ground's plane takes the bound)."""
    return soft_clip((radius / 4) ** 2 / (height**2 + 1e-12), BOUND, 16)


def cheeseman_bennett(height, radius: float, inplane2, induced):
    """Cheeseman and Bennett's ``k`` at the hub ``height`` (m), the air's in-plane speed squared
    ``inplane2`` (m²/s²) and the induced velocity ``induced`` (m/s)."""
    return 1 - image_term(height, radius) / (1 + inplane2 / (induced**2 + 1e-6))


def inflow_factor(height, radius: float, inplane2, induced):
    """``f = k^(3/2)``: the share of the induced velocity the blades see in ground effect."""
    k = cheeseman_bennett(height, radius, inplane2, induced)
    return k * ca.sqrt(k)
