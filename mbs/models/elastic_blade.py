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
continuous blade that has them (:func:`calibrate`, on :func:`beam_frequencies`: finite elements of the rotating uniform
beam, independent of the multibody model). Segment bodies are ``<blade>`` (the root
segment, whose coordinates are ``<blade>.pitch``, ``.flap``, ``.lag``, ``.torsion``) and
``<blade>_2`` … ``<blade>_<n>``.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Sequence

import numpy as np
from scipy.linalg import eigh
from scipy.optimize import brentq

from mbs.joints import Hinge, Joint, Serial
from mbs.tree import Model

DIRECTIONS = ("flap", "lag", "torsion")
AXES = {"flap": (0.0, -1.0, 0.0), "lag": (0.0, 0.0, -1.0), "torsion": (1.0, 0.0, 0.0)}
"""Hinge axes of a blade turning about its thrust axis; :func:`axes` for either sense."""


def axes(sense: int = 1) -> dict[str, tuple[float, float, float]]:
    """The hinge axes of a blade on a rotor of ``sense`` (+1 turning about its thrust axis)."""
    return {"flap": AXES["flap"], "lag": (0.0, 0.0, -sense * 1.0), "torsion": (sense * 1.0, 0.0, 0.0)}
BEAM_ELEMENTS = 48  # finite elements of the continuous reference blade


@dataclass(frozen=True)
class Blade:
    """A uniform elastic blade from ``root`` to ``tip`` (m from the rotor axis): mass per
    length ``mass`` (kg/m), section ``chord`` and ``thickness`` (m; the segments' inertia),
    bending stiffness in flap and lag and torsional stiffness (N m²), the damping of the
    root lag hinge (N m s/rad) and the structural damping, stiffness-proportional: each
    hinge's damping is ``damping_time[direction]`` (s) times its spring stiffness. The axial
    stiffness ``EA`` (N) matters only where the blade is modelled as extensible
    (:mod:`mbs.flexible`); the default, infinite, is the inextensible blade."""

    root: float
    tip: float
    mass: float
    chord: float
    thickness: float
    flap_stiffness: float
    lag_stiffness: float
    torsion_stiffness: float
    lag_damping: float = 0.0
    damping_time: tuple[float, float, float] = (0.0, 0.0, 0.0)  # flap, lag, torsion
    axial_stiffness: float = float("inf")

    @property
    def length(self) -> float:
        return self.tip - self.root

    @property
    def torsional_inertia(self) -> float:
        """Polar mass moment of inertia per length about the span axis, kg m."""
        return self.mass * (self.chord**2 + self.thickness**2) / 12

    def stiffness(self, direction: str) -> float:
        return getattr(self, f"{direction}_stiffness")


def blade_from_data(d, **stiffness: float) -> Blade:
    """The blade of the aircraft data ``d`` (``mbs.aircraft.load(...).data``): the rigid blade's
    span, mass and section, the ``[elastic_blade]`` stiffnesses (or those given), lag damper
    and structural damping (the damping ratio ``structural_damping`` at each direction's first
    frequency at the nominal rotor speed: ``damping_time = 2 ζ / ω``)."""
    mr, eb = d["main_rotor"], d["elastic_blade"]
    root, tip = mr["flap_hinge_offset"], mr["radius"]
    values = {f"{k}_stiffness": stiffness[k] if k in stiffness else eb[f"{k}_stiffness"] for k in DIRECTIONS}
    times = tuple(2 * eb["structural_damping"] / (eb[f"{k}_frequency"] * mr["omega"]) for k in DIRECTIONS)
    return Blade(root, tip, mr["blade_mass"] / (tip - root), mr["chord"], mr["blade_thickness"],
                 lag_damping=mr["lag_damping"], damping_time=times, **values)


# -- the segmented blade ------------------------------------------------------------------

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


def _check(n) -> int:
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
    n = _check(n)
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


def mode_frequencies(jacobian: np.ndarray, q_names: list[str]) -> dict[str, float]:
    """The lowest frequency (rad/s, ``|λ|``) among the modes of the state Jacobian (nx, nx)
    whose shape moves the ``flap``, ``lag`` or ``torsion`` coordinates of ``q_names`` (the
    first ``len(q_names)`` states) more than all the others together."""
    lam, vec = np.linalg.eig(jacobian)
    shape = np.abs(vec[:len(q_names)])
    out = {}
    for k in DIRECTIONS:
        own = np.array([n.endswith("." + k) for n in q_names])
        moved = [i for i in range(lam.size) if lam[i].imag > 0 and shape[own, i].sum() > shape[~own, i].sum()]
        out[k] = float(min(abs(lam[i]) for i in moved))
    return out


def segmented_frequencies(n: int, data=None) -> dict[str, float]:
    """First flap, lag and torsion frequencies (rad/s, rotating frame) of one blade (of the
    aircraft ``data``, default the Bo105) of
    ``n`` segments on a hub driven at the rotor speed, in vacuum, without gravity and
    dampers: the eigenvalues of the AD Jacobian of the multibody model at the undeformed
    blade (:func:`mode_frequencies`)."""
    from mbs.dynamics import symbolic
    from mbs.linearize import rhs_jacobian
    from mbs.models import helicopter

    cfg = helicopter.Config(fuselage="none", blades=1, tail_rotor=False, rotor_aero=False, airframe_aero=False,
                            dampers=False, shaft_tilt=False, pitch_hinge=False, blade_segments=_check(n))
    model = helicopter.build(cfg, data, name=f"elastic-blade{n}")
    model.gravity = np.zeros(3)
    sym = symbolic(model)
    p = [model.parameters[k].default for k in model.parameters]
    jac = np.array(rhs_jacobian(sym["rhs"])(np.zeros(sym.layout.nx), 0.0, p))
    return mode_frequencies(jac, sym.layout.q_names)


