"""The kinematics of a modal blade, written once: where a section of the blade is and how it
is turned, as functions of the modal coordinates.

A blade frame at the root (x along the span, y towards the leading edge for a rotor turning
about its thrust axis, the trailing edge for one turning against it, z up at zero pitch;
:mod:`mbs.models.helicopter.frames`) carries the deflections of its modes
(:mod:`mbs.flexible.shapes`): flap ``w(x)`` along z (tip up), lag ``v(x)`` against the
rotation (lagging), twist ``θ(x)`` about the span (nose up) and, on an extensible blade,
stretch ``s(x)`` along x. The section at ``x`` sits at

    p(x) = (x + s(x) - ½ ∫_0^x (w'² + v'²) dξ,  -σ v(x),  w(x))      (σ: the sense of rotation)

and is turned by the flap slope ``w'`` about -y, then the lag slope ``v'`` about -σ z, then the
twist ``θ`` about σ x (the segmented blade's hinge axes). The integral is the axial
foreshortening of the bent beam: its length is kept, so a bent blade's outer sections move
inwards, and the centrifugal force doing work on that motion is what stiffens a turning blade
(the tension of the Southwell and rotating-beam theories, ``∫ T w'²/2``). Nothing about it is
written as a force: the equations of motion get it from these kinematics, as they get the
mass coupling, Coriolis and centrifugal terms. Velocities and angular velocities are the
forward-mode AD of the positions and angles in the coordinate rates.
"""
from __future__ import annotations

from dataclasses import dataclass, field

import casadi as ca
import numpy as np

from mbs import _rotation as rot
from mbs.flexible.shapes import DIRECTIONS, Shapes, mode_shapes
from mbs.joints import Relative, compose
from mbs.flexible.uniform_blade import BEAM_ELEMENTS, Blade


def _counts(modes) -> dict[str, int]:
    """Modes per direction from an int (flap, lag, torsion alike), a sequence (flap, lag,
    torsion[, axial]) or a dict; ValueError naming a bad count."""
    if isinstance(modes, dict):
        counts = {k: modes.get(k, 0) for k in DIRECTIONS}
        unknown = set(modes) - set(DIRECTIONS)
        if unknown:
            raise ValueError(f"unknown mode directions {sorted(unknown)}; choose among {', '.join(DIRECTIONS)}")
    elif isinstance(modes, (int, np.integer)) and not isinstance(modes, bool):
        counts = {"flap": modes, "lag": modes, "torsion": modes, "axial": 0}
    else:
        try:
            values = list(modes)
        except TypeError:
            raise ValueError(f"modes {modes!r}: give one whole count, or counts for flap, lag, torsion and "
                             "optionally axial") from None
        if not 1 <= len(values) <= 4:
            raise ValueError(f"modes {modes!r}: give one count, or counts for flap, lag, torsion and optionally axial")
        counts = dict(zip(DIRECTIONS, values + [0] * (4 - len(values))))
    for k, n in counts.items():
        if isinstance(n, bool) or not isinstance(n, (int, np.integer)) or n < 0:
            raise ValueError(f"blade modes: {k} = {n!r} must be a whole number >= 0")
    if not any(counts.values()):
        raise ValueError("blade modes: a modal blade needs at least one mode")
    return {k: int(n) for k, n in counts.items()}


def coordinate_names(counts: dict[str, int]) -> tuple[str, ...]:
    """``flap``, ``flap2``, …, ``lag``, …, ``torsion``, …, ``axial``, …: the first mode of a
    direction carries its bare name, as the rigid and segmented blades' hinges."""
    return tuple(k if i == 0 else f"{k}{i + 1}" for k in DIRECTIONS for i in range(counts[k]))


