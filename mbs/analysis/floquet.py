"""Floquet stability of a periodic solution: multipliers, characteristic exponents, modes.

Coordinates ``y``: the rotor states and, for a free fuselage, roll, pitch and heading (rad)
and the body-axis velocities and rates; the position is left out (the equations do not
depend on it: its three multipliers are exactly 1). The heading is kept: its neutral mode
(multiplier 1) is the aircraft's indifference to its direction of flight.

Over the shooting interval ``τ`` the linearised map is ``Ψ = S dy(τ)/dy(0)`` (``S`` reverses the
teeter when ``τ`` is half the period, :mod:`mbs.analysis.period`); its eigenvalues ``ρ`` give
the multipliers of the whole period ``ρ^(period/τ)`` and the characteristic exponents
``λ = ln ρ / τ`` (1/s), whose imaginary part is known only up to multiples of ``2π/τ``.

That ambiguity is resolved by the eigenvector's dominant harmonic: the perturbation
``δy(t) = Φ(t) v`` is recorded over the interval (the tangent propagation records
``Φ(t_k)``) and continued over the second half of the period by the symmetry
(``δy(t + τ) = ρ S δy(t)``); ``p(t) = exp(-λ₀ t) δy(t)`` is then periodic for the principal
value ``λ₀``, and the harmonic ``m`` of ``p`` with the largest energy (states scaled per
radius and revolution) moves the frequency to ``Im λ₀ + 2π m / period``, so that the
periodic part of the mode is as close to constant as possible. For a time-invariant system
(the single blade on a vertical shaft) this recovers the natural frequencies in the rotating
frame. Rotor states are in the rotating frame (per blade), so rotor-mode frequencies read
in them are rotating-frame frequencies; :func:`floquet` reads them in the fixed frame by
default (``frame="fixed"``: the periodic part in multi-blade coordinates, and a teetering body's
teeter as the tilt of its plane, :mod:`mbs.analysis.multiblade`), which also names the rotor modes
(regressing, advancing, collective, differential). Multipliers and damping do not depend on the
frame.

Mode names from participation: the scaled eigenvector's energy by group (body, flap, lag,
inflow, tail rotor, stabilizer bar); the name lists the groups above 25 %.
"""
from __future__ import annotations

import time
from dataclasses import dataclass, field

import casadi as ca
import numpy as np

from mbs.analysis.period import periodic_scene
from mbs.analysis.shooting import TrimLayout, euler_angles, residual_scales

GROUPS = ("body", "flap", "lag", "inflow", "tail rotor", "stabilizer bar")


@dataclass
class FloquetMode:
    """One characteristic exponent ``λ`` (1/s) and its multiplier over the period."""

    exponent: complex
    multiplier: complex
    participation: dict[str, float]
    omega: float  # main-rotor speed, rad/s
    vector: np.ndarray | None = field(default=None, repr=False)  # eigenvector (ny,) at t = 0, ∝ exp(+i |Im λ| t)
    label: str | None = None  # name in the frame the frequency is read in; None: from participation

    @property
    def damping(self) -> float:
        """Decay rate ``-Re λ``, 1/s (negative: growing)."""
        return -self.exponent.real

    @property
    def frequency_hz(self) -> float:
        return abs(self.exponent.imag) / (2 * np.pi)

    @property
    def per_rev(self) -> float:
        """Frequency in multiples of the main-rotor speed."""
        return abs(self.exponent.imag) / abs(self.omega)

    @property
    def damping_ratio(self) -> float:
        from mbs.analysis.flight_modes import damping_ratio

        return damping_ratio(self.exponent)

    @property
    def group(self) -> str:
        """The group with the largest share of the mode's energy."""
        return max(self.participation.items(), key=lambda kv: kv[1])[0] if self.participation else "body"

    @property
    def name(self) -> str:
        if self.label:
            return self.label
        top = [g for g, w in sorted(self.participation.items(), key=lambda kv: -kv[1]) if w >= 0.25]
        return " + ".join(top)

    def summary(self) -> dict:
        return {"name": self.name, "exponent": [self.exponent.real, self.exponent.imag],
                "multiplier": [self.multiplier.real, self.multiplier.imag], "damping_per_s": self.damping,
                "damping_ratio": None if np.isnan(self.damping_ratio) else self.damping_ratio,
                "frequency_hz": self.frequency_hz, "per_rev": self.per_rev,
                "participation": self.participation}


