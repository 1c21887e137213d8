"""Adding a flexible blade to a model: its frame, its sections and its elasticity.

The flexible body ``name`` is a body frame (no mass of its own) on the joint
``Serial(*inboard, Modal(beam))``; its mass sits on ``name:1`` … ``name:<nodes>``, sections
at the Gauss–Legendre nodes, each with its share of the blade's mass and the section's
rotary inertia (and a box of its span for the viewer); sections ``name:aero1`` … at the
given span coordinates carry no mass and take the blade-element loads there. The elasticity
(:class:`mbs.flexible.elasticity.ModalElasticity`) gives the modal coordinates their
stiffness and, with ``dampers``, the structural damping: per direction the blade's
``damping_time`` times the stiffness, as on the segmented blade's hinges.
"""
from __future__ import annotations

from typing import Sequence

import numpy as np

from mbs.flexible.beam import ModalBlade
from mbs.flexible.elasticity import ModalElasticity
from mbs.flexible.joints import Modal, Section
from mbs.joints import Joint, Serial
from mbs.tree import WORLD, Body, Model


def _insert(m: Model, body: Body) -> Body:
    """Add a body that :meth:`mbs.tree.Model.add_body` would refuse for having no mass."""
    if body.name in m.bodies or body.name == WORLD or "/" in body.name:
        raise ValueError(f"duplicate or invalid body name {body.name!r}")
    m.bodies[body.name] = body
    return body


def aero_name(name: str, k: int) -> str:
    """The massless section ``k`` (from 1) of blade ``name`` taking blade-element loads."""
    return f"{name}:aero{k}"


def node_names(name: str, beam: ModalBlade) -> list[str]:
    """The sections carrying the mass of blade ``name``, root first."""
    return [f"{name}:{k + 1}" for k in range(beam.nodes)]


def add_flexible_blade(m: Model, beam: ModalBlade, name: str, parent: str, at=(0.0, 0.0, 0.0), frame=None,
                       inboard: Sequence[Joint] = (), aero_stations: Sequence[float] = (), dampers: bool = True,
                       color: str = "#d62728") -> list[str]:
    """Add ``beam`` as the flexible body ``name`` on ``parent`` (joint origin ``at`` (3,) m and
    axes ``frame`` (3, 3) in the parent frame, x along the span) after the ``inboard`` joints,
    with massless sections at the span coordinates ``aero_stations`` (m from the root).
    Returns the names of the body and its sections."""
    if parent != WORLD and parent not in m.bodies:
        raise ValueError(f"flexible blade {name!r}: unknown parent {parent!r}")
    frame = np.eye(3) if frame is None else np.asarray(frame, dtype=float)
    joint = Serial(*inboard, Modal(beam))
    _insert(m, Body(name, parent, joint, 0.0, np.zeros(3), np.zeros((3, 3)), np.asarray(at, dtype=float), frame))
    m._add_hinge_springs(m.bodies[name])
    names = [name] + _add_mass_nodes(m, beam, name, color)
    for k, x in enumerate(aero_stations):
        names.append(_insert(m, Body(aero_name(name, k + 1), name, Section(beam, x), 0.0, np.zeros(3),
                                     np.zeros((3, 3)))).name)
    damping = np.diag(beam.damping_times()) @ beam.stiffness() if dampers else np.zeros((beam.size,) * 2)
    m.add_force(ModalElasticity(name, beam.names, beam.stiffness(), 0.5 * (damping + damping.T), beam.strain_energy))
    return names


def _add_mass_nodes(m: Model, beam: ModalBlade, name: str, color: str) -> list[str]:
    x, mass, inertia = beam.mass_nodes()
    edges, b = beam.node_spans(), beam.blade
    out = []
    for k, node in enumerate(node_names(name, beam)):
        span = edges[k + 1] - edges[k]
        shape = {"kind": "box", "size": [span, b.chord, b.thickness],
                 "offset": [(edges[k] + edges[k + 1]) / 2 - x[k], 0.0, 0.0], "color": color}
        m.add_body(node, name, Section(beam, x[k]), mass=mass[k], inertia=inertia[k], shape=shape)
        out.append(node)
    return out
