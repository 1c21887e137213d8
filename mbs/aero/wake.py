"""The main rotor's wake at points of the airframe: downwash, swirl, and whether it reaches them.

The wake is the skewed tube that leaves the disc with the through-flow ``λ = V_normal + v0``
(m/s, down through the disc) and the in-plane air velocity ``a`` (m/s, relative to the hub).
Its edges are the tip vortices, carried down by the through-flow where they left the disc and
aft by ``a``: the rear edge with the rear of the disc's inflow ``λ + v_1`` (``v_1`` the
Pitt–Peters first harmonic along ``a`` at the disc edge), the front edge with ``λ − v_1``, both
growing on the way down as the wake develops (``v0`` times the mean of ``g`` over the way,
``(sqrt(s² + R²) − R)/s``). At the depth ``h`` the wake's section is therefore centred
``h a (1/λ_rear + 1/λ_front)/2`` downstream and shortened along ``a`` by the edges' different
drifts: the rear edge is less skewed than the mean wake (the tip vortices leave the rear of the
disc almost normal to it at low advance ratio, as flow visualisation shows), the front one more.
Laterally the section keeps the disc's radius less Landgrebe's hover contraction (0.87 R within
0.13 R below the disc, :func:`landgrebe_radius`) times the share of it the momentum stream tube
keeps in forward flight, ``(1 − sqrt(V_disc/V_far)) / (1 − 1/√2)`` with ``V_disc = sqrt(a² + λ²)``
and ``V_far = sqrt(a² + (λ + v0)²)`` (1 in hover, tending to 0 edgewise). A point is in the wake
by the smoothed edge ``K = ½ (1 − tanh((e − R_w)/width))``, times ``½ (1 + tanh(h/width))`` so
that nothing above the disc is reached.

Along the wake the induced velocity develops as on the axis of a semi-infinite vortex cylinder,
``v(s) = v0 (1 + g) + (v_disc − v0)(1 − g)``, ``g = s / sqrt(s² + R²)`` at the distance
``s = h V_T / λ`` along the skewed axis: the mean doubles to momentum theory's ``2 v0`` far
downstream (Glauert) while the disc's first harmonics (``v_disc`` the Pitt–Peters inflow where
the streamline left the disc) fade, so the wake never exceeds ``2 v0``; far behind a cruising
rotor it is the ``2 v0`` behind a uniformly loaded wing that Heyson and Katzoff measured (NACA
Rep. 1319, 1957). The downwash is along the shaft axis (the rings of a vortex cylinder induce
no in-plane velocity inside it). The swirl is the angular momentum the rotor torque ``Q`` puts
into the wake, ``v_θ = Q e / (ρ A V (e² + r_c²))`` about the wake's centre in the rotor's sense
of rotation, with a core ``r_c`` at the root cut-out (no torque is produced inboard of it); the
angular momentum is carried by Glauert's mass flow through the disc, ``ρ A V`` with ``V =
sqrt(a² + λ²)`` (``λ`` alone in hover; in a descent through ``λ = 0`` the through-flow alone
would make the swirl unbounded). It gives the sidewash at the fin.

Sources: H. Glauert, *Aerodynamic Theory* IV (1935), wake velocity; W. Johnson, *Helicopter
Theory* §2.2 and §5.2 (momentum theory, the vortex-cylinder wake and its skew); G.D. Padfield,
*Helicopter Flight Dynamics* §3.2.5 (the tailplane in the wake beyond a transition speed, set by
the wake-skew geometry); A.J. Landgrebe, J. AHS 17(4) (1972) 3-15, the contraction of the
hovering rotor's tip-vortex wake; H.H. Heyson and S. Katzoff, NACA Rep. 1319 (1957), induced
velocities near a lifting rotor, measured and computed. Units: SI, rad; vectors in world
components.
"""
from __future__ import annotations

from dataclasses import dataclass

import casadi as ca
import numpy as np

MIN_THROUGH_FLOW = 0.1  # m/s: smooth floor of λ, so the skew stays finite in a descent through λ = 0