@dataclass
class Floquet:
    """Modes of a periodic solution (one per conjugate pair, least damped first) and the work."""

    scene: str
    speed: float
    modes: list[FloquetMode]
    coordinates: list[str]
    interval_revs: int
    period_revs: int
    trim: object = None
    nfwd: int = 0
    wall_s: float = 0.0
    extra: dict = field(default_factory=dict)
    frame: str = "rotating"  # where rotor-mode frequencies are read: "rotating" or "fixed (multi-blade)"

    @property
    def stable(self) -> bool:
        return all(abs(m.multiplier) <= 1 + 1e-9 for m in self.modes)

    def summary(self) -> dict:
        return {"scene": self.scene, "speed": self.speed, "frame": self.frame, "interval_revs": self.interval_revs,
                "period": self.trim.period_summary() if hasattr(self.trim, "period_summary") else None,
                "period_revs": self.period_revs, "coordinates": self.coordinates, "stable": self.stable,
                "modes": [m.summary() for m in self.modes], "nfwd": self.nfwd, "wall_s": self.wall_s, **self.extra}


def group_of(name: str) -> str:
    """The participation group of a coordinate name."""
    if name.startswith(("seesaw.", "tail_rotor.", "tail_blade")):
        return "tail rotor"
    if name.startswith("main_seesaw."):  # a teetering main rotor's flapping
        return "flap"
    if name.startswith("stabilizer_bar."):
        return "stabilizer bar"
    if ".inflow" in name:
        return "inflow"
    for key in ("flap", "lag", "torsion"):
        if name.rsplit(".", 1)[-1].startswith(key):
            return key
    return "body"


def coordinate_functions(lay: TrimLayout, nx: int) -> tuple[list[str], ca.Function]:
    """Names of ``y`` and ``from_state(x) -> (y, dy/dx)`` (AD)."""
    x = ca.SX.sym("x", nx)
    parts, names = [], []
    if lay.free:
        parts += [euler_angles(ca.vertcat(*[x[k] for k in lay.quaternion])), *[x[k] for k in lay.body]]
        names += ["roll", "pitch", "heading", *(lay.state_names[k] for k in lay.body)]
    parts += [x[k] for k in lay.rotor]
    names += [lay.state_names[k] for k in lay.rotor]
    y = ca.vertcat(*parts)
    return names, ca.Function("from_state", [x], [y, ca.jacobian(y, x)], ["x"], ["y", "dy_dx"])


def right_inverse(dy_dx: np.ndarray, position: list[int]) -> np.ndarray:
    """``dx/dy`` (nx, ny) with ``dy/dx · dx/dy = I``, zero in the position and, being the
    minimum-norm solution, tangent to the unit quaternions (Euler angles ignore the norm)."""
    keep = [k for k in range(dy_dx.shape[1]) if k not in position]
    out = np.zeros(dy_dx.shape[::-1])
    out[keep] = np.linalg.pinv(dy_dx[:, keep])
    return out


def floquet(scene: str = "forward-flight", speed: float | None = None, method: str = "rk4",
            steps_per_rev: int | None = None, backend: str = "compiled", system=None, stepper=None,
            record_every: int = 2, frame: str = "fixed") -> Floquet:
    """Floquet analysis of ``scene`` at its periodic solution (the trim at ``speed`` for a
    free-flying scene, the periodic rotor response otherwise).

    frame: ``"fixed"`` reads rotor-mode frequencies in multi-blade coordinates and names the
    modes there (regressing lag, ...), ``"rotating"`` per blade."""
    from mbs import scenes
    from mbs.analysis.monodromy import TangentStepper
    from mbs.analysis.trim import evaluators, periodic_solution

    if frame not in FRAMES:
        raise ValueError(f"unknown frame {frame!r}; choose one of {FRAMES}")
    sc = periodic_scene(scenes.get(scene) if isinstance(scene, str) else scene)
    check_scene(sc)
    if system is None and stepper is None:
        system, stepper = evaluators(sc, method, backend)
    system = system or sc.system(backend)
    stepper = stepper or TangentStepper(sc.model(), method, backend)
    sol = periodic_solution(sc, speed, method=method, steps_per_rev=steps_per_rev, system=system, stepper=stepper)
    if not sol.converged:
        raise RuntimeError(f"no periodic solution of {sc.name!r} to analyse: {sol.reason}")
    if frame == "rotating":
        return analyse(sol, system, stepper, record_every)
    return in_fixed_frame(sol, system, stepper, record_every)


