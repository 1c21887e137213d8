"""Elastic main-rotor blades as chains of rigid segments on flap, lag and torsion hinges.

The blade is a uniform beam clamped at the rigid blade's hinge radius (the rotor axis for
the Bo105's centre-spring equivalent) out to the tip, cut into ``n`` rigid segments of
length ``Δ = (tip - root) / n``. Segment ``j`` (root first) hangs on its inboard neighbour,
the first on the hub (after the pitch bearing), by flap, lag and torsion hinges in series,
with the rigid blade's axes and signs (flap about -y, tip up; lag about -z, lagging;
torsion about x, nose up; lag and torsion about +z and -x on a rotor turning against its
thrust axis, :mod:`mbs.models.helicopter.frames`). The hinges sit a quarter of ``Δ`` outboard of ``root + j Δ``:
with hinges at the segment ends the chain is too soft, at their middles too stiff, by about
the same amount (lag frequency -2.6 % and +2.6 % at n = 8), and the quarter points leave
-0.8 %. Each hinge's spring is ``EI`` (``GJ`` in torsion) over the span it stands for,
from half-way to its inboard neighbour to half-way to its outboard one (the root and the
tip closing the first and the last). Each segment carries the blade's mass per length with
the inertia of a box (its length, chord, thickness), the root stub's mass lumped on the
first hinge, so the centrifugal stiffening, the propeller moment in torsion and the
couplings come from the multibody dynamics itself. When the scene has dampers, every hinge
carries structural damping proportional to its spring (``[elastic_blade]
structural_damping``: that ratio at the direction's first frequency, more on higher modes)
and the root lag hinge the rigid blade's lag damper (``main_rotor.lag_damping``).

The aircraft file gives the blade's first rotating frequencies (``[elastic_blade]``; see
:mod:`mbs.aircraft`), and the loader derives the stiffnesses ``EI`` and ``GJ`` of the
continuous blade that has them (:func:`mbs.flexible.uniform_blade.calibrate`, on
:func:`~mbs.flexible.uniform_blade.beam_frequencies`: finite elements of the rotating uniform
beam, independent of the multibody model). The segmented blade's own frequencies:
:func:`mbs.analysis.blade_modes.segmented_frequencies`. Segment bodies are ``<blade>`` (the root
segment, whose coordinates are ``<blade>.pitch``, ``.flap``, ``.lag``, ``.torsion``) and
``<blade>_2`` … ``<blade>_<n>``.
"""
from __future__ import annotations

from typing import Sequence

import numpy as np

from mbs.flexible.uniform_blade import DIRECTIONS, Blade, blade_from_data
from mbs.joints import Hinge, Joint, Serial
from mbs.tree import Model

AXES = {"flap": (0.0, -1.0, 0.0), "lag": (0.0, 0.0, -1.0), "torsion": (1.0, 0.0, 0.0)}
"""Hinge axes of a blade turning about its thrust axis; :func:`axes` for either sense."""


def axes(sense: int = 1) -> dict[str, tuple[float, float, float]]:
    """The hinge axes of a blade on a rotor of ``sense`` (+1 turning about its thrust axis)."""
    return {"flap": AXES["flap"], "lag": (0.0, 0.0, -sense * 1.0), "torsion": (sense * 1.0, 0.0, 0.0)}


def segment_names(blade: str, n: int) -> list[str]:
    """Body names of the ``n`` segments of ``blade``, root first."""
    return [blade] + [f"{blade}_{j}" for j in range(2, n + 1)]


HINGE_POSITION = 0.25
"""Where a segment's hinges sit, as a fraction of ``Δ`` outboard of ``root + j Δ``."""


