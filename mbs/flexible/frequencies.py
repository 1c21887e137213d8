"""Natural frequencies of a flexible blade turning on a driven hub, from the multibody model.

The blade (a :class:`mbs.flexible.beam.ModalBlade`) hangs on a hub driven at ``omega`` about
z, without gravity or damping; the frequencies are the eigenvalues ``|λ|`` (rad/s, in the
rotating frame) of the exact AD Jacobian of the equations of motion, each assigned to the
direction (flap, lag, torsion, axial) whose coordinates dominate its mode shape.

An inextensible blade is in equilibrium undeformed. An extensible one stretches: the
frequencies are taken about its equilibrium (:func:`equilibrium`, Newton on the AD residual),
or, with ``linear=True``, from the homogeneous equations about the undeformed blade,
``Mt δu' = ∂ht/∂x δx`` (the linear theory of the rotating-beam papers, which leaves out the
stretch's own effect on the geometry: ``(mΩ²L²/EA)`` against 1).
"""
from __future__ import annotations

import numpy as np

from mbs.flexible.beam import ModalBlade
from mbs.flexible.body import add_flexible_blade
from mbs.flexible.shapes import DIRECTIONS
from mbs.joints import DrivenHinge
from mbs.tree import Model


def blade_on_hub(beam: ModalBlade, omega: float, name: str = "blade") -> Model:
    """A hub driven at the parameter ``omega`` (rad/s) about z carrying ``beam`` at its root
    radius, without gravity or damping."""
    m = Model(f"{name}-on-hub", gravity=(0.0, 0.0, 0.0))
    m.add_parameter("omega", float(omega), "rad/s", "hub speed")
    m.add_body("hub", "world", DrivenHinge((0, 0, 1), lambda t, p: beam.sense * p["omega"] * t, name="azimuth"),
               mass=1.0)
    add_flexible_blade(m, beam, name, "hub", at=(beam.blade.root, 0.0, 0.0), dampers=False)
    return m


def direction_of(name: str) -> str:
    """The direction of a modal coordinate name (``blade.flap2`` -> ``flap``)."""
    return name.rsplit(".", 1)[-1].rstrip("0123456789")


def classify(jacobian: np.ndarray, q_names: list[str]) -> dict[str, list[float]]:
    """Per direction the frequencies ``|λ|`` (rad/s, ascending) of the oscillatory modes of the
    state Jacobian (nx, nx) whose coordinate part (the first ``len(q_names)`` states) is
    dominated by that direction's coordinates."""
    lam, vec = np.linalg.eig(jacobian)
    shape = np.abs(vec[:len(q_names)])
    kind = np.array([direction_of(n) for n in q_names])
    out: dict[str, list[float]] = {k: [] for k in DIRECTIONS}
    for i in np.flatnonzero(lam.imag > 1e-9 * np.abs(lam).max()):
        weight = {k: shape[kind == k, i].sum() for k in DIRECTIONS}
        out[max(weight, key=weight.get)].append(float(abs(lam[i])))
    return {k: sorted(v) for k, v in out.items() if v}


def equilibrium(sym, p, x0=None, t: float = 0.0, iterations: int = 30, tol: float = 1e-12) -> np.ndarray:
    """A state (nx,) of ``sym`` (a :class:`mbs.dynamics.Symbolic`) at rest in the turning frame:
    rates zero and ``x' = 0`` (coordinates and extra states solved for; an axisymmetric rotor's
    periodic solution), by Newton's method from ``x0`` (default: undeformed) with the exact AD
    Jacobian, to ``tol`` of the first residual."""
    from mbs.linearize import rhs_jacobian

    lay = sym.layout
    rhs, jac = sym["rhs"], rhs_jacobian(sym["rhs"])
    unknown = np.r_[np.arange(lay.nq), np.arange(lay.nq + lay.nv, lay.nx)]
    state = np.zeros(lay.nx) if x0 is None else np.array(x0, dtype=float)
    state[lay.nq:lay.nq + lay.nv], scale = 0.0, None
    for _ in range(iterations):
        r = np.array(rhs(state, t, p), dtype=float).ravel()[lay.nq:]
        scale = scale or max(1e-300, np.abs(r).max())
        if np.abs(r).max() <= tol * scale:
            return state
        j = np.array(jac(state, t, p), dtype=float)[lay.nq:][:, unknown]
        state[unknown] -= np.linalg.lstsq(j, r, rcond=None)[0]
    raise RuntimeError(f"no equilibrium of {sym.model.name!r} after {iterations} Newton steps")


def linear_jacobian(sym, x: np.ndarray, p) -> np.ndarray:
    """``d x'/dx`` (nx, nx) of the homogeneous equations at ``x``: ``Mt`` held at ``x`` and only
    ``ht`` differentiated (equal to the full Jacobian at an equilibrium)."""
    import casadi as ca

    lay = sym.layout
    xs = ca.SX.sym("x", lay.nx)
    sdot, mt, ht, _ = sym["parts"](xs, 0.0, p)
    parts = ca.Function("tangent", [xs], [ca.jacobian(sdot, xs), mt, ca.jacobian(ht, xs)])
    dsdot, mass, dht = (np.array(a, dtype=float) for a in parts(x))
    return np.vstack([dsdot, np.linalg.solve(mass, dht)])


def rotating_frequencies(beam: ModalBlade, omega: float, linear: bool = False) -> dict[str, list[float]]:
    """Per direction the natural frequencies (rad/s, rotating frame) of ``beam`` on a hub
    turning at ``omega`` (rad/s): about its equilibrium, or (``linear``) by the linear theory
    about the undeformed blade (see the module)."""
    from mbs.dynamics import symbolic

    sym = symbolic(blade_on_hub(beam, omega))
    x = np.zeros(sym.layout.nx) if linear else equilibrium(sym, [omega])
    return classify(linear_jacobian(sym, x, [omega]), sym.layout.q_names)
