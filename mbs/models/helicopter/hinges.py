"""A main-rotor blade's flap hinge, shared by the blades of the tree and of the swashplate's loops."""
from __future__ import annotations

from mbs.aircraft.geometry import delta3_axis
from mbs.joints import Hinge


def main_flap_hinge(mr: dict, sense: int = 1) -> Hinge:
    """A main-rotor blade's flap hinge (blade axes: about -y, up positive; skewed by the file's
    ``delta3`` in the disc plane, :func:`mbs.aircraft.geometry.delta3_axis`, for a rotor turning
    in ``sense``) with the file's flap spring (N m/rad), relaxed at the precone (rad)."""
    axis = delta3_axis(mr.get("delta3", 0.0), sense)
    if mr.get("precone"):
        return Hinge(axis, name="flap", stiffness=mr["flap_stiffness"], rest_angle=mr["precone"])
    return Hinge(axis, name="flap", stiffness=mr["flap_stiffness"])