# -- the continuous reference blade -------------------------------------------------------

GAUSS = np.polynomial.legendre.leggauss(4)
"""Gauss–Legendre points (on [-1, 1]) and weights of the element integrals."""


def hermite(xi: np.ndarray, length: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Cubic Hermite shape functions (4, q) of an element of ``length`` (m) and their first and
    second derivatives in r at ``xi`` in [0, 1]; the element's dofs are (w, w') at either end."""
    n = np.array([1 - 3 * xi**2 + 2 * xi**3, length * (xi - 2 * xi**2 + xi**3), 3 * xi**2 - 2 * xi**3,
                  length * (xi**3 - xi**2)])
    dn = np.array([(6 * xi**2 - 6 * xi) / length, 1 - 4 * xi + 3 * xi**2, (6 * xi - 6 * xi**2) / length,
                   3 * xi**2 - 2 * xi])
    ddn = np.array([(12 * xi - 6) / length**2, (6 * xi - 4) / length, (6 - 12 * xi) / length**2,
                    (6 * xi - 2) / length])
    return n, dn, ddn


def linear(xi: np.ndarray, length: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Linear shape functions (2, q) at ``xi`` in [0, 1] and their first and (zero) second derivatives."""
    return np.array([1 - xi, xi]), np.array([-np.ones_like(xi), np.ones_like(xi)]) / length, np.zeros((2, xi.size))


def element_shapes(direction: str):
    """``(shape functions, dofs per node)`` of ``direction``: cubic Hermite in bending, linear
    in torsion and extension."""
    return (linear, 1) if direction in ("torsion", "axial") else (hermite, 2)


def beam_matrices(blade: Blade, omega: float, direction: str, elements: int = BEAM_ELEMENTS
                  ) -> tuple[np.ndarray, np.ndarray]:
    """Stiffness and mass matrices of the rotating blade clamped at its root, one direction;
    the root node's dofs removed (``dofs per node * elements`` rows, root first).

    Flap and lag: Euler-Bernoulli bending with the centrifugal tension
    ``T(r) = m Ω² (R² - r²) / 2`` (lag also ``- m Ω²``); torsion: ``GJ`` with the propeller
    moment ``m Ω² (c² - t²) / 12`` per length, inertia ``m (c² + t²) / 12``; axial (extension,
    ``blade.axial_stiffness`` EA): ``EA`` with the centrifugal softening ``- m Ω²``. At
    ``omega = 0`` the stiffness is the elastic one alone."""
    shape, per_node = element_shapes(direction)
    size = per_node * (elements + 1)
    k, mm = np.zeros((size, size)), np.zeros((size, size))
    length = blade.length / elements
    xi, w = (GAUSS[0] + 1) / 2, GAUSS[1] * length / 2
    for e in range(elements):
        r = blade.root + (e + xi) * length
        n, dn, _ = shape(xi, length)
        if direction in ("torsion", "axial"):
            inertia = (blade.torsional_inertia if direction == "torsion" else blade.mass) * (n * w) @ n.T
            spring = blade.stiffness(direction) * (dn * w) @ dn.T
            spring += (omega**2 * blade.mass * (blade.chord**2 - blade.thickness**2) / 12 * (n * w) @ n.T
                       if direction == "torsion" else -omega**2 * inertia)
        else:
            tension = blade.mass * omega**2 * (blade.tip**2 - r**2) / 2
            spring = blade.stiffness(direction) / length**3 * np.array(
                [[12, 6 * length, -12, 6 * length], [6 * length, 4 * length**2, -6 * length, 2 * length**2],
                 [-12, -6 * length, 12, -6 * length], [6 * length, 2 * length**2, -6 * length, 4 * length**2]])
            spring += (dn * w * tension) @ dn.T
            inertia = blade.mass * (n * w) @ n.T
            spring -= omega**2 * inertia if direction == "lag" else 0.0
        dofs = slice(per_node * e, per_node * e + 2 * per_node)
        k[dofs, dofs] += spring
        mm[dofs, dofs] += inertia
    return k[per_node:, per_node:], mm[per_node:, per_node:]


def beam_frequencies(blade: Blade, omega: float, elements: int = BEAM_ELEMENTS) -> dict[str, float]:
    """First flap, lag and torsion frequencies (rad/s, rotating frame) of the continuous
    blade turning at ``omega`` (rad/s), by ``elements`` finite elements (cubic in bending,
    linear in torsion; converged to about 1e-5 at the default)."""
    return {k: float(np.sqrt(eigh(*beam_matrices(blade, omega, k, elements), eigvals_only=True)[0]))
            for k in DIRECTIONS}


def calibrate(blade: Blade, omega: float, targets: dict[str, float]) -> dict[str, float]:
    """The stiffnesses (N m²) that give the continuous blade the first frequencies
    ``targets`` (direction -> per revolution at ``omega`` rad/s), one direction at a time."""
    out = {}
    for k, per_rev in targets.items():
        def miss(log_stiffness: float) -> float:
            trial = Blade(**{**blade.__dict__, f"{k}_stiffness": np.exp(log_stiffness)})
            return beam_frequencies(trial, omega)[k] / omega - per_rev
        out[k] = float(np.exp(brentq(miss, np.log(1.0), np.log(1e9), xtol=1e-12)))
    return out
