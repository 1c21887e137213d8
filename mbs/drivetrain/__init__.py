"""The rotors' speed as a degree of freedom: the drive train, its engines and their governor.

* :mod:`mbs.drivetrain.train`: the main and tail rotors on one drive train (gear ratio, the
  transmission's inertia, rigid or with a torsionally flexible main shaft), the azimuths and the
  blades' cyclic pitch as dependent coordinates of the main rotor's azimuth;
* :mod:`mbs.drivetrain.shaft`: a torsion spring and damper between two geared coordinates.

The equations hold in the independent coordinates (:mod:`mbs.dynamics._dependent`); constant-speed
scenes are untouched.
"""
from mbs.drivetrain.shaft import TorsionShaft
from mbs.drivetrain.train import DRIVE_TRAINS, DriveTrain, add_drive_train, inertia_about_axes

__all__ = ["DRIVE_TRAINS", "DriveTrain", "TorsionShaft", "add_drive_train", "inertia_about_axes"]
