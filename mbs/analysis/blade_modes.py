"""Blade frequencies of the multibody model: the lowest flap, lag and torsion frequencies of one
elastic blade on a hub driven at the rotor speed, from the eigenvalues of the AD Jacobian of the
helicopter model (:func:`mbs.models.helicopter.build`) at the undeformed blade: the segmented
blade (:mod:`mbs.models.elastic_blade`) and the modal blade (:mod:`mbs.models.modal_blade`),
against the continuous blade's (:func:`mbs.flexible.uniform_blade.beam_frequencies`).
"""
from __future__ import annotations

import numpy as np

from mbs.flexible.uniform_blade import DIRECTIONS
from mbs.models import elastic_blade as eb


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
                            dampers=False, shaft_tilt=False, pitch_hinge=False, blade_segments=eb.check_segments(n))
    model = helicopter.build(cfg, data, name=f"elastic-blade{n}")
    model.gravity = np.zeros(3)
    sym = symbolic(model)
    p = [model.parameters[k].default for k in model.parameters]
    jac = np.array(rhs_jacobian(sym["rhs"])(np.zeros(sym.layout.nx), 0.0, p))
    return mode_frequencies(jac, sym.layout.q_names)


def modal_frequencies(modes, data=None) -> dict[str, float]:
    """First flap, lag and torsion frequencies (rad/s, rotating frame) of one modal blade with
    ``modes`` per direction (of the aircraft ``data``, default the Bo105) on a hub driven at
    the rotor speed, in vacuum, without gravity and dampers: the eigenvalues of the AD
    Jacobian of the multibody model at the undeformed blade, as
    :func:`segmented_frequencies` for the segmented blade."""
    from mbs.dynamics import symbolic
    from mbs.flexible.frequencies import classify
    from mbs.linearize import rhs_jacobian
    from mbs.models import helicopter

    cfg = helicopter.Config(fuselage="none", blades=1, tail_rotor=False, rotor_aero=False, airframe_aero=False,
                            dampers=False, shaft_tilt=False, pitch_hinge=False, blade_modes=modes)
    model = helicopter.build(cfg, data, name="modal-blade")
    model.gravity = np.zeros(3)
    sym = symbolic(model)
    p = [model.parameters[k].default for k in model.parameters]
    found = classify(np.array(rhs_jacobian(sym["rhs"])(np.zeros(sym.layout.nx), 0.0, p)), sym.layout.q_names)
    return {k: found[k][0] for k in DIRECTIONS if k in found}