def layout(blade: Blade, n: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Hinge radii (m from the rotor axis), segment lengths (m) and the span each hinge's
    spring stands for (m), each (n,), root first."""
    step = blade.length / n
    hinges = blade.root + (np.arange(n) + HINGE_POSITION) * step
    spans = np.diff(np.r_[blade.root, (hinges[1:] + hinges[:-1]) / 2, blade.tip])
    return hinges, np.diff(np.r_[hinges, blade.tip]), spans


def pieces(blade: Blade, names: list[str], n: int) -> dict[str, list[tuple[str, float]]]:
    """For the blade-element aerodynamics: blade name -> its segments with the radius (m) of
    each segment's hinges."""
    hinges = layout(blade, n)[0]
    return {name: list(zip(segment_names(name, n), hinges.tolist())) for name in names}


def _hinges(blade: Blade, span: float, root: bool, dampers: bool, sense: int = 1) -> list[Joint]:
    """Flap, lag and torsion hinges with the springs of ``span`` (m) of blade; with
    ``dampers``, the structural damping and, at the root, the lag damper."""
    root_lag = blade.lag_damping if dampers and root else 0.0
    stiff = {k: blade.stiffness(k) / span for k in DIRECTIONS}
    damping = {k: (t * stiff[k] if dampers else 0.0) + (root_lag if k == "lag" else 0.0)
               for k, t in zip(DIRECTIONS, blade.damping_time)}
    return [Hinge(axes(sense)[k], name=k, stiffness=stiff[k], damping=damping[k]) for k in DIRECTIONS]


def _segment_inertia(blade: Blade, length: float, stub: float) -> tuple[float, np.ndarray, np.ndarray]:
    """Mass (kg), centre of mass (3,) and inertia about it (3, 3) of a segment of ``length``
    (m) from its hinge, with the mass of ``stub`` (m) of blade lumped on the hinge."""
    mass, extra = blade.mass * length, blade.mass * stub
    com = mass / (mass + extra) * length / 2
    box = mass / 12 * np.diag([blade.chord**2 + blade.thickness**2, length**2 + blade.thickness**2,
                              length**2 + blade.chord**2])
    shift = mass * (length / 2 - com) ** 2 + extra * com**2  # parallel axes, offsets along x
    return mass + extra, np.array([com, 0.0, 0.0]), box + np.diag([0.0, shift, shift])


def check_segments(n) -> int:
    """The segment count ``n`` of an elastic blade as an int; ValueError unless a whole number >= 1."""
    if isinstance(n, bool) or not isinstance(n, (int, np.integer)) or n < 1:
        raise ValueError(f"blade_segments = {n!r}: an elastic blade needs a whole number of segments >= 1")
    return int(n)


def add_segmented_blade(m: Model, blade: Blade, n: int, name: str, parent: str, frame: np.ndarray,
                        inboard: Sequence[Joint] = (), dampers: bool = True, color: str = "#d62728",
                        sense: int = 1) -> list[str]:
    """Add ``blade`` cut into ``n`` segments to ``m``, hanging on ``parent`` with the hub-frame
    axes ``frame`` (x along the span), after the ``inboard`` joints (e.g. the pitch bearing;
    without rates: a free one would turn about the root torsion hinge's axis), on a rotor of
    ``sense`` (:func:`axes`). Returns the segment names, root first."""
    n = check_segments(n)
    if any(j.nv for j in inboard):
        raise ValueError(f"blade {name!r}: an elastic blade needs a driven pitch bearing or none; a free one "
                         "(rotors='free' with pitch_hinge) turns about the root torsion hinge's axis")
    names, (hinges, lengths, spans) = segment_names(name, n), layout(blade, n)
    for j, body in enumerate(names):
        root = j == 0
        mass, com, inertia = _segment_inertia(blade, lengths[j], hinges[0] - blade.root if root else 0.0)
        joint = Serial(*(inboard if root else ()), *_hinges(blade, spans[j], root, dampers, sense))
        shape = {"kind": "box", "size": [lengths[j], blade.chord, blade.thickness],
                 "offset": [lengths[j] / 2, 0, 0], "color": color}
        m.add_body(body, parent if root else names[j - 1], joint, mass=mass, com=com, inertia=inertia,
                   at=hinges[0] * frame[:, 0] if root else (lengths[j - 1], 0, 0), frame=frame if root else None,
                   shape=shape)
    return names


COLORS = ("#d62728", "#1f77b4", "#2ca02c", "#ff7f0e")  # per blade, as the rigid blades'


def add_elastic_blade(m: Model, d, cfg, k: int, frame: np.ndarray, inboard: Sequence[Joint] = (),
                      sense: int = 1) -> list[str]:
    """Blade ``k`` (from 0) of the main rotor of the aircraft data ``d`` as ``cfg.blade_segments``
    segments on ``main_hub`` (``cfg``: :class:`mbs.models.helicopter.Config`)."""
    if "elastic_blade" not in d or not d["elastic_blade"]:
        raise ValueError("elastic blades need the aircraft file's [elastic_blade] section (first torsion frequency "
                         "and structural damping); this aircraft has none")
    return add_segmented_blade(m, blade_from_data(d), cfg.blade_segments, f"blade{k + 1}", "main_hub", frame,
                               inboard, cfg.dampers, COLORS[k % len(COLORS)], sense)


def rotor_pieces(d, cfg) -> dict[str, list[tuple[str, float]]]:
    """The main rotor's :attr:`mbs.aero.Rotor.pieces`: none with rigid blades."""
    if not cfg.blade_segments:
        return {}
    blades = range(cfg.blade_count(d["main_rotor"]["n_blades"]))
    return pieces(blade_from_data(d), [f"blade{k + 1}" for k in blades], cfg.blade_segments)
