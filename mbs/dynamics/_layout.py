"""Where each body's coordinates live in the state."""
from __future__ import annotations

from dataclasses import dataclass, field

from mbs import tree as _tree
from mbs.backends.info import StateSizes


@dataclass
class Layout(StateSizes):
    """Bodies parents first and the slices of their coordinates in ``s`` and rates in ``u``;
    numeric data only. A section of a flexible body (a joint with ``shares = n``) owns no
    coordinates: its slices are the last ``n`` of its parent's (:mod:`mbs.flexible`)."""

    bodies: list
    q_slices: dict[str, slice] = field(default_factory=dict)
    v_slices: dict[str, slice] = field(default_factory=dict)
    q_names: list[str] = field(default_factory=list)
    v_names: list[str] = field(default_factory=list)
    z_names: list[str] = field(default_factory=list)

    @classmethod
    def of(cls, model: _tree.Model) -> "Layout":
        lay = cls(model.order())
        for b in lay.bodies:
            if getattr(b.joint, "shares", 0):
                lay._share(b)
                continue
            lay.q_slices[b.name] = slice(len(lay.q_names), len(lay.q_names) + b.joint.nq)
            lay.v_slices[b.name] = slice(len(lay.v_names), len(lay.v_names) + b.joint.nv)
            lay.q_names += [f"{b.name}.{n}" for n in b.joint.q_names]
            lay.v_names += [f"{b.name}.{n}" for n in b.joint.v_names]
        lay.z_names = list(model.states)
        return lay

    def _share(self, b) -> None:
        n, q, v = b.joint.shares, self.q_slices[b.parent], self.v_slices[b.parent]
        self.q_slices[b.name], self.v_slices[b.name] = slice(q.stop - n, q.stop), slice(v.stop - n, v.stop)

    def sections(self) -> dict[str, list]:
        """Per flexible body its sections (bodies reading its rates), in layout order."""
        out: dict[str, list] = {}
        for b in self.bodies:
            if getattr(b.joint, "shares", 0):
                out.setdefault(b.parent, []).append(b)
        return out

    def moving(self) -> list:
        """The bodies whose joints have rates (the others are fixed or driven)."""
        return [b for b in self.bodies if b.joint.nv]


def state_layout(model: _tree.Model):
    """The layout of the model's state: its tree's, without dependent coordinates
    (:class:`mbs.dynamics._dependent.DependentLayout`) when it declares some."""
    lay = Layout.of(model)
    if not model.dependent:
        return lay
    from mbs.dynamics._dependent import DependentLayout

    return DependentLayout(lay, model.dependent)