FRAMES = ("fixed", "rotating")


def in_fixed_frame(sol, system, stepper, record_every: int = 2) -> Floquet:
    """:func:`analyse` with frequencies read in multi-blade coordinates and the modes named
    there (:func:`mbs.analysis.multiblade.mode_name`)."""
    from mbs.analysis.multiblade import transform

    names = coordinate_functions(TrimLayout.of(system.info), system.info.nx)[0]
    res = analyse(sol, system, stepper, record_every, frame=transform(names, sol.period.omega))
    scale = residual_scales(names, sol.period.omega, sol.radius)
    for m, label in zip(res.modes, fixed_frame_names(res, scale)):
        m.label = label
    res.frame = "fixed (multi-blade)"
    return res


def fixed_frame_names(res: Floquet, scale: np.ndarray | None = None) -> list[str]:
    """Fixed-frame names of the modes of ``res`` (analysed in multi-blade coordinates) from
    their eigenvectors, divided by ``scale`` (ny,) when given (e.g. per radius and revolution,
    :func:`mbs.analysis.shooting.residual_scales`, so that speeds and angles compare)."""
    from mbs.analysis.multiblade import mode_name, transform

    if not res.modes:
        return []
    b0 = transform(res.coordinates, res.modes[0].omega)(0.0)[0]
    groups = {n: group_of(n) for n in res.coordinates}
    s = np.ones(len(res.coordinates)) if scale is None else scale
    return [mode_name(b0 @ (m.vector / s), res.coordinates, m.exponent.imag, m.omega, groups) for m in res.modes]


def check_scene(sc) -> None:
    """Refuse (ValueError) a scene (:class:`mbs.scenes.Scene`) without a periodic solution to
    analyse; symbolic only, so callers check before anything is compiled."""
    from mbs.analysis.trim import trimmable

    model = sc.model()
    free = any(b.joint.__class__.__name__ == "FreeJoint" for b in model.bodies.values())
    if not trimmable(sc) and (free or "omega" not in model.parameters):
        raise ValueError(f"scene {sc.name!r} has no periodic solution to analyse: Floquet analysis needs "
                         "driven rotors and either a trimmable scene or a fuselage that is not free")


def analyse(sol, system, stepper, record_every: int = 2, frame=None) -> Floquet:
    """Floquet modes of the periodic solution ``sol`` (a :class:`mbs.analysis.trim.Trim`).

    frame: optional ``frame(t) -> (m, ny, ny)``, coordinates along the period in which each
    mode's frequency is read (e.g. multi-blade coordinates, :func:`mbs.analysis.multiblade.transform`,
    for fixed-frame frequencies); multipliers and damping do not depend on it."""
    start = time.perf_counter()
    lay = TrimLayout.of(system.info)
    names, from_state = coordinate_functions(lay, system.info.nx)
    per, n = sol.period, sol.period.revs * sol.steps_per_rev
    seeds = right_inverse(np.asarray(from_state(sol.x0)[1]), lay.position)
    sens = stepper.propagate(sol.x0, sol.params, seeds, np.zeros((len(sol.params), seeds.shape[1])), 0.0,
                             per.revolution / sol.steps_per_rev, n, every=record_every)
    sym = CoordinateSymmetry.of(names, per, system.info.state_names)
    phi = np.array([np.asarray(from_state(x)[1]) @ d for x, d in zip(sens.xs, sens.dxs)])
    psi = sym.apply(np.asarray(from_state(sens.x)[1]) @ sens.dx)
    t = np.arange(len(phi)) * record_every * per.revolution / sol.steps_per_rev
    if frame is not None:
        phi = frame(t) @ phi
    scale = residual_scales(names, per.omega, sol.radius)
    modes = _modes(psi, phi, t, per, names, scale, sym)
    return Floquet(sol.scene, sol.speed, modes, names, per.revs, per.full_revs, sol, sens.nfwd,
                   time.perf_counter() - start)


