"""Elastic main-rotor blades as flexible bodies with modal coordinates (:mod:`mbs.flexible`).

The blade of the aircraft file (:func:`mbs.flexible.uniform_blade.blade_from_data`: the
uniform blade clamped at the rigid blade's hinge radius, with the ``[elastic_blade]``
stiffnesses and structural damping) carries ``cfg.blade_modes`` modes per direction, the
blade's own rotating modes at the rotor's nominal speed; its mass sits on Gauss–Legendre
sections and the blade elements of the rotor act on massless sections at the element radii,
whose motion (position, velocity, turn by slopes and twist) the aerodynamics reads as it
reads a rigid blade's. The flexible body ``blade<k>`` hangs on the hub after the pitch
bearing; its coordinates are ``blade<k>.flap``, ``.flap2``, … ``.lag``, … ``.torsion``, …
(tip deflection over the blade length, tip twist; rad). With the scene's dampers the modes
have the data's structural damping (stiffness-proportional, as on the segmented blade's
hinges); the rigid blade's lag damper (``main_rotor.lag_damping``) stands for a lag hinge's
damper, which a hingeless modal blade does not have: it is not applied.
"""
from __future__ import annotations

from typing import Sequence

import numpy as np

from mbs.flexible.beam import ModalBlade
from mbs.flexible.body import add_flexible_blade, aero_name
from mbs.flexible.uniform_blade import blade_from_data
from mbs.joints import Joint
from mbs.models import elastic_blade as eb
from mbs.tree import Model


def modal_blade(d, modes, sense: int = 1, nodes: int | None = None) -> ModalBlade:
    """The blade of the aircraft data ``d`` with ``modes`` per direction (see
    :class:`mbs.flexible.beam.ModalBlade`), shapes at the nominal rotor speed."""
    if "elastic_blade" not in d or not d["elastic_blade"]:
        raise ValueError("elastic blades need the aircraft file's [elastic_blade] section (first torsion frequency "
                         "and structural damping); this aircraft has none")
    return ModalBlade(blade_from_data(d), modes, d["main_rotor"]["omega"], sense, nodes)


def aero_radii(d, cfg) -> np.ndarray:
    """Radii (m) of the main rotor's blade elements (:meth:`mbs.aero.Rotor.stations`)."""
    mr = d["main_rotor"]
    r0 = mr["root_cutout"] * mr["radius"]
    n = int(cfg.elements or mr["elements"])
    return r0 + (mr["radius"] - r0) / n * (np.arange(n) + 0.5)


def add_modal_blade(m: Model, d, cfg, k: int, frame: np.ndarray, inboard: Sequence[Joint] = (),
                    sense: int = 1) -> list[str]:
    """Blade ``k`` (from 0) of the main rotor of the aircraft data ``d`` with ``cfg.blade_modes``
    modes per direction on ``main_hub``, after the ``inboard`` joints (the pitch bearing)."""
    beam = modal_blade(d, cfg.blade_modes, sense)
    root = beam.blade.root
    stations = aero_radii(d, cfg) - root if cfg.rotor_aero else ()
    return add_flexible_blade(m, beam, f"blade{k + 1}", "main_hub", root * frame[:, 0], frame, inboard, stations,
                              cfg.dampers, eb.COLORS[k % len(eb.COLORS)])


STATIONS = 8
"""A modal blade's load stations: the joints of the 8-segment blade (``elastic-rotor``), so that
``blade<k>.station<j>`` (j = 2 … 8) names the same radius on either blade."""


def station_radii(d) -> dict[int, float]:
    """Station number ``j`` -> radius (m from the rotor axis) of the modal blade's load
    stations (:data:`STATIONS`) on the blade of the aircraft data ``d``."""
    hinges = eb.layout(blade_from_data(d), STATIONS)[0]
    return {j: float(hinges[j - 1]) for j in range(2, STATIONS + 1)}


def rotor_pieces(d, cfg) -> dict[str, list[tuple[str, float]]]:
    """The main rotor's :attr:`mbs.aero.Rotor.pieces`: the bodies carrying its blade elements
    (segments of a segmented blade, the element sections of a modal one; none when rigid)."""
    if not cfg.blade_modes:
        return eb.rotor_pieces(d, cfg)
    radii = aero_radii(d, cfg).tolist()
    blades = [f"blade{k + 1}" for k in range(cfg.blade_count(d["main_rotor"]["n_blades"]))]
    return {b: [(aero_name(b, j + 1), r) for j, r in enumerate(radii)] for b in blades}