@dataclass
class ModalBlade:
    """A blade whose sections move with modal coordinates on top of its root frame.

    blade: the section data (:class:`mbs.flexible.uniform_blade.Blade`; ``root`` is the radius
    of the blade frame's origin from the rotor axis). modes: per direction (see
    :func:`_counts`). omega: the reference speed of the mode shapes (rad/s; the rotor's
    nominal speed: its own rotating modes). sense: +1 for a rotor turning about its thrust
    axis, -1 against it. nodes: Gauss–Legendre points carrying the blade's mass (default
    ``2 × most modes + 2``: the Bo105 blade's frequencies converge with 4 for one mode per
    direction and 6 for two). elements: of the finite elements behind the shapes.
    """

    blade: Blade
    modes: object = 2
    omega: float = 0.0
    sense: int = 1
    nodes: int | None = None
    elements: int = BEAM_ELEMENTS
    shapes: dict[str, Shapes] = field(init=False)
    counts: dict[str, int] = field(init=False)

    def __post_init__(self):
        self.counts = _counts(self.modes)
        self.nodes = self.nodes or 2 * max(self.counts.values()) + 2
        if isinstance(self.nodes, bool) or not isinstance(self.nodes, (int, np.integer)) or self.nodes < 1:
            raise ValueError(f"blade nodes = {self.nodes!r} must be a whole number >= 1")
        if self.sense not in (1, -1):
            raise ValueError(f"sense of rotation {self.sense!r} must be +1 or -1")
        self.shapes = {k: mode_shapes(self.blade, k, n, self.omega, self.elements)
                       for k, n in self.counts.items() if n}

    @property
    def names(self) -> tuple[str, ...]:
        return coordinate_names(self.counts)

    @property
    def size(self) -> int:
        return len(self.names)

    def _split(self, q) -> dict[str, object]:
        out, i = {}, 0
        for k in DIRECTIONS:
            out[k], i = q[i:i + self.counts[k]], i + self.counts[k]
        return out

    def section(self, q, x: float) -> tuple[ca.SX, ca.SX]:
        """Position (3,) of the section at ``x`` (m from the root) in the blade frame (m) and
        its angles (3,): flap slope, lag slope, twist (rad), at the coordinates ``q`` (size,)."""
        parts, zero = self._split(q), ca.SX(0)
        value = {k: (self.shapes[k].values(x) if self.counts[k] else None) for k in DIRECTIONS}

        def deflection(k, d):  # a deflection (d = 0) or its slope (d = 1) at x
            return ca.dot(ca.DM(value[k][d]), parts[k]) if self.counts[k] else zero

        shorten = sum((ca.mtimes([parts[k].T, ca.DM(self.shapes[k].foreshortening(x)), parts[k]])
                       for k in ("flap", "lag") if self.counts[k]), zero)
        position = ca.vertcat(x + deflection("axial", 0) - shorten / 2, -self.sense * deflection("lag", 0),
                              deflection("flap", 0))
        return position, ca.vertcat(deflection("flap", 1), deflection("lag", 1), deflection("torsion", 0))

    @property
    def axes(self) -> tuple[tuple[float, float, float], ...]:
        """The axes of the flap slope, lag slope and twist turns (blade frame)."""
        return (0.0, -1.0, 0.0), (0.0, 0.0, -self.sense * 1.0), (self.sense * 1.0, 0.0, 0.0)

    def _turned(self, position, velocity, angles, rates) -> Relative:
        """The section frame turned by ``angles`` (flap slope, lag slope, twist) about
        :attr:`axes` in turn, its rate of turn from the angles' ``rates`` (section axes)."""
        motion = Relative(position, ca.SX.eye(3), velocity, ca.SX.zeros(3))
        for k, axis in enumerate(self.axes):
            turn = Relative(ca.SX.zeros(3), rot.axis_angle(axis, angles[k]), ca.SX.zeros(3),
                            ca.DM(axis) * rates[k])
            motion = compose(motion, turn)
        return motion

    def relative(self, q, v, x: float) -> Relative:
        """Motion of the section frame at ``x`` in the blade frame (a joint's relative
        kinematics): velocity and angular velocity by forward-mode AD along ``v``."""
        position, angles = self.section(q, x)
        rates = ca.jtimes(ca.vertcat(position, angles), q, v)
        return self._turned(position, rates[:3], angles, rates[3:])

    def curvature(self, q, x: float) -> ca.SX:
        """Curvature and twist rate of the bent blade at ``x`` (1/m, section axes: x twist, y
        flap, z lag bending): the rate of turn of the section frame along the span, from the
        same turns as :meth:`relative` with the angles' span derivatives in place of their
        time rates. In the section's own axes, so its bending stiffnesses turn with the
        twist (as the segmented blade's hinges after its torsion hinges)."""
        ahead = {k: self.shapes[k].values(x) if self.counts[k] else None for k in DIRECTIONS}
        parts, zero = self._split(q), ca.SX(0)

        def along(k, d):
            return ca.dot(ca.DM(ahead[k][d]), parts[k]) if self.counts[k] else zero

        angles = ca.vertcat(along("flap", 1), along("lag", 1), along("torsion", 0))
        spans = ca.vertcat(along("flap", 2), along("lag", 2), along("torsion", 1))
        return self._turned(ca.SX.zeros(3), ca.SX.zeros(3), angles, spans).omega

    def strain_energy(self, q) -> ca.SX:
        """Strain energy (J) beyond the quadratic ``q·K·q / 2`` (:meth:`stiffness`, exact from
        the section data): ``½ ∫ (GJ κ_x² + EI_flap κ_y² + EI_lag κ_z²)`` of the section-axes
        curvature less its part quadratic in ``q``, by Gauss–Legendre quadrature over the
        mass nodes; zero to second order in ``q``."""
        b = self.blade
        stiff = ca.DM([b.torsion_stiffness, b.flap_stiffness, b.lag_stiffness])
        x, mass, _ = self.mass_nodes()
        total = ca.SX(0)
        for xk, wk in zip(x, mass / b.mass):
            kappa = self.curvature(q, xk)
            linear = ca.mtimes(ca.substitute(ca.jacobian(kappa, q), q, ca.SX.zeros(q.shape)), q)  # its linear part
            total += wk / 2 * ca.dot(stiff, kappa**2 - linear**2)
        return total

    def stiffness(self) -> np.ndarray:
        """Elastic stiffness of the modal coordinates (size, size): block-diagonal by direction."""
        from scipy.linalg import block_diag

        return block_diag(*[self.shapes[k].stiffness() for k in DIRECTIONS if self.counts[k]])

    def damping_times(self) -> np.ndarray:
        """Per coordinate the structural damping time (s): the blade's per direction (flap,
        lag, torsion; extension undamped)."""
        times = dict(zip(("flap", "lag", "torsion"), self.blade.damping_time))
        return np.array([times.get(k, 0.0) for k in DIRECTIONS for _ in range(self.counts[k])])

    def mass_nodes(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Span coordinates (m), masses (kg) and section inertias (n, 3, 3) in section axes of the
        Gauss–Legendre nodes that carry the blade's mass (rotary inertia included: the chord's
        ``m c²/12`` about z, the thickness's ``m t²/12`` about y, their sum about the span)."""
        b = self.blade
        points, weights = np.polynomial.legendre.leggauss(self.nodes)
        x, w = (points + 1) / 2 * b.length, weights / 2 * b.length
        chord, thick = b.mass * b.chord**2 / 12, b.mass * b.thickness**2 / 12
        inertia = np.array([np.diag([chord + thick, thick, chord]) * wk for wk in w])
        return x, b.mass * w, inertia

    def node_spans(self) -> np.ndarray:
        """Edges (nodes + 1,) of the spans the mass nodes stand for (m): root, mid-points, tip."""
        x = self.mass_nodes()[0]
        return np.r_[0.0, (x[1:] + x[:-1]) / 2, self.blade.length]