@dataclass(frozen=True)
class WakeGeometry:
    """Edge smoothing ``width`` (m) and swirl core radius ``core`` (m) of a rotor's wake, and the
    coefficients of Landgrebe's hover wake (:func:`landgrebe_radius`): far-wake radius ``a``,
    contraction rate ``decay`` (1/rad), tip-vortex descent rates ``k1``, ``k2`` (per rad of wake
    age, positive down) before and after the next blade passes, ``n_blades``."""

    width: float
    core: float
    a: float = 0.78
    decay: float = 0.277
    k1: float = 0.0155
    k2: float = 0.0642
    n_blades: int = 4

    @classmethod
    def landgrebe(cls, width: float, core: float, thrust_coefficient: float, solidity: float,
                  twist_deg: float, n_blades: int) -> "WakeGeometry":
        """Landgrebe's coefficients at the hover ``C_T`` and ``σ`` for a blade twist in degrees:
        ``Λ = 0.145 + 27 C_T``, ``k1 = 0.25 (C_T/σ + 0.001 θ_tw)``,
        ``k2 = (1.41 + 0.0141 θ_tw) sqrt(C_T/2)``."""
        ct = thrust_coefficient
        return cls(width, core, 0.78, 0.145 + 27 * ct, 0.25 * (ct / solidity + 0.001 * twist_deg),
                   (1.41 + 0.0141 * twist_deg) * np.sqrt(ct / 2), int(n_blades))


def landgrebe_radius(depth, geo: WakeGeometry, smoothing: float = 0.1):
    """Tip-vortex radius per R of a hovering rotor at ``depth`` per R below the disc: the wake
    age ``ψ_w`` at which the tip vortex has descended that far (``k1`` per rad until the next
    blade passes at ``2π/N_b``, ``k2`` after; the kink rounded over ``smoothing`` rad), then
    ``r_L = a + (1 − a) exp(−Λ ψ_w)``. Above the disc it is 1."""
    z = 0.5 * (depth + ca.sqrt(depth**2 + 1e-8))
    passage = 2 * np.pi / geo.n_blades
    first, later = z / geo.k1, passage + (z - geo.k1 * passage) / geo.k2
    age = 0.5 * (first + later - ca.sqrt((first - later) ** 2 + smoothing**2))
    return geo.a + (1 - geo.a) * ca.exp(-geo.decay * age)


