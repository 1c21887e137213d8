"""A main-rotor blade's flap hinge, shared by the blades of the tree and of the swashplate's loops."""
from __future__ import annotations

from mbs.joints import Hinge


def main_flap_hinge(mr: dict) -> Hinge:
    """A main-rotor blade's flap hinge (blade axes: about -y, up positive) with the file's flap
    spring (N m/rad), relaxed at the precone (rad)."""
    if mr.get("precone"):
        return Hinge((0, -1, 0), name="flap", stiffness=mr["flap_stiffness"], rest_angle=mr["precone"])
    return Hinge((0, -1, 0), name="flap", stiffness=mr["flap_stiffness"])
