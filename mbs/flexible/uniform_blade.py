"""The uniform rotating blade of the aircraft file, and its continuous reference model.

:class:`Blade` holds the section data of a uniform elastic blade; :func:`blade_from_data` reads
it from the aircraft data (span, mass, section, the ``[elastic_blade]`` stiffnesses, lag damper
and structural damping). The continuous blade clamped at its root, turning at the rotor speed,
is cut into finite elements (cubic Hermite in bending, linear in torsion and extension;
:func:`beam_matrices`), which give its first rotating frequencies (:func:`beam_frequencies`)
and, the other way round, the stiffnesses ``EI`` and ``GJ`` that give it the frequencies an
aircraft file states (:func:`calibrate`, which the aircraft loader uses). The segmented blade
(:mod:`mbs.models.elastic_blade`) and the mode shapes of the modal blade
(:mod:`mbs.flexible.shapes`) are built on it. numpy and scipy only: the aircraft data layer
imports it.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.linalg import eigh
from scipy.optimize import brentq

DIRECTIONS = ("flap", "lag", "torsion")
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
        low, high = np.log(1.0), np.log(1e9)
        ends = (miss(low), miss(high))
        if ends[0] * ends[1] > 0:
            reach = [per_rev + e for e in ends]
            raise ValueError(f"elastic_blade.{k}_frequency: {per_rev:.4g}/rev is beyond what this rotor's uniform blade "
                             f"gives ({min(reach):.4g} to {max(reach):.4g}/rev for a stiffness of 1 to 1e9 N m^2): give "
                             f"elastic_blade.{k}_stiffness, or a frequency within that, or leave [elastic_blade] out "
                             "(only the elastic-rotor scenes use it)")
        out[k] = float(np.exp(brentq(miss, low, high, xtol=1e-12)))
    return out