@dataclass
class Wake:
    """The wake of one rotor in the current state (symbolic), published by its
    :class:`mbs.aero.RotorAero` as the signal ``<rotor>.wake``.

    ``hub`` (3,) m and ``shaft`` (3, 3) the rotor's azimuth frame (x at ψ = 0, y at 90° in the
    sense of rotation, z the thrust axis; left-handed for a rotor turning against its thrust
    axis), world; ``inflow`` the rotor's inflow states (m/s: ``[v0]`` or
    ``[v0, v1s, v1c]``); ``air`` (3,) the air velocity relative to the hub (m/s, world);
    ``torque`` N m; ``radius`` m (the effective disc with tip loss); ``rho`` kg/m³.
    """

    hub: object
    shaft: object
    inflow: list
    air: object
    torque: object
    radius: float
    rho: float
    geometry: WakeGeometry

    def __post_init__(self):
        """The rotor's flow, shared by every point: thrust axis, through-flow ``λ``, the in-plane
        air velocity ``a`` (shaft frame x, y), ``V_T/λ``, the first harmonic of the inflow along
        ``a`` at the disc edge and the swirl's ``Q/(ρ A V)``, ``V = sqrt(a² + λ²)`` the speed of
        the flow through the disc (Glauert's mass flow ``ρ A V`` carries the angular momentum)."""
        self.axis = self.shaft[:, 2]
        self.lam = self._through_flow(self.axis)
        air_xy = self.air - ca.dot(self.air, self.axis) * self.axis
        self.a_x, self.a_y = ca.dot(air_xy, self.shaft[:, 0]), ca.dot(air_xy, self.shaft[:, 1])
        speed2 = self.a_x**2 + self.a_y**2
        self.stretch = ca.sqrt(speed2 + self.lam**2) / self.lam
        self.edge_harmonic = 0 if len(self.inflow) == 1 else \
            (self.inflow[2] * self.a_x + self.inflow[1] * self.a_y) / ca.sqrt(speed2 + MIN_THROUGH_FLOW**2)
        self.swirl = self.torque / (self.rho * np.pi * self.radius**2 * ca.sqrt(speed2 + self.lam**2))
        self.hover_share = self._hover_share(speed2)

    def _hover_share(self, speed2):
        """Share of the hover contraction left in forward flight: the momentum stream tube's
        contraction ``1 − sqrt(V_disc / V_far)`` (``V_disc = sqrt(a² + λ²)``, ``V_far = sqrt(a² +
        (λ + v0)²)``, its cross-section normal to the flow falls as the flow speeds up) over its
        hover value ``1 − 1/√2``."""
        disc = ca.sqrt(speed2 + self.lam**2)
        far = ca.sqrt(speed2 + (self.lam + self.inflow[0]) ** 2)
        return (1 - ca.sqrt(disc / far)) / (1 - np.sqrt(0.5))

    def velocity(self, point):
        """Induced air velocity (3,) (m/s, world) of the wake at ``point`` (3,) (m, world)."""
        return self.flow(point)[0]

    def flow(self, point):
        """The wake's induced velocity (3,) (m/s, world) at ``point`` (3,) (m, world) and the
        point's immersion (0 outside the wake, 1 inside, between at the smoothed edge)."""
        axis, r = self.axis, point - self.hub
        depth = -ca.dot(r, axis)
        along = depth * self.stretch
        grow = along / ca.sqrt(along**2 + self.radius**2)
        rear, front = self._edge_flows(along)
        centre = 0.5 * depth * (1 / rear + 1 / front)  # drift of the wake's centre per in-plane air speed
        e_x = ca.dot(r, self.shaft[:, 0]) - centre * self.a_x
        e_y = ca.dot(r, self.shaft[:, 1]) - centre * self.a_y
        e2 = e_x**2 + e_y**2
        shrink = 0.5 * depth * (1 / front - 1 / rear)  # the front edge drifts faster than the rear one
        immersion = self.immersion(self._edge_distance(e_x, e_y, shrink), depth, self.hover_share)
        swirl = self.swirl / (e2 + self.geometry.core**2)
        tangential = e_x * self.shaft[:, 1] - e_y * self.shaft[:, 0]  # along increasing azimuth: the rotation
        return immersion * (-self._developed(grow, e_x, e_y) * axis + swirl * tangential), immersion

    def _edge_flows(self, along):
        """Mean through-flow (m/s) carrying the wake's rear and front edges from the disc down to
        the distance ``along`` (m): ``λ`` plus ``v0`` times the development's mean over the way,
        ``(sqrt(s² + R²) − R)/s``, and ± the disc edge's first harmonic, fading likewise."""
        mean = along / (ca.sqrt(along**2 + self.radius**2) + self.radius)
        lam = self.lam + self.inflow[0] * mean
        if len(self.inflow) == 1:
            return lam, lam
        harmonic = self.edge_harmonic * (1 - mean)
        front = lam - harmonic
        return lam + harmonic, 0.5 * (front + ca.sqrt(front**2 + 4 * MIN_THROUGH_FLOW**2))

    def _edge_distance(self, e_x, e_y, shrink):
        """Distance (m) of the in-plane offset ``(e_x, e_y)`` from the wake's centre, the part
        along the in-plane flow stretched by ``R/(R − a shrink)`` (the section shortened by the
        edges' different drifts; at least a tenth of R long)."""
        speed = ca.sqrt(self.a_x**2 + self.a_y**2 + MIN_THROUGH_FLOW**2)
        e_d = (e_x * self.a_x + e_y * self.a_y) / speed
        e_p2 = e_x**2 + e_y**2 - e_d**2
        half = self.radius - speed * shrink
        half = 0.5 * (half + 0.1 * self.radius + ca.sqrt((half - 0.1 * self.radius) ** 2 + 1e-6))
        return ca.sqrt((e_d * self.radius / half) ** 2 + e_p2 + 1e-12)

    def immersion(self, distance, depth, hover_share):
        """Share (0..1) of the wake's velocity at a point ``distance`` (m) from its centre,
        ``depth`` (m) below the disc: the smoothed edge of the tube, contracted by ``hover_share``
        (1 in hover, 0 in edgewise flow) of Landgrebe's hover contraction."""
        geo = self.geometry
        contraction = 1 - landgrebe_radius(depth / self.radius, geo)
        edge = self.radius * (1 - contraction * hover_share)
        return 0.25 * (1 - ca.tanh((distance - edge) / geo.width)) * (1 + ca.tanh(depth / geo.width))

    def _through_flow(self, axis):
        """``λ`` (m/s), floored smoothly at :data:`MIN_THROUGH_FLOW`."""
        lam = -ca.dot(self.air, axis) + self.inflow[0]
        return 0.5 * (lam + ca.sqrt(lam**2 + 4 * MIN_THROUGH_FLOW**2))

    def _developed(self, grow, x, y):
        """Induced velocity (m/s) along the wake from the disc point ``(x, y)`` (m, shaft frame),
        ``grow`` (0 at the disc, 1 far downstream) of the way to the fully developed far wake: the
        mean ``v0`` doubles (momentum theory's far wake), the first harmonics of the disc
        (Pitt–Peters' ``v1s``, ``v1c``, the near field of the skewed wake's vorticity) fade, so
        that the wake never exceeds twice the rotor's mean induced velocity."""
        if len(self.inflow) == 1:
            return (1 + grow) * self.inflow[0]
        v0, v1s, v1c = self.inflow
        return (1 + grow) * v0 + (1 - grow) * (v1s * y + v1c * x) / self.radius