@dataclass(frozen=True)
class CoordinateSymmetry:
    """The symmetry ``S`` of the shooting interval (:class:`mbs.analysis.period.RotorPeriod`) in
    the coordinates ``y``: ``(S y)[k] = sign[k] y[source[k]]``."""

    sign: np.ndarray
    source: np.ndarray

    @classmethod
    def of(cls, names: list[str], per, state_names: list[str]) -> "CoordinateSymmetry":
        nx, where = len(state_names), {n: i for i, n in enumerate(state_names)}
        sign, source, index = per.symmetry(nx), per.permutation(nx), {n: i for i, n in enumerate(names)}
        return cls(np.array([sign[where[n]] if n in where else 1.0 for n in names]),
                   np.array([index[state_names[source[where[n]]]] if n in where else i for i, n in enumerate(names)]))

    def apply(self, y: np.ndarray) -> np.ndarray:
        """``S y`` along the first axis of ``y`` (ny, ...)."""
        return (self.sign * y[self.source].T).T

    def inverse(self, y: np.ndarray) -> np.ndarray:
        """``S⁻¹ y`` along the last axis of ``y`` (..., ny)."""
        out = np.empty_like(y)
        out[..., self.source] = self.sign * y
        return out


def _modes(psi, phi, t, per, names, scale, sym) -> list[FloquetMode]:
    """One :class:`FloquetMode` per eigenvalue of ``psi`` with ``Im λ >= 0``, least damped first."""
    rho, vec = np.linalg.eig(psi)
    out = []
    for j in np.flatnonzero(rho.imag >= 0):
        lam = complex(np.log(complex(rho[j]))) / per.duration
        lam += 1j * _harmonic_shift(phi, vec[:, j], rho[j], lam, t, scale, sym, per)
        out.append(FloquetMode(complex(lam.real, abs(lam.imag)), complex(rho[j]) ** (per.full_revs // per.revs),
                               _participation(vec[:, j], names, scale), per.omega,
                               vec[:, j] if lam.imag >= 0 else vec[:, j].conj()))
    return sorted(out, key=lambda m: m.exponent.real, reverse=True)


def _harmonic_shift(phi, v, rho: complex, lam: complex, t, scale, sym, per) -> float:
    """``2π m / period`` (rad/s) for the harmonic ``m`` with most energy in the periodic part
    ``exp(-λ t) Φ(t) v`` over the whole period; over its later intervals (when the interval is a
    part of the period) the perturbation is ``ρ S⁻¹ δy(t - τ)``."""
    parts, times = [phi @ v], [t]
    for j in range(1, per.full_revs // per.revs):
        parts.append(rho * sym.inverse(parts[-1]))
        times.append(t + j * per.duration)
    dy, t = np.vstack(parts), np.concatenate(times)
    p = dy * np.exp(-lam * t)[:, None] / scale
    energy = (np.abs(np.fft.fft(p, axis=0)) ** 2).sum(axis=1)
    m = np.fft.fftfreq(len(t), 1.0 / len(t))[np.argmax(energy)]
    return 2 * np.pi * float(np.round(m)) / (per.full_revs * per.revolution)


def _participation(v, names, scale) -> dict[str, float]:
    """Share of each group in the scaled eigenvector's energy (sums to 1)."""
    w = np.abs(v / scale) ** 2
    share = {g: float(sum(wi for wi, n in zip(w, names) if group_of(n) == g)) for g in GROUPS}
    total = sum(share.values()) or 1.0
    return {g: s / total for g, s in share.items() if s > 0}
